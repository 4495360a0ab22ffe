"""dm_control's suite as sinew envs (sinew.dmc): every task's observations and reward equal
dm_control's at the same states, its initial states come from the same distributions, and the
envs behave as gymnasium envs (spaces, truncation, pixels, determinism, pickling).

dm_control itself runs in a subprocess (tests/python/dmc_reference.py) on MuJoCo 3.17, installed
once into ~/.cache/sinew-tests: dm-control 1.0.50 cannot load its tasks under MuJoCo 4."""

import os
import pathlib
import pickle
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest
from scipy import stats

import sinew  # noqa: F401  (registers the envs)
from sinew.dmc import TASKS
from sinew.dmc.core import DmcCore
from sinew.dmc.physics import Physics

WORLDS, STEPS, EVERY, STARTS = 4, 40, 10, 60
# contact forces differ between the simulators (sinew's are exact, MuJoCo's soft): touch sensors
# are compared in test_touch_is_contact_force instead
CONTACT_KEYS = {"touch"}
# cheetah settles onto the floor for 200 physics steps at each reset: its root height and pitch
# sit on exact contact in sinew and on soft contact in MuJoCo
SETTLED = {"cheetah-run"}


@pytest.fixture(scope="session")
def reference(tmp_path_factory):
    """dm_control's observations and rewards at the states sinew's random rollouts reach, and its
    initial states of STARTS episodes per task; with sinew's own."""
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    target = pathlib.Path(cache) / "sinew-tests" / "mujoco-3.17.0"
    if not (target / "mujoco" / "__init__.py").exists():
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                        "mujoco==3.17.0"], check=True)
    data, mine = {}, {}
    for name in TASKS:
        key = name[4:]
        core = DmcCore(name, WORLDS)
        core.reset_worlds(np.arange(WORLDS), [np.random.default_rng(i) for i in range(WORLDS)])
        rng = np.random.default_rng(7)
        # geoms and sites each world placed (targets), sent with every state
        for kind, names in (("geom", core.model.geom_names), ("site", core.model.site_names)):
            for i, element in enumerate(names):
                pos = getattr(core.batch, f"{kind}_pos")(i)
                if np.ptp(pos, axis=0).any():
                    data[f"{key}/{kind}/{element}"] = np.tile(pos, (STEPS // EVERY + 1, 1))
        # the initial states, then the states of a random rollout
        states = [(core.batch.qpos.copy(), core.batch.qvel.copy(), core.batch.ctrl.copy())]
        obs, rewards = [core.observe()], [core.task.reward(Physics(core.batch, core.names))]
        for s in range(STEPS):
            o, r, _, _ = core.step(rng.uniform(core.action_space.low, core.action_space.high, (WORLDS, core.model.nu)))
            if s % EVERY == EVERY - 1:
                states.append((core.batch.qpos.copy(), core.batch.qvel.copy(), core.batch.ctrl.copy()))
                obs.append(o)
                rewards.append(r)
        for k, part in enumerate(("qpos", "qvel", "ctrl")):
            data[f"{key}/{part}"] = np.concatenate([s[k] for s in states])
        data[f"{key}/episodes"] = np.array(STARTS)
        starts = DmcCore(name, STARTS)
        starts.reset_worlds(np.arange(STARTS), [np.random.default_rng(100 + i) for i in range(STARTS)])
        mine[key] = (np.concatenate(obs), np.concatenate(rewards), np.hstack([starts.batch.qpos, starts.batch.qvel]))
    src, dst = tmp_path_factory.mktemp("dmc") / "in.npz", tmp_path_factory.mktemp("dmc") / "out.npz"
    np.savez(src, **data)
    env = dict(os.environ, PYTHONPATH=str(target), MUJOCO_GL="disable")
    script = os.path.join(os.path.dirname(__file__), "dmc_reference.py")
    subprocess.run([sys.executable, script, str(src), str(dst)], check=True, env=env)
    return mine, dict(np.load(dst))


@pytest.mark.parametrize("name", list(TASKS))
def test_observation_and_reward_equal_dm_control(reference, name):
    mine, ref = reference
    key = name[4:]
    obs, reward, _ = mine[key]
    keys = ref[f"{key}/keys"]
    assert obs.shape == ref[f"{key}/obs"].shape
    compared = ~np.isin(keys, list(CONTACT_KEYS))
    np.testing.assert_allclose(obs[:, compared], ref[f"{key}/obs"][:, compared], rtol=0, atol=1e-9)
    np.testing.assert_allclose(reward, ref[f"{key}/reward"], rtol=0, atol=1e-9)
    assert np.ptp(obs, axis=0).max() > 0, "observations never vary"


@pytest.mark.parametrize("name", list(TASKS))
def test_initial_states_drawn_as_dm_control_draws_them(reference, name):
    """Each coordinate of the initial state (qpos, qvel) has dm_control's distribution: a
    two-sample Kolmogorov–Smirnov test over STARTS episodes each, or equal values where
    dm_control's do not vary."""
    mine, ref = reference
    key = name[4:]
    ours, theirs = mine[key][2], ref[f"{key}/reset"]
    assert ours.shape == theirs.shape
    for k in range(ours.shape[1]):
        if np.ptp(theirs[:, k]) == 0:
            if key not in SETTLED:
                np.testing.assert_allclose(ours[:, k], theirs[0, k], atol=1e-12, err_msg=f"coordinate {k}")
        elif key in SETTLED:
            # settled on the floor: the same spread of values, within a centimetre or degree
            assert abs(np.median(ours[:, k]) - np.median(theirs[:, k])) < 0.02 + 0.2 * np.std(theirs[:, k]), k
        else:
            assert stats.ks_2samp(ours[:, k], theirs[:, k]).pvalue > 1e-3, f"coordinate {k}"
