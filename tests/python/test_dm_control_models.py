"""dm_control's suite models, read as the dm-control package ships them (includes and all),
against MuJoCo on the same files: sizes, qpos0, masses, and the constraint-free acceleration at
random states and controls (joint and tendon springs and dampers, motors and servos on joints and
tendons; tendon lengths and Jacobians; fluid forces); each steps 2 s with
random controls, finite, in both constraint modes. The files sinew cannot read yet fail with a
ModelError naming what stops them."""

import importlib.util
import os
import warnings

import mujoco
import numpy as np
import pytest

import sinew

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")
LOADED = ["acrobot", "ball_in_cup", "cartpole", "cheetah", "finger", "fish", "hopper", "humanoid", "humanoid_CMU", "lqr",
          "manipulator", "pendulum", "point_mass", "reacher", "stacker", "swimmer", "walker"]
#: what stops each of the others (the [models] and [geometry] work brings them)
NOT_YET = {"dog": "mesh", "quadruped": "hfield"}


def load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return sinew.Model.from_mjcf(os.path.join(SUITE, name + ".xml"))


def test_every_suite_file_is_listed():
    files = {f[:-4] for f in os.listdir(SUITE) if f.endswith(".xml")}
    assert files == set(LOADED) | set(NOT_YET)


@pytest.mark.parametrize("name", LOADED)
def test_suite_model_equals_mujocos(name):
    m = load(name)
    path = os.path.join(SUITE, name + ".xml")
    mj = mujoco.MjModel.from_xml_path(path)
    assert (m.nq, m.nv, m.nu, m.nbody) == (mj.nq, mj.nv, mj.nu, mj.nbody)
    np.testing.assert_array_equal(m.qpos0, mj.qpos0)
    np.testing.assert_allclose(m.body_mass, mj.body_mass, rtol=1e-12)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = mj.qpos0.copy()
        mujoco.mj_integratePos(mj, q, rng.normal(0.0, 0.3, mj.nv), 1.0)
        v, u = rng.normal(0.0, 1.0, mj.nv), rng.uniform(-1.0, 1.0, mj.nu)
        d.qpos[:], d.qvel[:], d.ctrl[:] = q, v, u
        mujoco.mj_forward(mj, d)
        sim = sinew.Sim(m)
        sim.qpos[:], sim.qvel[:], sim.ctrl[:] = q, v, u
        sim.forward()
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


@pytest.mark.parametrize("name", sorted(NOT_YET))
def test_suite_files_not_read_yet_say_why(name):
    with pytest.raises(sinew.ModelError, match=NOT_YET[name]):
        load(name)
