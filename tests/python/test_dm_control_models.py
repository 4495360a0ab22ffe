"""dm_control's suite models, read as the dm-control package ships them (includes and all),
against MuJoCo on the same files: sizes, qpos0, masses, and the constraint-free acceleration at
random states and controls (joint and tendon springs and dampers, motors and servos on joints and
tendons; tendon lengths and Jacobians; fluid forces); each steps 2 s with
random controls, finite, in both constraint modes: every file of the suite."""

import importlib.util
import os
import warnings

import mujoco
import numpy as np
import pytest

import sinew
from twins import assert_inertias_equal, forward_both, near_qpos0

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")
LOADED = ["acrobot", "ball_in_cup", "cartpole", "cheetah", "dog", "finger", "fish", "hopper", "humanoid", "humanoid_CMU", "lqr",
          "manipulator", "pendulum", "point_mass", "quadruped", "reacher", "stacker", "swimmer", "walker"]
#: models whose inertias come from meshes: MuJoCo diagonalises them to about 1e-8 (its eigen
#: solver's tolerance on near-equal moments); sinew keeps the f64 tensor. qacc is compared with
#: sinew's inertias given to MuJoCo, the inertias themselves to that tolerance
MESH_INERTIA = {"dog": 2e-8}


def load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return sinew.Model.from_mjcf(os.path.join(SUITE, name + ".xml"))


def test_every_suite_file_is_listed():
    files = {f[:-4] for f in os.listdir(SUITE) if f.endswith(".xml")}
    assert files == set(LOADED)


@pytest.mark.parametrize("name", LOADED)
def test_suite_model_equals_mujocos(name):
    m = load(name)
    path = os.path.join(SUITE, name + ".xml")
    mj = mujoco.MjModel.from_xml_path(path)
    assert (m.nq, m.nv, m.nu, m.nbody) == (mj.nq, mj.nv, mj.nu, mj.nbody)
    np.testing.assert_array_equal(m.qpos0, mj.qpos0)
    np.testing.assert_allclose(m.body_mass, mj.body_mass, rtol=1e-12)
    ours = np.array(m.body_inertia_tensor)
    assert_inertias_equal(ours, mj, MESH_INERTIA.get(name, 1e-12))
    for b in range(1, mj.nbody) if name in MESH_INERTIA else ():
        moments, axes = np.linalg.eigh(ours[b])
        axes[:, 0] *= np.sign(np.linalg.det(axes))
        mj.body_inertia[b] = moments
        mujoco.mju_mat2Quat(mj.body_iquat[b], axes.flatten())
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = near_qpos0(mj, rng, 0.3)
        v, u = rng.normal(0.0, 1.0, mj.nv), rng.uniform(-1.0, 1.0, mj.nu)
        sim = sinew.Sim(m)
        forward_both(mj, d, sim, q, v, u)
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(sim.ten_length, d.ten_length, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(sim.ten_J, dense_ten_j(mj, d), rtol=1e-12, atol=1e-12)


def dense_ten_j(mj, d):
    """MuJoCo's tendon Jacobian (sparse since 3.6) as (ntendon, nv)."""
    j = np.zeros((mj.ntendon, mj.nv))
    for t in range(mj.ntendon):
        adr, nnz = mj.ten_J_rowadr[t], mj.ten_J_rownnz[t]
        j[t, mj.ten_J_colind[adr:adr + nnz]] = d.ten_J[adr:adr + nnz]
    return j


@pytest.mark.parametrize("mode", ["acceleration", "velocity"])
@pytest.mark.parametrize("name", LOADED)
def test_suite_model_steps_two_seconds_with_random_controls(name, mode):
    m = load(name).with_options(constraint_mode=mode)
    sim = sinew.Sim(m)
    rng = np.random.default_rng(0)
    lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
    for _ in range(int(round(2.0 / m.timestep))):
        sim.ctrl[:] = rng.uniform(lo, hi)
        sim.step()
    assert np.isfinite(sim.qpos).all() and np.isfinite(sim.qvel).all()
    assert sim.constraint_stats["fallback_zero"] == 0

