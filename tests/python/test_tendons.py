"""Spatial tendons against MuJoCo on the same file: lengths, Jacobians and the constraint-free
acceleration (tendon springs, dampers and actuators through them) at random states, for paths
through sites on moving bodies, around spheres and cylinders, and split by a pulley. Paths whose
side sites pick the side of a wrap are left out: MuJoCo 4 picks that side by another rule than
its documented one (docs/mjcf.md), which sinew follows; their J is checked against the length's
derivative in tests/tendons.rs."""

import mujoco
import numpy as np

import sinew
from twins import forward_both, near_qpos0

from test_dm_control_models import dense_ten_j

XML = """<mujoco model="spatial tendons">
  <worldbody>
    <site name="anchor" pos="0 0 1"/>
    <site name="anchor2" pos="0.3 0.1 1.1"/>
    <body name="a" pos="0 0 0.5">
      <joint type="hinge" axis="0 1 0" damping="0.1"/>
      <joint type="hinge" axis="1 0 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <geom name="ball" type="sphere" pos="0.2 0 0.05" size="0.06" contype="0" conaffinity="0"/>
      <site name="s1" pos="0.1 0 0.02"/>
      <body name="b" pos="0.4 0 0">
        <joint type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
        <geom name="drum" type="cylinder" quat="0.707107 0.707107 0 0" size="0.05 0.05" contype="0" conaffinity="0"/>
        <site name="s2" pos="0.3 0 0.03"/>
        <body name="c" pos="0.4 0 0">
          <joint type="slide" axis="1 0 0"/>
          <geom type="sphere" size="0.05"/>
          <site name="s3" pos="0 0 0.05"/>
        </body>
      </body>
    </body>
    <body pos="0.5 0.5 1">
      <freejoint/>
      <geom type="box" size="0.05 0.05 0.05"/>
      <site name="s4" pos="0.05 0 0"/>
    </body>
  </worldbody>
  <tendon>
    <spatial name="wrapped" stiffness="20" damping="0.5">
      <site site="s1"/><geom geom="ball"/><site site="s2"/><geom geom="drum"/><site site="s3"/>
    </spatial>
    <spatial name="around">
      <site site="anchor"/><geom geom="ball"/><site site="s2"/>
    </spatial>
    <spatial name="pulleyed" stiffness="5" springlength="1.2">
      <site site="anchor"/><site site="s1"/><pulley divisor="2"/><site site="anchor2"/><site site="s4"/>
    </spatial>
  </tendon>
  <actuator>
    <motor tendon="wrapped" gear="2"/>
    <general tendon="pulleyed" gainprm="3" biastype="affine" biasprm="0.1 -2 -0.5"/>
  </actuator>
</mujoco>"""


def test_spatial_tendons_equal_mujocos():
    m = sinew.Model.from_mjcf_string(XML)
    mj = mujoco.MjModel.from_xml_string(XML)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d = mujoco.MjData(mj)
    sim = sinew.Sim(m)
    assert (m.ntendon, m.tendon_names) == (3, ["wrapped", "around", "pulleyed"])
    rng = np.random.default_rng(0)
    wrapped = 0
    for _ in range(200):
        q = near_qpos0(mj, rng, 0.6)
        v, u = rng.normal(0.0, 1.0, mj.nv), rng.uniform(-1.0, 1.0, mj.nu)
        forward_both(mj, d, sim, q, v, u)
        np.testing.assert_allclose(sim.ten_length, d.ten_length, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(sim.ten_J, dense_ten_j(mj, d), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(sim.ten_velocity, d.ten_velocity, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-10, atol=1e-10)
        wrapped += d.ten_wrapnum[0] > 3
    # the wraps were exercised
    assert wrapped > 20
