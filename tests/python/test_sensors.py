"""Sensors a model file declares, against MuJoCo on dm_control's suite files: every position and
velocity sensor (frame positions and axes, joints, subtree centre of mass and velocity, gyro,
velocimeter) equals MuJoCo's `sensordata` at random states, and accelerometers, force and torque
sensors do with constraints off; a touch sensor reads the weight a box rests on it with, a force
sensor the weight it carries; the kinds sinew does not compute are named in a warning."""

import importlib.util
import os
import pickle
import warnings

import mujoco
import numpy as np
import pytest

import sinew
from twins import forward_both, near_qpos0

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")
#: suite files whose sensors include position and velocity kinds
FILES = ["cheetah", "finger", "fish", "hopper", "humanoid", "humanoid_CMU", "swimmer", "walker"]


def load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return sinew.Model.from_mjcf(os.path.join(SUITE, name + ".xml"))


@pytest.mark.parametrize("name", FILES)
def test_position_and_velocity_sensors_equal_mujocos(name):
    m, mj = load(name), mujoco.MjModel.from_xml_path(os.path.join(SUITE, name + ".xml"))
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    kinds = {mj.sensor(i).name: mujoco.mjtSensor(mj.sensor_type[i]).name for i in range(mj.nsensor)}
    forces = ("mjSENS_TOUCH", "mjSENS_ACCELEROMETER", "mjSENS_FORCE", "mjSENS_TORQUE")
    checked = [n for n in m.sensor_names if kinds[n] not in forces]
    assert checked
    rng = np.random.default_rng(2)
    for _ in range(10):
        q = near_qpos0(mj, rng, 0.5)
        forward_both(mj, d, sim, q, rng.normal(0.0, 1.0, mj.nv))
        data = sim.sensordata
        for n, adr, dim in zip(m.sensor_names, m.sensor_adr, m.sensor_dim):
            if n in checked:
                np.testing.assert_allclose(data[adr:adr + dim], d.sensor(n).data, rtol=1e-10, atol=1e-12, err_msg=n)


def touch_box(sites):
    """A 2 kg box resting on the floor with box sites `sites` (name, half-height, centre), each
    with a touch sensor of its name."""
    placed = "".join(f'<site name="{n}" type="box" size="0.25 0.15 {h}" pos="{p}"/>' for n, h, p in sites)
    sensors = "".join(f'<touch name="{n}" site="{n}"/>' for n, _, _ in sites)
    return f"""<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
      <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.2 0.1 0.1" mass="2"/>{placed}</body></worldbody>
      <sensor>{sensors}</sensor></mujoco>"""


def test_touch_reads_the_weight_a_foot_carries():
    # a box resting on the floor: a site around its bottom face reads its weight, one around its
    # top face nothing
    xml = touch_box([("bottom", 0.02, "0 0 -0.1"), ("top", 0.02, "0 0 0.1")])
    for mode in ["acceleration", "velocity"]:
        sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(constraint_mode=mode))
        for _ in range(200):
            sim.step()
        bottom, top = sim.sensordata
        assert bottom == pytest.approx(2 * 9.81, rel=1e-6) and top == 0.0, (mode, bottom, top)
        # a batch's worlds read the same
        b = sinew.Batch(sim.model, 2, num_threads=1)
        b.step(200)
        np.testing.assert_array_equal(b.sensordata, [sim.sensordata] * 2)


def test_touch_counts_a_contact_whose_normal_points_into_the_site_as_mujoco_does():
    # MuJoCo's rule: a contact counts when the ray from its point along its normal, away from the
    # sensor's body, meets the site; a site below the floor under the box's corners does, one
    # beside them does not (neither holds a contact point)
    xml = touch_box([("under", 0.05, "0 0 -0.25"), ("beside", 0.05, "0.5 0 -0.25")])
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    mj = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(mj)
    sim.step(200)
    mujoco.mj_step(mj, d, 2000)
    under, beside = sim.sensordata
    assert under == pytest.approx(2 * 9.81, rel=1e-6) and beside == 0.0, (under, beside)
    assert d.sensor("under").data[0] == pytest.approx(2 * 9.81, rel=1e-2) and d.sensor("beside").data[0] == 0.0


@pytest.mark.parametrize("name", ["quadruped", "dog", "humanoid"])
def test_accelerometer_force_and_torque_equal_mujocos_without_constraints(name):
    # with constraints off, accelerations and interaction forces are functions of the state and
    # controls alone: MuJoCo's mj_forward and sinew's must agree
    m = load(name).with_options(contact=False, limit=False)
    mj = mujoco.MjModel.from_xml_path(os.path.join(SUITE, name + ".xml"))
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    kinds = {mj.sensor(i).name: mujoco.mjtSensor(mj.sensor_type[i]).name for i in range(mj.nsensor)}
    checked = [n for n in m.sensor_names if kinds[n] in ("mjSENS_ACCELEROMETER", "mjSENS_FORCE", "mjSENS_TORQUE")]
    assert len(checked) >= 3
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = near_qpos0(mj, rng, 0.3)
        forward_both(mj, d, sim, q, rng.normal(0.0, 0.5, mj.nv), rng.uniform(-1, 1, mj.nu))
        data = sim.sensordata
        # the dog's masses come from mesh volumes, equal to MuJoCo's to 2e-8 (test_dm_control_models)
        tol = 1e-7 if name == "dog" else 1e-9
        for n, adr, dim in zip(m.sensor_names, m.sensor_adr, m.sensor_dim):
            if n in checked:
                ref = d.sensor(n).data
                np.testing.assert_allclose(data[adr:adr + dim], ref, rtol=0, atol=tol * max(1.0, np.abs(ref).max()), err_msg=n)


def test_force_sensor_reads_the_weight_below_it():
    # a box hanging from a site on a body that rests on the floor: the force sensor at the top of
    # the resting body reads what it carries
    xml = """<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
      <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/>
        <body pos="0 0 0.2"><geom type="box" size="0.1 0.1 0.1" mass="3"/><site name="joint"/></body>
        <site name="base" pos="0 0 -0.1"/></body></worldbody>
      <sensor><force name="carried" site="joint"/><accelerometer name="acc" site="base"/></sensor></mujoco>"""
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    sim.step(300)
    carried, acc = sim.sensordata[:3], sim.sensordata[3:]
    # the upper box's weight, pushed up by the lower one; a resting body's proper acceleration is g up
    np.testing.assert_allclose(carried, [0, 0, 3 * 9.81], atol=1e-6)
    np.testing.assert_allclose(acc, [0, 0, 9.81], atol=1e-6)


#: one geom of each type (an invisible sphere too) around a probe with rays in many directions
RAYS = """<mujoco><asset><mesh name="tet" vertex="0 0 0  .3 0 0  0 .3 0  0 0 .3  .1 .1 -.2"/>
<hfield name="hf" nrow="4" ncol="5" size=".6 .5 .3 .1" elevation="0 .2 .5 .3 .1 .4 .8 .1 0 .6 .3 .3 .9 .2 .1 0 .1 .2 .7 .5"/></asset>
<worldbody><geom type="plane" size="3 3 .1" pos="0 0 -1.2"/><geom type="sphere" size=".2" pos="1 0 0"/>
<geom type="capsule" size=".1 .3" pos="-1 0 0" euler="30 40 0"/><geom type="ellipsoid" size=".3 .2 .1" pos="0 1 0" euler="10 0 70"/>
<geom type="cylinder" size=".2 .3" pos="0 -1 0" euler="0 60 20"/><geom type="box" size=".2 .3 .1" pos="0 0 1" euler="20 20 20"/>
<geom type="mesh" mesh="tet" pos="1 1 .2"/><geom type="hfield" hfield="hf" pos="-1 -1 -.6"/>
<geom type="sphere" size=".3" pos="1 -1 0" rgba="1 1 1 0"/>
<body name="probe"><freejoint/><geom type="sphere" size=".05" contype="0" conaffinity="0"/>
<site name="s0" zaxis="1 0 0"/>
<site name="s1" zaxis="-1 0 0"/>
<site name="s2" zaxis="0 1 0"/>
<site name="s3" zaxis="0 -1 0"/>
<site name="s4" zaxis="0 0 1"/>
<site name="s5" zaxis="0 0 -1"/>
<site name="s6" zaxis="1 1 0"/>
<site name="s7" zaxis="1 -1 1"/>
<site name="s8" zaxis="-1 1 -1"/>
<site name="s9" zaxis="1 1 1"/>
<site name="s10" zaxis="-1 -1 -1"/>
<site name="s11" zaxis="0 1 -1"/>
<site name="s12" zaxis="2 -1 -3"/>
<site name="s13" zaxis="-1 3 1"/>
<site name="s14" zaxis="1 0 -2"/>
<site name="s15" zaxis="0 -2 1"/>
</body></worldbody><sensor><rangefinder site="s0"/><rangefinder site="s1"/><rangefinder site="s2"/><rangefinder site="s3"/><rangefinder site="s4"/><rangefinder site="s5"/><rangefinder site="s6"/><rangefinder site="s7"/><rangefinder site="s8"/><rangefinder site="s9"/><rangefinder site="s10"/><rangefinder site="s11"/><rangefinder site="s12"/><rangefinder site="s13"/><rangefinder site="s14"/><rangefinder site="s15"/></sensor></mujoco>"""


def test_rangefinders_equal_mujocos_against_every_geom_type():
    m, mj = sinew.Model.from_mjcf_string(RAYS), mujoco.MjModel.from_xml_string(RAYS)
    # inline elevations: the first row at +y, normalized, as MuJoCo reads them
    np.testing.assert_allclose(m.hfield_data(0), mj.hfield_data.reshape(4, 5), atol=1e-7)
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    rng = np.random.default_rng(0)
    seen, geom = set(), np.zeros(1, np.int32)
    for _ in range(300):
        quat = rng.normal(size=4)
        q = np.concatenate([rng.uniform(-1.4, 1.4, 3), quat / np.linalg.norm(quat)])
        forward_both(mj, d, sim, q, np.zeros(6))
        # MuJoCo keeps mesh vertices and height-field elevations in single precision
        np.testing.assert_allclose(sim.sensordata, d.sensordata, rtol=0, atol=1e-6)
        for s in range(mj.nsite):
            mujoco.mj_ray(mj, d, d.site_xpos[s], d.site_xmat[s].reshape(3, 3)[:, 2], None, 1, mj.site_bodyid[s], geom)
            seen.add(int(geom[0]))
    # every visible geom was met by some ray (the invisible sphere, geom 8, by none)
    assert set(range(8)) <= seen and 8 not in seen


def test_quadruped_rangefinders_equal_mujocos():
    m, mj = load("quadruped"), mujoco.MjModel.from_xml_path(os.path.join(SUITE, "quadruped.xml"))
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    rf = [i for i in range(mj.nsensor) if mj.sensor_type[i] == mujoco.mjtSensor.mjSENS_RANGEFINDER]
    adr = [mj.sensor_adr[i] for i in rf]
    ours = [m.sensor_adr[m.sensor_names.index(mj.sensor(i).name)] for i in rf]
    assert len(rf) == 20
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = near_qpos0(mj, rng, 0.3)
        forward_both(mj, d, sim, q, np.zeros(mj.nv))
        np.testing.assert_allclose(sim.sensordata[ours], d.sensordata[adr], rtol=0, atol=1e-9)


def test_kinds_not_computed_are_named_in_a_warning():
    xml = """<mujoco><worldbody><body><freejoint/><geom size=".1"/><site name="s"/></body></worldbody>
<sensor><magnetometer name="mag" site="s"/><gyro name="gyro" site="s"/></sensor></mujoco>"""
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        m = sinew.Model.from_mjcf_string(xml)
    assert any("<magnetometer> sensor 'mag'" in w for w in m.warnings)
    assert m.sensor_names == ["gyro"]


def test_watched_sensors_are_read_by_the_step_as_read_sensors_reads_them():
    # hopper's touch sensors read the step's contact forces, its velocimeter the end state
    m = load("hopper")
    b = sinew.Batch(m, 6, seed=2, num_threads=2)
    chosen = [len(m.sensor_names) - 1, 0, 2]
    b.watch_sensors(chosen)
    rng = np.random.default_rng(0)
    mask = np.array([True, False, True, True, False, True])
    for k in range(150):
        b.ctrl[:] = rng.uniform(-1, 1, b.ctrl.shape)
        before = b.watched_readings.copy()
        b.step(4, mask if k % 3 == 0 else None)
        # worlds a step leaves alone keep their readings, which are of their unchanged state
        if k % 3 == 0:
            assert np.array_equal(b.watched_readings[~mask], before[~mask])
        assert np.array_equal(b.watched_readings, b.read_sensors(chosen))
    assert np.abs(b.watched_readings).max() > 0
    # a pickled copy watches the same sensors and steps on to the same readings
    copy = pickle.loads(pickle.dumps(b))
    assert np.array_equal(copy.watched_readings, b.watched_readings)
    for x in (b, copy):
        x.ctrl[:] = 0.3
        x.step(5)
    assert np.array_equal(copy.watched_readings, b.watched_readings)
    b.watch_sensors([])
    b.step()
    assert b.watched_readings.shape == (6, 0)
    with pytest.raises(ValueError, match="sensor 99 out of range"):
        b.watch_sensors([99])
    # some worlds only: their rows of the whole batch's readings, in ascending order
    np.testing.assert_array_equal(b.read_sensors(chosen, worlds=[4, 1]), b.read_sensors(chosen)[[1, 4]])
    with pytest.raises(ValueError, match="world 6 out of range"):
        b.read_sensors(chosen, worlds=[6])


CONTACTS = """<mujoco><option timestep="0.002"/>
<worldbody><geom name="floor" type="plane" size="2 2 .1"/>
  <body name="box" pos="0 0 .1"><freejoint/><geom name="box" type="box" size=".1 .1 .1"/><site name="s"/>
    <body name="arm" pos="0 0 .3"><joint axis="0 1 0"/><geom name="ball" size=".05"/></body></body>
  <body name="high" pos="1 0 .5"><freejoint/><geom name="high" size=".05"/></body>
</worldbody>
<sensor>
  <contact name="box_floor" geom1="box" geom2="floor"/>
  <contact name="floor_box" geom1="floor" geom2="box" num="2" data="found normal" reduce="mindist"/>
  <contact name="tree" subtree1="box" data="found dist"/>
  <contact name="high" body1="high"/>
  <framequat name="q" objtype="site" objname="s"/>
  <framequat name="q_rel" objtype="body" objname="arm" reftype="site" refname="s"/>
</sensor></mujoco>"""


def test_contact_sensors_count_and_orient_the_contacts_as_mujoco():
    """A box resting on the floor: its four corner contacts found (whichever geom is named
    first), normals pointing away from the first object, slots by nearest; a ball in the air
    finds none. MuJoCo's soft box sinks; sinew's rests at zero distance."""
    mj, m = mujoco.MjModel.from_xml_string(CONTACTS), sinew.Model.from_mjcf_string(CONTACTS)
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    for _ in range(100):
        mujoco.mj_step(mj, d)
    sim.step(100)
    read = lambda name: sim.sensordata[m.sensor_adr[m.sensor_names.index(name)]:][:m.sensor_dim[m.sensor_names.index(name)]]
    assert read("box_floor")[0] == d.sensor("box_floor").data[0] == 4
    np.testing.assert_array_equal(read("floor_box"), d.sensor("floor_box").data)   # 4, (0, 0, 1) twice
    assert read("tree")[0] == d.sensor("tree").data[0] == 4 and abs(read("tree")[1]) < 1e-9
    assert read("high")[0] == d.sensor("high").data[0] == 0


def test_framequat_is_mujocos_rotation():
    mj, m = mujoco.MjModel.from_xml_string(CONTACTS), sinew.Model.from_mjcf_string(CONTACTS)
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    rng = np.random.default_rng(0)
    for _ in range(10):
        q = mj.qpos0 + rng.normal(0, 0.5, mj.nq)
        q[3:7] /= np.linalg.norm(q[3:7])
        q[11:15] /= np.linalg.norm(q[11:15])
        forward_both(mj, d, sim, q, np.zeros(mj.nv))
        for name in ("q", "q_rel"):
            ours = sim.sensordata[m.sensor_adr[m.sensor_names.index(name)]:][:4]
            theirs = d.sensor(name).data
            # the same rotation: equal up to the quaternion's sign
            assert min(np.abs(ours - theirs).max(), np.abs(ours + theirs).max()) < 1e-12
