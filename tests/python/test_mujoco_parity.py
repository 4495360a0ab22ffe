"""sinew against the mujoco package on gymnasium's own model files: compiled mass properties,
body frames, qpos0, and accelerations at random states with constraints switched off."""

import os
import warnings

import mujoco
import numpy as np
import pytest

import sinew
from twins import forward_both, mujoco_inertia_tensors


def load_both(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # settotalmass deprecation (MuJoCo), viscosity (sinew)
        mj = mujoco.MjModel.from_xml_path(path)
        sm = sinew.Model.from_mjcf(path)
    return mj, sm


def same_rotation(q1, q2):
    return min(np.abs(q1 - q2).max(), np.abs(q1 + q2).max())


def test_compiled_model_matches_mujoco(gym_model):
    _, path = gym_model
    mj, sm = load_both(path)
    assert (sm.nq, sm.nv, sm.nu, sm.nbody, sm.njnt) == (mj.nq, mj.nv, mj.nu, mj.nbody, mj.njnt)
    assert sm.body_names == [mj.body(i).name for i in range(mj.nbody)][:1] + sm.body_names[1:]
    np.testing.assert_allclose(sm.body_mass, mj.body_mass, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sm.body_ipos, mj.body_ipos, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(sm.body_inertia_tensor, mujoco_inertia_tensors(mj), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sm.body_pos, mj.body_pos, rtol=1e-9, atol=1e-12)
    for b in range(mj.nbody):
        assert same_rotation(sm.body_quat[b], mj.body_quat[b]) < 1e-9, b
    np.testing.assert_allclose(sm.qpos0, mj.qpos0, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sm.actuator_ctrlrange, mj.actuator_ctrlrange, atol=0)


def random_state(mj, rng):
    q = mj.qpos0.copy()
    for j in range(mj.njnt):
        a = mj.jnt_qposadr[j]
        t = mj.jnt_type[j]
        if t == mujoco.mjtJoint.mjJNT_FREE:
            q[a : a + 3] += rng.normal(size=3) * 0.3
            quat = rng.normal(size=4)
            q[a + 3 : a + 7] = quat / np.linalg.norm(quat)
        elif t == mujoco.mjtJoint.mjJNT_BALL:
            quat = rng.normal(size=4)
            q[a : a + 4] = quat / np.linalg.norm(quat)
        else:
            q[a] += rng.normal() * 0.5
    return q, rng.normal(size=mj.nv), rng.uniform(-1.5, 1.5, size=mj.nu)


def test_accelerations_match_mj_forward_without_constraints(gym_model):
    _, path = gym_model
    mj, sm = load_both(path)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d = mujoco.MjData(mj)
    sim = sinew.Sim(sm)
    rng = np.random.default_rng(0)
    for _ in range(25):
        q, v, u = random_state(mj, rng)
        forward_both(mj, d, sim, q, v, u)
        scale = max(1.0, np.abs(d.qacc).max())
        assert np.abs(sim.qacc - d.qacc).max() / scale <= 1e-8
        np.testing.assert_allclose(sim.xpos, d.xpos, atol=1e-9)
        np.testing.assert_allclose(sim.xmat.reshape(-1, 9), d.xmat, atol=1e-9)


def assert_energy_equals_mujocos(path):
    """Potential (gravity, joint and tendon springs) and kinetic energy (armature included) at
    random states."""
    mj, sm = load_both(path)
    mj.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q, v, u = random_state(mj, rng)
        forward_both(mj, d, sim, q, v, u)
        mujoco.mj_energyPos(mj, d)
        mujoco.mj_energyVel(mj, d)
        np.testing.assert_allclose(sim.energy, d.energy, rtol=1e-12, atol=1e-12)


def test_energy_equals_mujocos(gym_model):
    assert_energy_equals_mujocos(gym_model[1])


@pytest.mark.parametrize("name", ["fish", "swimmer", "manipulator", "humanoid_CMU"])
def test_energy_equals_mujocos_with_springs(name):
    # dm_control's models with joint and tendon springs
    import dm_control
    assert_energy_equals_mujocos(os.path.join(os.path.dirname(dm_control.__file__), "suite", f"{name}.xml"))


def test_batch_body_quantities_match_mujoco(gym_model):
    """What environments observe of a Batch's bodies (xpos, xmat, xipos) at random states."""
    _, path = gym_model
    mj, sm = load_both(path)
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(3)
    states = [random_state(mj, rng) for _ in range(4)]
    b = sinew.Batch(sm, len(states), num_threads=1)
    for i, (q, v, _) in enumerate(states):
        b.qpos[i], b.qvel[i] = q, v
    b.forward_kinematics()
    for i, (q, v, _) in enumerate(states):
        d.qpos[:], d.qvel[:] = q, v
        mujoco.mj_kinematics(mj, d)
        np.testing.assert_allclose(b.xpos[i], d.xpos, atol=1e-9)
        np.testing.assert_allclose(b.xmat[i], d.xmat, atol=1e-9)
        np.testing.assert_allclose(b.xipos[i], d.xipos, atol=1e-9)


@pytest.mark.parametrize(
    "name, integrator",
    [(n, i) for n in ["inverted_double_pendulum", "reacher", "half_cheetah"] for i in ["Euler", "RK4"]]
    + [("humanoid", "Euler")],
)
def test_short_trajectories_match_mujoco(name, integrator):
    """Same integrator (MuJoCo's Euler has implicit joint damping, as sinew's) over 100 steps.
    Humanoid's free joint under RK4 is checked against the published tableau below instead:
    mujoco 4.0's mj_step differs from it by ~1e-11 per step on quaternion joints."""
    from conftest import gym_model_path

    mj, sm = load_both(gym_model_path(name))
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    mj.opt.integrator = getattr(mujoco.mjtIntegrator, "mjINT_EULER" if integrator == "Euler" else "mjINT_RK4")
    sm = sm.with_options(integrator=integrator, contact=False, limit=False)
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    rng = np.random.default_rng(1)
    q, v, _ = random_state(mj, rng)
    d.qpos[:], d.qvel[:] = q, v * 0.1
    sim.qpos[:], sim.qvel[:] = q, v * 0.1
    for _ in range(100):
        u = rng.uniform(-1, 1, size=mj.nu)
        d.ctrl[:] = u
        sim.ctrl[:] = u
        mujoco.mj_step(mj, d)
        sim.step()
    np.testing.assert_allclose(sim.qpos, d.qpos, atol=1e-8)
    np.testing.assert_allclose(sim.qvel, d.qvel, atol=1e-7)


def test_rk4_step_equals_mujocos_on_a_free_joint():
    """sinew's RK4 step equals MuJoCo's own (mj_step, RK4) on the humanoid with its free joint:
    the same tableau, and rotations through dexp⁻¹ (fourth order on SO(3))."""
    from conftest import gym_model_path

    mj, sm = load_both(gym_model_path("humanoid"))
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    mj.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    d, sim = mujoco.MjData(mj), sinew.Sim(sm.with_options(integrator="RK4", contact=False, limit=False))
    rng = np.random.default_rng(3)
    q0, v0, u = random_state(mj, rng)
    d.qpos[:], d.qvel[:], d.ctrl[:] = q0, v0, u
    sim.qpos[:], sim.qvel[:], sim.ctrl[:] = q0, v0, u
    for _ in range(10):
        mujoco.mj_step(mj, d)
        sim.step()
    np.testing.assert_allclose(sim.qpos, d.qpos, atol=1e-12)
    np.testing.assert_allclose(sim.qvel, d.qvel, atol=1e-10)


def test_springdamper_sets_stiffness_and_damping_as_mujocos():
    """A joint's springdamper (time constant, damping ratio) overrides its stiffness and damping
    with those of its effective inertia at qpos0, 1 / (M⁻¹)ᵢᵢ, as MuJoCo's compiler does."""
    xml = """<mujoco><worldbody><body><joint springdamper="0.2 0.7" armature="0.01"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05"/>
      <body pos="0.4 0 0"><joint springdamper="0.1 1" stiffness="5" damping="3"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
        <body pos="0.4 0 0"><joint type="slide" springdamper="0.05 0.3"/><geom size="0.05"/></body></body></body>
      </worldbody></mujoco>"""
    mj, sim = mujoco.MjModel.from_xml_string(xml), sinew.Sim(sinew.Model.from_mjcf_string(xml))
    assert mj.jnt_stiffness.min() > 0 and mj.dof_damping.min() > 0
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(3)
    for _ in range(10):
        q, v = rng.normal(0.0, 0.5, mj.nq), rng.normal(0.0, 1.0, mj.nv)
        forward_both(mj, d, sim, q, v)
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-10, atol=1e-10)
