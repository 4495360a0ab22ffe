"""Cartesian forces on bodies: those applied from outside (Batch.set_xfrc_applied, MuJoCo's
xfrc_applied: Newton's and Euler's laws on a free body, MuJoCo's step on an articulated one, per
world, cleared at reset) and gravity compensation (MuJoCo's gravcomp: MuJoCo's step, a fully
compensated arm hanging still)."""

import mujoco
import numpy as np
import pytest

from sinew import Batch, Model

CHAIN = """
<mujoco>
  <option timestep="0.002" gravity="0 0 -9.81"/>
  <worldbody>
    <body name="base" pos="0 0 1">
      <freejoint/>
      <geom type="box" size="0.2 0.1 0.05" mass="3" contype="0" conaffinity="0"/>
      <body name="arm" pos="0.2 0 0">
        <joint name="hinge" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="0.7" contype="0" conaffinity="0"/>
        <body name="hand" pos="0.3 0 0">
          <joint name="ball" type="ball"/>
          <geom type="sphere" pos="0.05 0.02 0" size="0.05" mass="0.4" contype="0" conaffinity="0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_a_force_at_the_centre_of_mass_accelerates_a_free_body_by_f_over_m_and_a_torque_spins_it():
    xml = """<mujoco><option gravity="0 0 0" timestep="0.01"/><worldbody><body pos="0 0 1">
             <freejoint/><geom type="box" size="0.3 0.2 0.1" mass="2" pos="0.1 0 0"/></body></worldbody></mujoco>"""
    b = Batch(Model.from_mjcf_string(xml), 2)
    f = np.zeros((2, 2, 6))
    f[0, 1, :3] = [4.0, -2.0, 6.0]
    f[1, 1, 3:] = [0.0, 0.0, 0.5]
    b.set_xfrc_applied(f)
    b.step()
    np.testing.assert_allclose(b.qvel[0, :3], np.array([4.0, -2.0, 6.0]) / 2.0 * 0.01, rtol=1e-12)
    np.testing.assert_allclose(b.qvel[0, 3:], 0.0, atol=1e-14)
    izz = 2.0 * (0.6 ** 2 + 0.4 ** 2) / 12.0
    w = 0.5 / izz * 0.01
    np.testing.assert_allclose(b.qvel[1, 3:], [0.0, 0.0, w], rtol=1e-12, atol=1e-14)
    # the free joint's velocity is its frame's origin's, 0.1 m behind the centre of mass it spins about
    np.testing.assert_allclose(b.qvel[1, :3], np.cross([0.0, 0.0, w], [-0.1, 0.0, 0.0]), rtol=1e-12, atol=1e-14)


def test_forces_on_an_articulated_body_step_as_in_mujoco_per_world_until_reset():
    model = Model.from_mjcf_string(CHAIN)
    mj = mujoco.MjModel.from_xml_string(CHAIN)
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(3)
    n = 4
    b = Batch(model, n)
    qpos = np.tile(mj.qpos0, (n, 1))
    qpos[:, 7] = rng.uniform(-1, 1, n)
    qvel = rng.normal(size=(n, mj.nv))
    b.reset(qpos=qpos, qvel=qvel)
    f = rng.normal(size=(n, mj.nbody, 6)) * 5.0
    f[:, 0] = 0.0            # the world's own is ignored by both
    f[3] = 0.0               # a world without forces
    b.set_xfrc_applied(f)
    np.testing.assert_array_equal(b.xfrc_applied, f)
    b.step()
    for i in range(n):
        mujoco.mj_resetData(mj, d)
        d.qpos[:], d.qvel[:], d.xfrc_applied[:] = qpos[i], qvel[i], f[i]
        mujoco.mj_step(mj, d)
        np.testing.assert_allclose(b.qvel[i], d.qvel, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(b.qpos[i], d.qpos, rtol=1e-9, atol=1e-9)
    b.reset(mask=np.array([True, False, False, False]))
    assert (b.xfrc_applied[0] == 0).all() and (b.xfrc_applied[1] == f[1]).all()


def test_bad_forces_raise():
    b = Batch(Model.from_mjcf_string(CHAIN), 2)
    with pytest.raises(ValueError, match="shape"):
        b.set_xfrc_applied(np.zeros((2, 6)))
    bad = np.zeros((4, 6))
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="finite"):
        b.set_xfrc_applied(bad)


def test_gravity_compensation_steps_as_in_mujoco_and_holds_a_compensated_arm_still():
    xml = CHAIN.replace('<body name="arm" pos="0.2 0 0">', '<body name="arm" pos="0.2 0 0" gravcomp="1">').replace(
        '<body name="hand" pos="0.3 0 0">', '<body name="hand" pos="0.3 0 0" gravcomp="0.5">')
    model = Model.from_mjcf_string(xml)
    assert not any("gravcomp" in w for w in model.warnings)
    mj = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(5)
    b = Batch(model, 3)
    qpos = np.tile(mj.qpos0, (3, 1))
    qpos[:, 7] = rng.uniform(-1, 1, 3)
    qvel = rng.normal(size=(3, mj.nv))
    b.reset(qpos=qpos, qvel=qvel)
    b.step()
    for i in range(3):
        mujoco.mj_resetData(mj, d)
        d.qpos[:], d.qvel[:] = qpos[i], qvel[i]
        mujoco.mj_step(mj, d)
        np.testing.assert_allclose(b.qvel[i], d.qvel, rtol=1e-9, atol=1e-9)
    # an arm fixed at its shoulder, fully compensated, hangs still wherever it is put
    arm = """<mujoco><worldbody><body gravcomp="1"><joint type="hinge" axis="0 1 0"/>
             <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="2"/>
             <body pos="0.4 0 0" gravcomp="1"><joint type="hinge" axis="0 1 0"/>
             <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></body></worldbody></mujoco>"""
    b = Batch(Model.from_mjcf_string(arm), 1)
    b.reset(qpos=np.array([[0.3, -0.7]]), qvel=np.zeros((1, 2)))
    b.step(500)
    np.testing.assert_allclose(b.qpos[0], [0.3, -0.7], atol=1e-12)


def test_a_sim_applies_body_forces_as_a_batch_world_does():
    from sinew import Sim
    model = Model.from_mjcf_string(CHAIN)
    f = np.random.default_rng(2).normal(size=(model.nbody, 6))
    f[0] = 0.0
    sim, b = Sim(model), Batch(model, 1)
    sim.set_xfrc_applied(f)
    b.set_xfrc_applied(f)
    np.testing.assert_array_equal(sim.xfrc_applied, f)
    for _ in range(20):
        sim.step()
        b.step()
    np.testing.assert_array_equal(sim.qpos, b.qpos[0])
    np.testing.assert_array_equal(sim.qvel, b.qvel[0])
    sim.reset()
    np.testing.assert_array_equal(sim.xfrc_applied, 0.0)
