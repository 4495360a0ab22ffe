"""Torsional and rolling friction (MuJoCo's condim 4 and 6) as rows of the exact LCP: a couple
bounded by μ f_n with true stiction. Checked against closed forms: a spinning ball's deceleration
μ_t m g / I, a rolling ball's stopping distance, the steepest slope a ball rests on (tan θ = μ_r / R),
and a pinch grasp of two point contacts that holds a twist only with torsional friction."""

import numpy as np
import pytest

import sinew

R, M, G = 0.1, 1.0, 9.81
I = 0.4 * M * R**2


def ball(condim, spin=0.0, roll=0.0, gravity=(0.0, 0.0, -G), pair=""):
    xml = f"""<mujoco><option timestep="0.002" gravity="{' '.join(map(str, gravity))}"/>
    <worldbody><geom name="floor" type="plane" size="5 5 .1" condim="{condim}" friction="1 {spin} {roll}"/>
    <body name="ball" pos="0 0 {R}"><freejoint/>
    <geom name="ball" type="sphere" size="{R}" mass="{M}" condim="{condim}" friction="1 {spin} {roll}"/></body>
    </worldbody>{pair}</mujoco>"""
    return sinew.Sim(sinew.Model.from_mjcf_string(xml))


def set_vel(sim, **dofs):
    v = np.zeros(6)
    for k, x in dofs.items():
        v["xyz".index(k[-1]) + (3 if k[0] == "w" else 0)] = x
    sim.qvel[:] = v


def test_a_spinning_ball_slows_at_mu_m_g_over_i_and_stops_for_good():
    mu_t, w0 = 0.01, 10.0
    sim = ball(4, spin=mu_t)
    set_vel(sim, wz=w0)
    sim.step()
    assert "spin" in sim.constraint_system()["kind"]
    decel = mu_t * M * G / I
    for k in range(2, 200):
        sim.step()
    # the couple is μ_t f_n, so ω falls linearly to the step
    assert sim.qvel[5] == pytest.approx(w0 - decel * 0.002 * 199, rel=1e-6)
    assert sim.contacts[0]["friction_torque"][2] == pytest.approx(-mu_t * M * G, rel=1e-6)
    for _ in range(300):
        sim.step()
    assert abs(sim.qvel[5]) < 1e-12 and np.abs(sim.qvel).max() < 1e-9


def test_without_torsional_friction_a_spinning_ball_spins_on():
    sim = ball(3, spin=0.01)
    set_vel(sim, wz=10.0)
    for _ in range(500):
        sim.step()
    assert sim.qvel[5] == pytest.approx(10.0, rel=1e-9)


def twist(sim, tau, inertia, limit):
    """Turns body 1 about z by the couple `tau` for 1 s; checks it held still when `tau` is
    under `limit`, else that it spun up at (tau − limit) / inertia."""
    xf = np.zeros((sim.model.nbody, 6))
    xf[1, 5] = tau
    sim.set_xfrc_applied(xf)
    for _ in range(500):
        sim.step()
    if tau < limit:
        assert abs(sim.qvel[5]) < 1e-8
    else:
        assert sim.qvel[5] == pytest.approx((tau - limit) / inertia * 1.0, rel=1e-3)


@pytest.mark.parametrize("scale", [0.9, 1.1])
def test_a_twist_below_mu_m_g_does_not_turn_the_ball_and_one_above_accelerates_it(scale):
    mu_t = 0.01
    twist(ball(4, spin=mu_t), scale * mu_t * M * G, I, mu_t * M * G)


def test_a_rolling_ball_stops_where_its_rolling_resistance_says():
    # rolling without slipping under a couple μ_r m g: a = 5 μ_r g / (7 R)
    mu_r, v0 = 0.005, 1.0
    sim = ball(6, spin=0.0, roll=mu_r)
    set_vel(sim, vx=v0, wy=v0 / R)
    for _ in range(2000):
        sim.step()
    stop = v0**2 / (2 * 5 * mu_r * G / (7 * R))
    assert sim.qpos[0] == pytest.approx(stop, rel=2e-3)
    assert np.abs(sim.qvel).max() < 1e-9
    x = sim.qpos[0]
    for _ in range(500):
        sim.step()
    assert sim.qpos[0] == x


@pytest.mark.parametrize("scale, rests", [(0.8, True), (1.25, False)])
def test_a_ball_rests_on_a_slope_up_to_tan_theta_mu_r_over_r(scale, rests):
    mu_r = 0.005
    theta = np.arctan(scale * mu_r / R)
    sim = ball(6, roll=mu_r, gravity=(G * np.sin(theta), 0.0, -G * np.cos(theta)))
    for _ in range(1000):
        sim.step()
    if rests:
        assert abs(sim.qpos[0]) < 1e-6 and np.abs(sim.qvel).max() < 1e-8
    else:
        # rolling down: m a = m g sin θ − (μ_r m g cos θ / R) less the spin-up, a = 5/7 (g sin θ − μ_r g cos θ / R)
        a = 5 / 7 * (G * np.sin(theta) - mu_r * G * np.cos(theta) / R)
        assert sim.qvel[0] == pytest.approx(a * 2.0, rel=1e-2)


def test_a_pair_sets_the_torsional_coefficient_from_its_third_friction_value():
    pair = '<contact><pair geom1="ball" geom2="floor" condim="4" friction="1 1 0.02 0 0"/></contact>'
    sim = ball(3, pair=pair)
    set_vel(sim, wz=10.0)
    for _ in range(100):
        sim.step()
    assert sim.qvel[5] == pytest.approx(10.0 - 0.02 * M * G / I * 0.2, rel=1e-6)


def pinch(condim):
    """Two sphere fingertips on slide joints squeezing a box from ±x with 20 N each, no gravity."""
    fingers = "".join(
        f"""<body pos="{s * 0.1} 0 0"><joint name="f{i}" type="slide" axis="1 0 0"/>
        <geom type="sphere" size="0.02" mass="0.1" condim="{condim}" friction="1 0.01 0"/></body>"""
        for i, s in enumerate((-1, 1))
    )
    xml = f"""<mujoco><option timestep="0.002" gravity="0 0 0"/><worldbody>{fingers}
    <body name="object"><freejoint/><geom type="box" size="0.05 0.03 0.03" mass="0.2" condim="{condim}" friction="1 0.01 0"/></body>
    </worldbody><actuator><motor joint="f0" gear="1"/><motor joint="f1" gear="-1"/></actuator></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    q = sim.qpos.copy()
    q[0], q[1] = 0.03, -0.03  # fingertips touching the box's faces at x = ±0.05
    sim.qpos[:] = q
    sim.ctrl[:] = [20.0, 20.0]
    return sim


@pytest.mark.parametrize("condim", [3, 4])
def test_a_pinch_of_two_point_contacts_holds_a_twist_only_with_torsional_friction(condim):
    sim = pinch(condim)
    for _ in range(100):
        sim.step()
    # a twist about the pinch axis below the two contacts' limit 2 μ_t f_n = 0.4 N m
    xf = np.zeros((sim.model.nbody, 6))
    xf[3, 3] = 0.3
    sim.set_xfrc_applied(xf)
    for _ in range(500):
        sim.step()
    turn = abs(sim.qvel[2 + 3])  # the object's angular velocity about x
    if condim == 4:
        assert turn < 1e-7
    else:
        assert turn > 1.0


@pytest.mark.parametrize("scale", [0.9, 1.1])
def test_a_boxs_corner_contacts_share_one_torsion_group_bounded_by_its_weight(scale):
    # no sliding friction: only the torsional couple, μ_t times the four corners' normal forces
    # together, holds the twist
    mu_t, a = 0.02, 0.1
    xml = f"""<mujoco><option timestep="0.002"/><worldbody>
    <geom name="floor" type="plane" size="5 5 .1" condim="4" friction="0 {mu_t} 0"/>
    <body pos="0 0 {a}"><freejoint/><geom type="box" size="{a} {a} {a}" mass="{M}" condim="4" friction="0 {mu_t} 0"/></body>
    </worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    for _ in range(50):
        sim.step()
    kinds = list(sim.constraint_system()["kind"])
    assert kinds.count("normal") == 4 and kinds.count("spin") == 2
    twist(sim, scale * mu_t * M * G, M * (2 * a) ** 2 / 6, mu_t * M * G)


def test_a_planar_balls_rolling_friction_is_one_pair_about_the_planes_normal():
    # a ball on x, z slides and a y hinge: torsion would leave the plane, so only the rolling
    # pair about y is built, and the ball stops where the 3D one does
    mu_r, v0 = 0.005, 1.0
    xml = f"""<mujoco><option timestep="0.002"/><worldbody>
    <geom type="plane" size="5 5 .1" condim="6" friction="1 0.01 {mu_r}"/>
    <body pos="0 0 {R}"><joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 0 1"/><joint type="hinge" axis="0 1 0"/>
    <geom type="sphere" size="{R}" mass="{M}" condim="6" friction="1 0.01 {mu_r}"/></body></worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    sim.qvel[:] = [v0, 0.0, v0 / R]
    sim.step()
    assert list(sim.constraint_system()["kind"]).count("spin") == 2
    for _ in range(1999):
        sim.step()
    assert sim.qpos[0] == pytest.approx(v0**2 / (2 * 5 * mu_r * G / (7 * R)), rel=2e-3)
    assert np.abs(sim.qvel).max() < 1e-9
