"""Coulomb friction against analytic answers: sticking on a slope, sliding down one, and a box
sliding to a stop. Both friction models: the seed's one tangent (Kokkevis 2004, eqs. 19–21) and
the two-tangent pyramid."""

import math

import numpy as np
import pytest

import sinew

G = 9.81


def box_on_slope(deg, mu, dt, friction, mode="acceleration", integrator="Euler"):
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody>
    <geom type="plane" size="50 50 .1" euler="0 {deg} 0" friction="{mu}"/>
    <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" friction="{mu}"/></body>
    </worldbody></mujoco>"""
    m = sinew.Model.from_mjcf_string(xml).with_options(friction=friction, constraint_mode=mode, integrator=integrator)
    sim = sinew.Sim(m)
    th = math.radians(deg)
    sim.qpos[3:7] = [math.cos(th / 2), 0, math.sin(th / 2), 0]
    sim.qpos[:3] = [0.1 * math.sin(th), 0, 0.1 * math.cos(th)]
    downhill = np.array([math.cos(th), 0.0, -math.sin(th)])
    return sim, downhill


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("friction", ["one_tangent", "pyramid"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_box_on_a_20_degree_slope_with_mu_1_stays_put(dt, friction, mode):
    """MuJoCo creeps 4–9 mm here. The seed's single tangent holds because a contact the step would
    set slipping gets its tangent across that slip (a random one would let it creep sideways)."""
    sim, _ = box_on_slope(20, 1.0, dt, friction, mode)
    sim.step(int(0.2 / dt))
    start = sim.qpos[:3].copy()
    sim.step(int(5 / dt))
    assert np.linalg.norm(sim.qpos[:3] - start) < 1e-6


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("friction", ["one_tangent", "pyramid"])
@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_box_slides_down_a_30_degree_slope_at_g_sin_minus_mu_cos(dt, friction, mode):
    sim, down = box_on_slope(30, 0.3, dt, friction, mode)
    sim.step(int(0.5 / dt))
    t0, v0 = sim.time, sim.qvel[:3] @ down
    sim.step(int(0.5 / dt))
    accel = (sim.qvel[:3] @ down - v0) / (sim.time - t0)
    th = math.radians(30)
    expected = G * (math.sin(th) - 0.3 * math.cos(th))
    assert abs(accel - expected) / expected <= 0.005
    assert sim.constraint_stats["fallback_zero"] == 0


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("friction", ["one_tangent", "pyramid"])
@pytest.mark.parametrize("integrator, dt, tol", [("Euler", 0.002, 0.005), ("Euler", 0.01, 0.02),
                                                 ("leapfrog", 0.002, 0.005), ("leapfrog", 0.01, 0.005)])
def test_sliding_box_stops_at_v0_squared_over_2_mu_g(integrator, dt, tol, friction, mode):
    """Semi-implicit Euler shortens the distance by μ g h / v0 of itself (1.6% at dt = 0.01, above
    the issue's 0.5%; the bound there is the measured one); leapfrog, exact under the constant
    friction deceleration, is within 0.5% at both steps."""
    sim, _ = box_on_slope(0, 0.5, dt, friction, mode, integrator)
    sim.qvel[0] = 3.0
    sim.step(int(1.5 / dt))
    expected = 3.0**2 / (2 * 0.5 * G)
    assert abs(sim.qpos[0] - expected) / expected <= tol
    assert abs(sim.qvel[0]) < 1e-9


@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_planar_model_gets_in_plane_friction_rows_only(dt):
    """A model whose joints all move in one plane (slides in it, hinges across it: hopper, walker,
    half-cheetah) has one usable tangent per contact: pyramid friction builds ±t along it and no
    rows across the plane, and still holds a box on a 20° slope with μ = 1."""
    th = math.radians(20)
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody>
    <geom type="plane" size="50 50 .1" euler="0 20 0" friction="1"/>
    <body pos="{0.1 * math.sin(th)} 0 {0.1 * math.cos(th)}" euler="0 20 0">
      <joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
      <joint name="r" type="hinge" axis="0 1 0"/><geom type="box" size="0.1 0.1 0.1" friction="1"/>
    </body></worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(friction="pyramid"))
    sim.step(int(0.2 / dt))
    start = sim.qpos.copy()
    sim.step(int(5 / dt))
    contacts = sim.contacts
    assert len(contacts) == 4
    assert sim.constraint_stats["rows"] == 3 * len(contacts)
    assert np.abs(sim.qpos - start).max() < 1e-6
    assert all(abs(c["friction_force"][1]) < 1e-12 for c in contacts)


@pytest.mark.parametrize(
    "box, floor, slides",
    [
        ('condim="1"', 'condim="3"', False),  # the larger condim: friction, as a hopper's foot on its floor
        ('condim="3"', 'condim="1"', False),
        ('condim="1"', 'condim="1"', True),
        ('condim="3" priority="-1"', 'condim="1"', True),  # the higher-priority geom decides
        ('condim="1" priority="2"', 'condim="3" friction="2"', True),
    ],
)
def test_contact_friction_combines_condim_and_priority_as_mujoco(box, floor, slides):
    """A box launched at 2 m/s along a floor: it slides on where the pair is frictionless, stops
    where it has friction; MuJoCo's own contact dimension for the same pair agrees."""
    import mujoco

    xml = f"""<mujoco><option timestep="0.002"/><worldbody>
    <geom name="floor" type="plane" size="50 50 .1" {floor}/>
    <body pos="0 0 0.1"><freejoint/><geom name="box" type="box" size="0.1 0.1 0.1" {box}/></body>
    </worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    sim.qvel[0] = 2.0
    sim.step(1000)
    assert (sim.qvel[0] > 1.99) == slides, sim.qvel[0]
    mj = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(mj)
    mujoco.mj_forward(mj, d)
    assert d.ncon > 0 and (d.contact.dim[0] == 1) == slides


def test_joint_dry_friction_holds_where_mujocos_creeps():
    """A horizontal pendulum held by 1% more frictionloss than gravity's torque: sinew's exact
    friction rows keep it at rest for 4 s; MuJoCo's soft friction lets it creep."""
    import mujoco

    xml = f"""<mujoco><option gravity='0 0 -9.81'/><worldbody><body><joint axis='0 1 0' frictionloss='{1.01 * 9.81 * 0.5}'/>
        <geom type='sphere' size='0.01' mass='1' pos='0.5 0 0'/></body></worldbody></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    sim.step(2000)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(2000):
        mujoco.mj_step(m, d)
    assert abs(sim.qpos[0]) < 1e-8
    assert abs(d.qpos[0]) > 0.05, d.qpos[0]


def pair_on_slope(pair: str) -> str:
    """A box on a 30° slope whose geoms do not collide by their own filters (contype 0) and whose
    own friction (0.9) would hold it: only `pair` (a `<contact>` child) makes them touch."""
    return f"""<mujoco><option timestep="0.002"/><worldbody>
    <geom name="slope" type="plane" size="50 50 .1" euler="0 30 0" friction="0.9" contype="0"/>
    <body pos="0 0 0.1"><freejoint/><geom name="box" type="box" size="0.1 0.1 0.1" friction="0.9" contype="0"/></body>
    </worldbody><contact>{pair}</contact></mujoco>"""


@pytest.mark.parametrize("friction", ["one_tangent", "pyramid"])
def test_an_explicit_pair_collides_with_its_own_friction(friction):
    """`<contact><pair>` as MuJoCo reads it: the geoms collide whatever contype says, with the
    pair's friction (0.3, not the geoms' 0.9): the box slides at g (sin θ − 0.3 cos θ)."""
    xml = pair_on_slope('<pair geom1="box" geom2="slope" friction="0.3 0.3 0.005 0.0001 0.0001" solref="0.02 1"/>')
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(friction=friction))
    th = math.radians(30)
    sim.qpos[3:7] = [math.cos(th / 2), 0, math.sin(th / 2), 0]
    sim.qpos[:3] = [0.1 * math.sin(th), 0, 0.1 * math.cos(th)]
    down = np.array([math.cos(th), 0.0, -math.sin(th)])
    sim.step(250)
    t0, v0 = sim.time, sim.qvel[:3] @ down
    sim.step(250)
    accel = (sim.qvel[:3] @ down - v0) / (sim.time - t0)
    expected = G * (math.sin(th) - 0.3 * math.cos(th))
    assert abs(accel - expected) / expected <= 0.005
    assert [(c["geom1"], c["geom2"]) for c in sim.contacts] == [(1, 0)] * len(sim.contacts) and len(sim.contacts) == 4
    # without the pair the box falls through the slope
    free = sinew.Sim(sinew.Model.from_mjcf_string(pair_on_slope("")))
    free.step(250)
    assert free.qpos[2] < -0.5 and not free.contacts


@pytest.mark.parametrize("pair, complaint", [
    ('<pair geom1="box"/>', "geom2"),
    ('<pair geom1="box" geom2="nowhere"/>', "nowhere"),
    ('<pair geom1="box" geom2="box"/>', "make no pair"),
    ('<pair geom1="box" geom2="slope" condim="2"/>', "condim"),
    ('<pair geom1="box" geom2="slope" friction="-1"/>', "friction"),
])
def test_a_bad_pair_is_an_error_naming_it(pair, complaint):
    with pytest.raises(ValueError, match=complaint):
        sinew.Model.from_mjcf_string(pair_on_slope(pair))
