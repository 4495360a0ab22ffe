"""URDF robots of example-robot-data (legged robots, arms, a humanoid) read by sinew and by MuJoCo
from the same files: sizes, masses, inertias and the constraint-free acceleration at random states
agree; each robot steps 2 s finite under random torques, fixed, and the legged ones floating on a
floor (the URDF written as MJCF with ``urdf_to_mjcf`` and a floor added)."""

import importlib.metadata
import os
import re
import warnings

import mujoco
import numpy as np
import pytest

import sinew
from twins import assert_inertias_equal, forward_both, near_qpos0

SHARE = str(importlib.metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share"))
ROBOTS = os.path.join(SHARE, "example-robot-data", "robots")
#: (file, legged)
FILES = [
    ("a1_description/urdf/a1.urdf", True),
    ("solo_description/robots/solo12.urdf", True),
    ("laikago_description/urdf/laikago.urdf", True),
    ("bolt_description/robots/bolt.urdf", True),
    ("panda_description/urdf/panda.urdf", False),
    ("ur_description/urdf/ur5_robot.urdf", False),
    ("z1_description/urdf/z1.urdf", False),
    ("so_arm_description/urdf/so100.urdf", False),
    ("double_pendulum_description/urdf/double_pendulum.urdf", False),
    ("talos_data/robots/talos_reduced.urdf", False),
]


def ours(rel, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return sinew.Model.from_urdf(os.path.join(ROBOTS, rel), package_dirs=[SHARE], **kw)


def mujocos(rel, tmp_path):
    """MuJoCo's model of the same file (its package:// paths written out: MuJoCo has no search
    path for them)."""
    text = open(os.path.join(ROBOTS, rel)).read().replace("package://", SHARE + "/")
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    return mujoco.MjModel.from_xml_path(str(path))


@pytest.mark.parametrize("rel", [f for f, _ in FILES])
def test_urdf_robot_equals_mujocos(rel, tmp_path):
    m, mj = ours(rel), mujocos(rel, tmp_path)
    assert (m.nq, m.nv, m.nbody, m.ngeom) == (mj.nq, mj.nv, mj.nbody, mj.ngeom)
    np.testing.assert_allclose(m.body_mass, mj.body_mass, rtol=1e-9)
    assert_inertias_equal(np.array(m.body_inertia_tensor), mj, 1e-9)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    for _ in range(3):
        q = near_qpos0(mj, rng, 0.3)
        sim = sinew.Sim(m)
        forward_both(mj, d, sim, q, rng.normal(0.0, 1.0, mj.nv))
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-8, atol=1e-8)


def floored(rel):
    """The robot floating 0.6 m over a floor, motors on its joints."""
    xml = sinew.urdf_to_mjcf(os.path.join(ROBOTS, rel), package_dirs=[SHARE], floating_base=True, motors=True)
    xml = xml.replace("<worldbody>", '<worldbody><geom type="plane" size="5 5 0.1"/>', 1)
    xml = re.sub(r'(<body name="[^"]*") pos="[^"]*"', r'\1 pos="0 0 0.6"', xml, count=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return sinew.Model.from_mjcf_string(xml)


@pytest.mark.parametrize("rel,legged", FILES)
def test_urdf_robot_steps_two_seconds(rel, legged):
    m = floored(rel) if legged else ours(rel, motors=True)
    sim = sinew.Sim(m)
    rng = np.random.default_rng(0)
    lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
    for _ in range(int(round(2.0 / m.timestep))):
        # torques of up to 1 N m (many URDFs give 1000 N m effort limits as placeholders)
        sim.ctrl[:] = np.clip(rng.uniform(-1.0, 1.0, m.nu), lo, hi)
        sim.step()
    assert np.isfinite(sim.qpos).all() and np.isfinite(sim.qvel).all()
    stats = sim.constraint_stats
    assert stats["fallback_zero"] == 0, stats
    # a legged robot fallen in a heap on the floor has piles of redundant contacts: every LCP is
    # still solved exactly (docs/physics.md)
    assert stats["fallback_pgs"] == 0 and stats["inexact"] == 0, stats
    if legged:
        # it landed: something touches the floor and the base stays above it
        assert 0.0 < sim.qpos[2] < 0.6


CARTPOLE = """<robot name="cartpole">
  <link name="rail"/>
  <joint name="slider" type="prismatic"><parent link="rail"/><child link="cart"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="3"/></joint>
  <link name="cart"><inertial><mass value="10"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <joint name="hinge" type="continuous"><parent link="cart"/><child link="pole"/><axis xyz="0 1 0"/></joint>
  <link name="pole"><inertial><origin xyz="0 0 0.3"/><mass value="5"/><inertia ixx="0.15" ixy="0" ixz="0" iyy="0.15" iyz="0" izz="0.001"/></inertial>
    <collision><origin xyz="0 0 0.3"/><geometry><capsule radius="0.049" length="0.6"/></geometry></collision></link>
</robot>"""


def test_an_env_takes_a_urdf_as_its_xml_file(tmp_path):
    """gym.make(..., xml_file=robot.urdf): the robot with a motor on each joint with an effort limit."""
    import gymnasium as gym

    path = tmp_path / "cartpole.urdf"
    path.write_text(CARTPOLE)
    env = gym.make("sinew/InvertedPendulum-v0", xml_file=str(path))
    assert env.action_space.shape == (1,) and env.action_space.high[0] == 3.0
    obs, _ = env.reset(seed=0)
    assert obs.shape == (4,)
    for _ in range(50):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        assert np.isfinite(obs).all()
        if terminated:
            break
