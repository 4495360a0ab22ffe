"""Fluid forces (MuJoCo's inertia-box and ellipsoid models) against MuJoCo on the same files: the
constraint-free acceleration at random states with density, viscosity and wind, for bodies whose
inertia is not diagonal in their frame and a free body; and gymnasium's swimmer stepped with RK4
(whose stages read the bodies' poses) beside MuJoCo until a joint reaches its limit."""

import os

import mujoco
import numpy as np
import pytest

import sinew
from twins import forward_both, near_qpos0
from conftest import gym_model_path

XML = """<mujoco><option density="1200" viscosity="0.02" wind="0.3 -0.2 0.1" gravity="0 0 -3">
    <flag contact="disable"/></option>
  <worldbody>
    <body pos="0 0 1"><freejoint/>
      <geom type="box" size="0.2 0.1 0.05" euler="20 35 -10"/>
      <geom type="capsule" fromto="0 0 0 0.3 0.2 0.1" size="0.04"/>
      <body pos="0.3 0.2 0.1"><joint type="hinge" axis="0 1 1"/><joint type="slide" axis="1 0 0"/>
        <geom type="ellipsoid" size="0.1 0.05 0.03" euler="0 40 70"/></body>
    </body>
    <body pos="1 0 0"><joint type="ball"/><geom type="cylinder" size="0.05 0.2" euler="30 0 0"/></body>
  </worldbody>
</mujoco>"""


def largest_passive_force_beside_mujoco(xml, seed, speed, tol):
    """At 50 random states (velocities of deviation `speed`), sinew's constraint-free acceleration
    equals MuJoCo's to `tol`; returns the largest passive force MuJoCo met."""
    m, mj = sinew.Model.from_mjcf_string(xml), mujoco.MjModel.from_xml_string(xml)
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    assert not m.warnings
    rng = np.random.default_rng(seed)
    moved = 0.0
    for _ in range(50):
        q = near_qpos0(mj, rng, 0.5)
        forward_both(mj, d, sim, q, rng.normal(0.0, speed, mj.nv))
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=tol, atol=tol)
        moved = max(moved, np.abs(d.qfrc_passive).max())
    return moved


def test_fluid_forces_equal_mujocos():
    # the fluid's forces were far from negligible
    assert largest_passive_force_beside_mujoco(XML, 0, 2.0, 1e-10) > 1.0


def test_swimmer_steps_as_mujocos_until_a_joint_limit():
    path = gym_model_path("swimmer")
    m, mj = sinew.Model.from_mjcf(path), mujoco.MjModel.from_xml_path(path)
    assert m.integrator == "RK4"
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    rng = np.random.default_rng(1)
    d.qvel[:] = sim.qvel[:] = rng.uniform(-0.1, 0.1, mj.nv)
    for t in range(300):
        d.ctrl[:] = sim.ctrl[:] = 0.3 * np.sin(0.2 * t + np.array([0.0, -1.5]))
        mujoco.mj_step(mj, d)
        sim.step()
    assert np.abs(d.qpos[3:]).max() < np.radians(100)  # no limit reached
    assert abs(d.qpos[0]) > 0.01  # it swam
    np.testing.assert_allclose(sim.qpos, d.qpos, rtol=0, atol=1e-10)
    np.testing.assert_allclose(sim.qvel, d.qvel, rtol=0, atol=1e-10)


# every primitive as an ellipsoid in the fluid, one body mixing a fluid geom with one that is not
# (the body then meets the fluid through the first alone), one body left to the inertia box
ELLIPSOIDS = """<mujoco><option density="1.2" viscosity="0.0002" wind="0.5 -0.3 0.2" gravity="0 0 -2">
    <flag contact="disable"/></option>
  <default><geom fluidshape="ellipsoid"/></default>
  <worldbody>
    <body pos="0 0 1"><freejoint/>
      <geom type="ellipsoid" size="0.3 0.1 0.02" euler="10 20 30" fluidcoef="0.4 0.3 1.2 1.5 0.8"/>
      <geom type="box" size="0.05 0.05 0.05" pos="0.2 0 0" fluidshape="none"/>
      <body pos="0.3 0 0"><joint type="hinge" axis="0 1 1"/>
        <geom type="capsule" fromto="0 0 0 0.2 0.1 0" size="0.03"/>
        <body pos="0.2 0.1 0"><joint type="ball"/><geom type="cylinder" size="0.05 0.15" euler="0 90 0"/>
          <geom type="sphere" size="0.04" pos="0 0 0.2"/></body>
      </body>
    </body>
    <body pos="1 0 1"><freejoint/><geom type="box" size="0.2 0.15 0.01" fluidcoef="0.5 0.25 1.5 2 0"/></body>
    <body pos="2 0 1"><freejoint/><geom type="box" size="0.1 0.2 0.3" fluidshape="none"/></body>
  </worldbody>
</mujoco>"""


def test_ellipsoid_fluid_forces_equal_mujocos():
    assert largest_passive_force_beside_mujoco(ELLIPSOIDS, 2, 3.0, 1e-9) > 0.05


def test_a_bad_fluid_shape_is_an_error_naming_it():
    for attrs, what in [('fluidshape="cube"', "fluidshape"), ('fluidshape="ellipsoid" fluidcoef="1 2 3 4 5 6"', "fluidcoef")]:
        with pytest.raises(ValueError, match=what):
            sinew.Model.from_mjcf_string(f'<mujoco><worldbody><body><freejoint/><geom size="0.1" {attrs}/></body></worldbody></mujoco>')
