"""Helpers for tests that compare sinew with MuJoCo on the same model: MuJoCo's inertias as full
tensors, states near qpos0, and one state set and forwarded in both simulators."""

import mujoco
import numpy as np


def mujoco_inertia_tensors(mj):
    """Each body's inertia about its centre of mass in the body frame (nbody, 3, 3), from
    MuJoCo's principal moments and axes."""
    out = np.zeros((mj.nbody, 3, 3))
    for b in range(mj.nbody):
        r = np.zeros(9)
        mujoco.mju_quat2Mat(r, mj.body_iquat[b])
        r = r.reshape(3, 3)
        out[b] = r @ np.diag(mj.body_inertia[b]) @ r.T
    return out


def near_qpos0(mj, rng, spread):
    """qpos0 moved by a normal velocity of deviation `spread` for unit time (quaternions kept unit)."""
    q = mj.qpos0.copy()
    mujoco.mj_integratePos(mj, q, rng.normal(0.0, spread, mj.nv), 1.0)
    return q


def forward_both(mj, d, sim, qpos, qvel, ctrl=None):
    """The state (and controls) set in MuJoCo's data `d` and in `sim`, each forwarded."""
    d.qpos[:], d.qvel[:] = qpos, qvel
    sim.qpos[:], sim.qvel[:] = qpos, qvel
    if ctrl is not None:
        d.ctrl[:], sim.ctrl[:] = ctrl, ctrl
    mujoco.mj_forward(mj, d)
    sim.forward()


def assert_inertias_equal(ours, mj, rel):
    """Every moving body's inertia tensor of sinew (`ours`, (nbody, 3, 3)) equals MuJoCo's to
    `rel` of its largest entry."""
    theirs = mujoco_inertia_tensors(mj)
    for b in range(1, mj.nbody):
        np.testing.assert_allclose(ours[b], theirs[b], rtol=0, atol=rel * np.abs(theirs[b]).max(), err_msg=f"body {b}")
