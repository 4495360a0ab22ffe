"""Sensors a model file declares, against MuJoCo on dm_control's suite files: every position and
velocity sensor (frame positions and axes, joints, subtree centre of mass and velocity, gyro,
velocimeter) equals MuJoCo's `sensordata` at random states, and accelerometers, force and torque
sensors do with constraints off; a touch sensor reads the weight a box rests on it with, a force
sensor the weight it carries; the kinds sinew does not compute are named in a warning."""

import importlib.util
import os
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


def test_touch_reads_the_weight_a_foot_carries():
    # a box resting on the floor: a site around its bottom face reads its weight, one around its
    # top face nothing
    xml = """<mujoco><worldbody><geom type="plane" size="5 5 0.1"/>
      <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.2 0.1 0.1" mass="2"/>
        <site name="bottom" type="box" size="0.25 0.15 0.02" pos="0 0 -0.1"/>
        <site name="top" type="box" size="0.25 0.15 0.02" pos="0 0 0.1"/></body></worldbody>
      <sensor><touch name="bottom" site="bottom"/><touch name="top" site="top"/></sensor></mujoco>"""
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


def test_kinds_not_computed_are_named_in_a_warning():
    m = load("quadruped")
    assert any("<rangefinder> sensor" in w for w in m.warnings)
    assert "rf_00" not in m.sensor_names
