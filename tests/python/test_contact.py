"""Contacts and joint limits by the Kokkevis constraint method, against analytic answers, with the
issue's tolerances."""

import warnings

import mujoco
import numpy as np
import pytest

import sinew
from conftest import gym_model_path

BOX = """<mujoco><option timestep="{dt}"/><worldbody><geom type="plane" size="5 5 .1"/>
<body pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body></worldbody></mujoco>"""

LIMIT = """<mujoco><option timestep="{dt}"/><worldbody><body><joint name="j" axis="0 1 0" range="-30 30"/>
<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/></body></worldbody>
<actuator><motor joint="j" gear="1"/></actuator></mujoco>"""

BALL = """<mujoco><option timestep="{dt}"/><custom><numeric name="sinew/restitution" data="0.5"/></custom>
<worldbody><geom type="plane" size="5 5 .1"/><body pos="0 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
</worldbody></mujoco>"""

STACK = ('<mujoco><option timestep="{dt}"/><worldbody><geom type="plane" size="5 5 .1"/>'
         + "".join(f'<body pos="0 0 {0.1 + 0.2 * i}"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>' for i in range(5))
         + "</worldbody></mujoco>")


def bounce_peak(dt, mode, friction="one_tangent", integrator="Euler"):
    """Highest point of the ball's gap over the floor after its first rebound (1.5 s), and the Sim."""
    m = sinew.Model.from_mjcf_string(BALL.format(dt=dt))
    sim = sinew.Sim(m.with_options(constraint_mode=mode, friction=friction, integrator=integrator))
    peak, rising = 0.0, False
    for _ in range(round(1.5 / dt)):
        sim.step()
        rising = rising or sim.qvel[2] > 0
        if rising:
            peak = max(peak, sim.qpos[2] - 0.1)
    return peak, sim


def stack_drift(dt, mode, friction, seconds=10.0, integrator="Euler"):
    """Largest displacement of any of five stacked boxes over `seconds`, and the Sim."""
    m = sinew.Model.from_mjcf_string(STACK.format(dt=dt))
    sim = sinew.Sim(m.with_options(constraint_mode=mode, friction=friction, integrator=integrator))
    start = sim.qpos.reshape(5, 7)[:, :3].copy()
    worst = 0.0
    for _ in range(round(seconds / dt)):
        sim.step()
        worst = max(worst, np.abs(sim.qpos.reshape(5, 7)[:, :3] - start).max())
    return worst, sim


@pytest.mark.parametrize("friction, rows_per_corner", [("one_tangent", 2), ("pyramid", 5)])
@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_resting_box_does_not_sink_or_slide(dt, mode, friction, rows_per_corner):
    model = sinew.Model.from_mjcf_string(BOX.format(dt=dt)).with_options(constraint_mode=mode, friction=friction)
    sim = sinew.Sim(model)
    sim.step(int(10 / dt))
    assert 0.1 - sim.qpos[2] <= 0.05e-3
    assert np.abs(sim.qpos[:2]).max() <= 1e-9
    stats = sim.constraint_stats
    # four corners: a normal and one friction row each (seed), or four (pyramid)
    assert stats["rows"] == 4 * rows_per_corner
    assert stats["fallback_pgs"] == 0 and stats["fallback_zero"] == 0


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_joint_driven_into_its_limit_stops_and_stays(dt, mode):
    sim = sinew.Sim(sinew.Model.from_mjcf_string(LIMIT.format(dt=dt)).with_options(constraint_mode=mode))
    sim.ctrl[:] = 5.0
    worst = 0.0
    for k in range(int(5 / dt)):
        sim.step()
        if sim.time > 2.0:
            worst = max(worst, sim.qpos[0] - np.radians(30))
    assert worst <= 1e-4
    assert abs(sim.qpos[0] - np.radians(30)) <= 1e-4


@pytest.mark.parametrize("integrator", ["Euler", "leapfrog"])
@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_ball_rebounds_to_e_squared_of_its_drop_height(dt, mode, integrator):
    """The rebound keeps the discrete energy of both integrators (see `rebound` in src/constraint/impact.rs)."""
    peak, sim = bounce_peak(dt, mode, integrator=integrator)
    assert sim.model.restitution == 0.5
    expected = 0.25 * 0.9
    assert abs(peak - expected) / expected <= 0.02
    assert sim.constraint_stats["impacts"] >= (1 if mode == "acceleration" else 0)


THROWN = """<mujoco><option timestep="{dt}"/><worldbody><geom type="plane" size="5 5 .1"/>
<body pos="0 0 0.5"><freejoint/><geom type="sphere" size="0.1"/></body></worldbody></mujoco>"""


@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_a_plastic_landing_needs_no_impact_solve(dt):
    """A ball thrown down at the floor with spin-free sliding: with e = 0 the force solve alone
    lands it (no impact solve) as the impact path does with e → 0: it stays on the floor, and
    rolls off at 5/7 of its speed (angular momentum about the contact point is conserved)."""
    ends = {}
    for e in [0.0, 1e-9]:
        sim = sinew.Sim(sinew.Model.from_mjcf_string(THROWN.format(dt=dt)).with_options(restitution=e))
        sim.qvel = np.array([2.0, 0, -3.0, 0, 0, 0])
        landed, rise, depth = False, 0.0, 0.0
        for _ in range(round(1.0 / dt)):
            sim.step()
            gap = sim.qpos[2] - 0.1
            landed = landed or gap < 1e-3
            if landed:
                rise, depth = max(rise, gap), max(depth, -gap)
        assert (sim.constraint_stats["impacts"] == 0) == (e == 0.0)
        assert rise <= 2e-3 and depth <= 1e-4, (e, rise, depth)
        # within the landing step's discretisation (0.7% at dt = 0.01)
        assert abs(sim.qvel[0] - 2.0 * 5 / 7) <= 0.01 * 2.0 * 5 / 7, (e, sim.qvel[0])
        ends[e] = sim.qpos[:3].copy(), sim.qvel[0]
    assert np.abs(ends[0.0][0] - ends[1e-9][0]).max() <= 1e-3
    assert abs(ends[0.0][1] - ends[1e-9][1]) <= 1e-4 * ends[0.0][1]


def test_contact_list_reports_geometry_and_forces():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(BOX.format(dt=0.002)))
    sim.step(200)
    contacts = sim.contacts
    assert len(contacts) == 4
    total = sum(c["normal_force"] for c in contacts)
    weight = sim.model.body_mass[1] * 9.81
    assert total == pytest.approx(weight, rel=1e-6)
    for c in contacts:
        assert c["normal"] == pytest.approx([0, 0, 1])
        assert c["body1"] == 1 and c["body2"] == 0


def test_contacts_and_limits_can_be_switched_off():
    m = sinew.Model.from_mjcf_string(BOX.format(dt=0.002)).with_options(contact=False)
    sim = sinew.Sim(m)
    sim.step(100)
    assert sim.qpos[2] < 0.0 and sim.contacts == []
    m = sinew.Model.from_mjcf_string(LIMIT.format(dt=0.002)).with_options(limit=False)
    sim = sinew.Sim(m)
    sim.ctrl[:] = 5.0
    sim.step(1000)
    assert sim.qpos[0] > np.radians(30)


def random_floor_run(name, seconds, penetration, **options):
    """`seconds` of random controls (a new one every 5 steps) on a gymnasium model with its floor:
    the Sim, the deepest penetration `penetration(sim)` reports after any step, and the worst
    hinge-limit violation after the first second (ant and humanoid start outside some ranges)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = sinew.Model.from_mjcf(gym_model_path(name)).with_options(**options)
    sim = sinew.Sim(m)
    rng = np.random.default_rng(0)
    lo, hi = m.actuator_ctrlrange.T
    hinges = [j for j in range(m.njnt) if m.jnt_limited[j] and m.joint_types[j] == "hinge"]
    adr = np.array([m.jnt_qposadr[j] for j in hinges])
    rlo, rhi = np.array([m.jnt_range[j] for j in hinges]).T
    pen = lim = 0.0
    for k in range(int(seconds / m.timestep)):
        if k % 5 == 0:
            sim.ctrl[:] = rng.uniform(lo, hi)
        sim.step()
        pen = max(pen, penetration(sim))
        if k * m.timestep >= 1.0:
            q = sim.qpos[adr]
            lim = max(lim, (rlo - q).max(), (q - rhi).max())
    return sim, pen, lim


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("name", ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"])
def test_gym_models_with_floors_hold_contacts_and_limits_under_random_actions(name, mode):
    """10 s of random controls at the model's own dt: finite, penetration below 1 mm (the contacts
    each step found), hinge limits held after the first second."""
    sim, pen, lim = random_floor_run(name, 10.0, lambda s: max([0.0] + [-c["dist"] for c in s.contacts]), constraint_mode=mode)
    assert np.isfinite(sim.get_state()).all()
    assert sim.constraint_stats["fallback_zero"] == 0
    assert pen < 1e-3
    assert lim < 1e-4
    if name == "ant":
        # its feet leave the floor: separating contacts start outside K and the LCP, and some,
        # pushed closed by the others, are brought back
        assert sim.constraint_stats["left_out"] > 0 and sim.constraint_stats["regrown"] > 0


@pytest.mark.parametrize("name", ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"])
def test_test_force_k_equals_j_minv_jt_on_the_gym_models(name):
    """At states of a random-control run on the floor with contacts, friction and limits: K by
    unit test forces through the ABA quantities equals J M⁻¹ Jᵀ from CRBA (≤ 1e-9 of K's
    largest entry; M there includes h × damping, which the step treats implicitly), and that M
    less h × damping is MuJoCo's mj_fullM at the same qpos (≤ 1e-9 relative)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = sinew.Model.from_mjcf(gym_model_path(name)).with_options(friction="pyramid")
    mj = mujoco.MjModel.from_xml_path(gym_model_path(name))
    mjd = mujoco.MjData(mj)
    sim = sinew.Sim(m)
    rng = np.random.default_rng(3)
    lo, hi = m.actuator_ctrlrange.T
    kinds_seen = set()
    checked = 0
    for k in range(int(3.0 / m.timestep)):
        if k % 5 == 0:
            sim.ctrl[:] = rng.uniform(lo, hi)
        sim.step()
        if k % 25:
            continue
        system = sim.constraint_system()
        K, J, M = system["K"], system["J"], system["M"]
        if "normal" not in system["kind"]:
            continue
        kinds_seen.update(system["kind"])
        scale = np.abs(K).max()
        np.testing.assert_array_less(np.abs(K - J @ np.linalg.solve(M, J.T)), 1e-9 * scale)
        mjd.qpos[:] = sim.qpos
        mujoco.mj_forward(mj, mjd)
        full = np.zeros((mj.nv, mj.nv))
        mujoco.mj_fullM(mj, mjd, full)
        rigid = M - m.timestep * np.diag(mj.dof_damping)
        np.testing.assert_array_less(np.abs(rigid - full), 1e-9 * np.abs(full).max())
        checked += 1
    assert checked >= 5
    assert {"normal", "friction"} <= kinds_seen, kinds_seen


def test_constraint_system_leaves_the_world_alone():
    m = sinew.Model.from_mjcf_string(BOX.format(dt=0.002))
    a, b = sinew.Sim(m), sinew.Sim(m)
    a.step(20)
    b.step(20)
    system = a.constraint_system()
    assert system["kind"][0] == "normal" and system["J"].shape == (len(system["kind"]), m.nv)
    a.step(50)
    b.step(50)
    np.testing.assert_array_equal(a.get_state(full=True), b.get_state(full=True))


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_painleve_rod_ends_finite_without_gaining_energy(mode, dt):
    """A rod leaning at tan θ = 2 on a floor with μ = 1.5, sliding: Painlevé's configuration."""
    import math

    th, half = math.atan(2.0), 0.5
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody><geom type="plane" size="10 10 .1" friction="1.5"/>
    <body><freejoint/><geom type="capsule" size="0.01 {half}" friction="1.5" mass="1"/></body></worldbody></mujoco>"""
    m = sinew.Model.from_mjcf_string(xml).with_options(constraint_mode=mode, friction="one_tangent")
    sim = sinew.Sim(m)
    a = math.pi / 2 - th
    sim.qpos[3:7] = [math.cos(a / 2), 0, math.sin(a / 2), 0]
    sim.qpos[2] = 0.01 + half * math.sin(th)
    sim.qvel[0] = -3.0
    inertia = m.body_inertia_tensor[1]

    def energy():
        v, w = sim.qvel[:3], sim.qvel[3:]
        return 0.5 * v @ v + 0.5 * w @ inertia @ w + 9.81 * sim.qpos[2]

    e0, worst = energy(), -np.inf
    for _ in range(int(1.0 / dt)):
        sim.step()
        worst = max(worst, energy() - e0)
    assert np.isfinite(sim.get_state()).all()
    assert worst <= 1e-9 * e0
    assert sim.constraint_stats["fallback_zero"] == 0


ARM = """<mujoco><option timestep="{dt}"/><worldbody><body><joint name="j" axis="0 1 0"/>
<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/><body pos="0.5 0 0"><joint name="k" axis="0 1 0"/>
<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/></body></body></worldbody>
<actuator><motor joint="j" gear="1" ctrlrange="{lim}"/><motor joint="k" gear="1" ctrllimited="false"/></actuator></mujoco>"""


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_motion_control_rows_track_a_sinusoid(dt, mode):
    """Dead-beat gains kp = 1/h², kd = 1/h with the reference one step ahead: semi-implicit Euler
    lands on the trajectory every step (the row's torque is whatever that takes)."""
    m = sinew.Model.from_mjcf_string(ARM.format(dt=dt, lim="-1e6 1e6"))
    m = m.with_options(trajectory_gains=(1 / dt**2, 1 / dt), constraint_mode=mode)
    sim = sinew.Sim(m)
    ref = lambda t: np.array([0.5 * np.sin(2 * t), 0.3 * np.sin(3 * t)])  # noqa: E731
    worst = 0.0
    for _ in range(int(3 / dt)):
        sim.ctrl[:] = ref(sim.time + dt)
        sim.step()
        worst = max(worst, np.abs(sim.qpos - ref(sim.time)).max())
    assert worst <= 1e-6


def test_torque_bounded_motion_control_saturates_at_the_motor_limit():
    m = sinew.Model.from_mjcf_string(ARM.format(dt=0.002, lim="-2 2")).with_options(trajectory_gains=(400.0, 40.0))
    b = sinew.Batch(m, 1)
    b.ctrl[0] = [1.5, 0.0]  # far target: the first joint's torque must saturate
    torques = []
    for _ in range(200):
        b.step()
        torques.append(b.qfrc_constraint[0, 0])
    torques = np.array(torques)
    assert np.abs(torques).max() <= 2 + 1e-9
    assert np.isclose(np.abs(torques), 2).any()
    assert b.qpos[0, 0] < 1.5  # it cannot follow the commanded acceleration


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("boxes", [1, 2, 4])
def test_redundant_coplanar_contacts_carry_exactly_the_weight(boxes, mode):
    """4, 8 and 16 coplanar corner contacts under one body: the normal impulse per step is m g h."""
    geoms = "".join(f'<geom type="box" size="0.1 0.1 0.1" pos="{0.2 * i} 0 0" mass="{1.0 / boxes}"/>' for i in range(boxes))
    xml = f"""<mujoco><option timestep="0.002"/><worldbody><geom type="plane" size="5 5 .1"/>
    <body pos="0 0 0.1"><freejoint/>{geoms}</body></worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(constraint_mode=mode))
    sim.step(100)
    assert len(sim.contacts) == 4 * boxes
    total = sum(c["normal_force"] for c in sim.contacts) * 0.002
    assert total == pytest.approx(1.0 * 9.81 * 0.002, rel=1e-9)
    stats = sim.constraint_stats
    assert stats["fallback_pgs"] == 0 and stats["fallback_zero"] == 0


@pytest.mark.parametrize("integrator", ["Euler", "leapfrog"])
@pytest.mark.parametrize("friction", ["one_tangent", "pyramid"])
@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_five_stacked_boxes_stay_stacked(dt, mode, friction, integrator):
    """10 s, drift < 1 mm (measured: about 1e-9 m), without a solver fallback."""
    worst, sim = stack_drift(dt, mode, friction, integrator=integrator)
    assert worst < 1e-3
    stats = sim.constraint_stats
    assert stats["fallback_pgs"] == 0 and stats["inexact"] == 0 and stats["fallback_zero"] == 0


def test_box_turned_on_a_box_rests_on_the_octagon_of_their_faces():
    """Turned 45° about z, no corner of either box lies on the other's face: the eight contact
    points are where the edges cross (face clipping)."""
    xml = """<mujoco><option timestep="0.002"/><worldbody><geom type="plane" size="5 5 .1"/>
    <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body pos="0 0 0.3" euler="0 0 45"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    </worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(friction="pyramid"))
    sim.step(1000)
    between = [c for c in sim.contacts if {c["body1"], c["body2"]} == {1, 2}]
    assert len(between) == 8
    assert all(abs(abs(c["normal"][2]) - 1) < 1e-12 for c in between)
    assert sim.qpos[7 + 2] == pytest.approx(0.3, abs=1e-6)
    assert np.abs(sim.qpos[7:9]).max() < 1e-6


def test_edge_crossing_edge_is_one_contact_at_the_crossing():
    """A box balanced edge-down across the edge-up ridge of a fixed box: one edge–edge contact at
    the crossing point, normal vertical, carrying the weight."""
    s2 = np.sqrt(2)
    xml = f"""<mujoco><option timestep="0.002"/><worldbody>
    <geom type="box" size="0.1 0.1 0.1" euler="45 0 0"/>
    <body pos="0 0 {0.2 * s2}" euler="0 45 0"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="2"/></body>
    </worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(friction="pyramid"))
    sim.step()
    (c,) = sim.contacts
    up = np.array(c["normal"]) * (1 if c["body1"] == 1 else -1)  # the normal points from body2 to body1
    assert np.allclose(up, [0, 0, 1], atol=1e-12)
    assert np.allclose(c["pos"], [0, 0, 0.1 * s2], atol=1e-9)
    assert c["normal_force"] == pytest.approx(2 * 9.81, rel=1e-7)  # the LCP regulariser is 1e-8


def test_sphere_and_capsule_rest_on_a_box():
    xml = """<mujoco><option timestep="0.002"/><worldbody><geom type="plane" size="5 5 .1"/>
    <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.3 0.3 0.1"/></body>
    <body pos="0 0.1 0.3"><freejoint/><geom type="sphere" size="0.1"/></body>
    <body pos="0.1 -0.1 0.25" euler="0 90 0"><freejoint/><geom type="capsule" size="0.05 0.1"/></body>
    </worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(friction="pyramid"))
    sim.step(2000)
    q = sim.qpos.reshape(3, 7)
    assert q[1, 2] == pytest.approx(0.3, abs=1e-4)  # sphere centre one radius above the box top
    assert q[2, 2] == pytest.approx(0.25, abs=1e-4)  # capsule axis one radius above it
    assert np.abs(q[:, :2] - [[0, 0], [0, 0.1], [0.1, -0.1]]).max() < 1e-4


@pytest.mark.parametrize("name", ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"])
def test_gym_models_under_leapfrog_end_each_step_clear_of_floor_and_limits(name):
    """Leapfrog evaluates a step at its midpoint, which an impact can carry into the floor or past
    a limit; the state each step ends in is what must be clean. Penetration is measured there by
    MuJoCo's collision on the same MJCF (its geometry for these shapes is sinew's)."""
    mj = mujoco.MjModel.from_xml_path(gym_model_path(name))
    d = mujoco.MjData(mj)

    def end_state_penetration(sim):
        d.qpos[:] = sim.qpos
        mujoco.mj_kinematics(mj, d)
        mujoco.mj_collision(mj, d)
        return max([0.0] + [-d.contact[i].dist for i in range(d.ncon)])

    sim, pen, lim = random_floor_run(name, 5.0, end_state_penetration, integrator="leapfrog")
    assert np.isfinite(sim.get_state()).all()
    assert pen < 1e-3
    assert lim < 1e-4


def test_a_reset_sim_steps_exactly_as_a_new_one():
    """reset() keeps nothing from earlier steps (friction tangents, the LCP's warm start, cached
    kinematics): a resting box's first step after it is a cold start, as a new Sim's, and the run
    that follows matches a new Sim's bit for bit."""
    m = sinew.Model.from_mjcf_string(BOX.format(dt=0.002))

    def run(sim, steps):
        before = sim.constraint_stats["warm_starts"]
        sim.step(steps)
        return sim.get_state(), sim.constraint_stats["warm_starts"] - before

    used = sinew.Sim(m)
    _, warm = run(used, 20)
    assert warm > 0, "resting contact warm-starts the LCP"
    used.reset()
    assert run(used, 1)[1] == run(fresh := sinew.Sim(m), 1)[1] == 0
    state_used, warm_used = run(used, 200)
    state_new, warm_new = run(fresh, 200)
    np.testing.assert_array_equal(state_used, state_new)
    assert warm_used == warm_new


def test_a_batchs_constraint_stats_sum_its_worlds():
    """Batch.constraint_stats: each counter the sum of what each world counts stepped alone (a
    batch of one with the world's seed), the residual the largest of theirs."""
    model = sinew.Model.from_mjcf_string(STACK.format(dt=0.005))
    qpos = np.repeat(model.qpos0[None], 3, axis=0)
    qpos[:, 2::7] += np.array([[0.0], [0.05], [0.2]])   # dropped from three heights
    batch = sinew.Batch(model, 3, seed=7, num_threads=2)
    batch.qpos[:] = qpos
    batch.step(200)
    alone = []
    for i in range(3):
        one = sinew.Batch(model, 1, seed=7 + i, num_threads=1)
        one.qpos[:] = qpos[i]
        one.step(200)
        alone.append(one.constraint_stats)
    got = batch.constraint_stats
    assert got["solves"] > 0 and got["warm_starts"] > 0 and got["pivots"] > 0
    for key, value in got.items():
        own = [a[key] for a in alone]
        assert value == (max(own) if key == "residual" else sum(own)), key
