"""dm_control's suite as sinew envs (sinew.dmc): every task's observations and reward equal
dm_control's at the same states (the sensors that read contact forces given sinew's readings),
its initial states come from the same distributions, and the envs behave as gymnasium envs
(spaces, truncation, pixels, determinism, pickling).

dm_control itself runs in a subprocess (tests/python/dmc_reference.py) on the installed MuJoCo
when the installed dm-control loads its tasks under it (1.0.52 and MuJoCo 4), else on MuJoCo 3.17,
installed once into ~/.cache/sinew-tests (dm-control 1.0.50 cannot load its tasks under MuJoCo 4)."""

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
# cheetah settles onto the floor for 200 physics steps at each reset: its root height and pitch
# sit on exact contact in sinew and on soft contact in MuJoCo
SETTLED = {"cheetah-run"}


@pytest.fixture(scope="session")
def reference(tmp_path_factory):
    """dm_control's observations and rewards at the states sinew's random rollouts reach, and its
    initial states of STARTS episodes per task; with sinew's own."""
    env = dict(os.environ, MUJOCO_GL="disable")
    loads = [sys.executable, "-c", "from dm_control import suite; suite.load('acrobot', 'swingup')"]
    if subprocess.run(loads, env=env, capture_output=True).returncode != 0:
        cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        target = pathlib.Path(cache) / "sinew-tests" / "mujoco-3.17.0"
        if not (target / "mujoco" / "__init__.py").exists():
            subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                            "mujoco==3.17.0"], check=True)
        env["PYTHONPATH"] = str(target)
    data, mine = {}, {}
    for name in TASKS:
        key = name[4:]
        core = DmcCore(name, WORLDS)
        core.reset_worlds(np.arange(WORLDS), [np.random.default_rng(i) for i in range(WORLDS)])
        rng = np.random.default_rng(7)
        # unbounded controls (lqr's) drawn in ±1
        lo, hi = np.clip(core.action_space.low, -1, 1), np.clip(core.action_space.high, -1, 1)
        # geoms and sites each world placed (targets), sent with every state
        for kind, names in (("geom", core.model.geom_names), ("site", core.model.site_names)):
            for i, element in enumerate(names):
                pos = getattr(core.batch, f"{kind}_pos")(i)
                if np.ptp(pos, axis=0).any():
                    data[f"{key}/{kind}/{element}"] = np.tile(pos, (STEPS // EVERY + 1, 1))
        # bodies each world placed (targets, receptacles), sent with every state
        for field in ("body_pos", "body_quat"):
            values = core.batch.params(field)
            for b in np.flatnonzero(np.ptp(values, axis=0).any(axis=1)):
                data[f"{key}/{field}/{core.model.body_names[b]}"] = np.tile(values[:, b], (STEPS // EVERY + 1, 1))
        # each world's own height fields, sent with every state
        if core.model.hfield_names and np.ptp(core.batch.params("hfield_data"), axis=0).any():
            data[f"{key}/hfield"] = np.tile(core.batch.params("hfield_data"), (STEPS // EVERY + 1, 1))
        # the initial states, then the states of a random rollout
        states = [(core.batch.qpos.copy(), core.batch.qvel.copy(), core.batch.ctrl.copy(), core.batch.act.copy(), core.batch.sensordata)]
        obs, rewards = [core.observe()], [core.task.reward(Physics(core.batch, core.names))]
        for s in range(STEPS):
            o, r, _, _ = core.step(rng.uniform(lo, hi, (WORLDS, core.model.nu)))
            if s % EVERY == EVERY - 1:
                states.append((core.batch.qpos.copy(), core.batch.qvel.copy(), core.batch.ctrl.copy(), core.batch.act.copy(),
                               core.batch.sensordata))
                obs.append(o)
                rewards.append(r)
        for k, part in enumerate(("qpos", "qvel", "ctrl", "act")):
            data[f"{key}/{part}"] = np.concatenate([s[k] for s in states])
        # sinew's readings of every sensor, which the reference uses for those that read contact
        # forces (the simulators' contacts differ): what follows from them must then agree too
        sensors = np.concatenate([s[4] for s in states])
        for n, adr, dim in zip(core.model.sensor_names, core.model.sensor_adr, core.model.sensor_dim):
            data[f"{key}/sensor/{n}"] = sensors[:, adr:adr + dim]
        data[f"{key}/episodes"] = np.array(STARTS)
        starts = DmcCore(name, STARTS)
        starts.reset_worlds(np.arange(STARTS), [np.random.default_rng(100 + i) for i in range(STARTS)])
        mine[key] = (np.concatenate(obs), np.concatenate(rewards), np.hstack([starts.batch.qpos, starts.batch.qvel]))
    src, dst = tmp_path_factory.mktemp("dmc") / "in.npz", tmp_path_factory.mktemp("dmc") / "out.npz"
    np.savez(src, **data)
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
    np.testing.assert_allclose(obs, ref[f"{key}/obs"], rtol=0, atol=1e-9 * max(1.0, np.abs(obs).max()))
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


def test_every_task_is_registered_with_its_spaces():
    for name in TASKS:
        env = gym.make(f"sinew/{name}-v0")
        obs, _ = env.reset(seed=0)
        assert env.observation_space.contains(obs), name
        assert env.action_space.shape == (env.unwrapped.model.nu,)
        env.close()


@pytest.mark.parametrize("kwargs", [{}, {"from_pixels": True, "frame_stack": 3, "action_repeat": 2},
                                    {"flat_observation": False}, {"from_pixels": True, "pixels_only": False}])
def test_gymnasium_env_checker_passes(kwargs):
    from gymnasium.utils.env_checker import check_env
    check_env(gym.make("sinew/dmc-walker-walk-v0", **kwargs).unwrapped, skip_render_check=True)


def test_episode_ends_at_the_time_limit_truncated_and_action_repeat_shortens_it():
    for repeat, steps in ((1, 1000), (8, 125), (3, 334)):
        env = gym.make("sinew/dmc-cartpole-balance-v0", action_repeat=repeat)
        env.reset(seed=0)
        for k in range(1, steps + 1):
            _, _, terminated, truncated, _ = env.step(np.zeros(1))
            assert not terminated
            assert truncated == (k == steps), (repeat, k)


def test_action_repeat_sums_the_rewards_of_its_control_steps():
    a = gym.make("sinew/dmc-cheetah-run-v0", action_repeat=2)
    b = gym.make("sinew/dmc-cheetah-run-v0")
    oa, _ = a.reset(seed=3)
    ob, _ = b.reset(seed=3)
    np.testing.assert_array_equal(oa, ob)
    rng = np.random.default_rng(0)
    for _ in range(20):
        u = rng.uniform(-1, 1, 6)
        oa, ra, *_ = a.step(u)
        ob, r1, *_ = b.step(u)
        ob, r2, *_ = b.step(u)
        np.testing.assert_array_equal(oa, ob)
        assert ra == r1 + r2


def rollout(env, steps, seed=0):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(1)
    out = [obs]
    for _ in range(steps):
        obs, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        out.append(obs)
    return np.stack(out)


@pytest.mark.parametrize("task", ["dmc-walker-walk", "dmc-humanoid-stand", "dmc-finger-turn_hard"])
def test_vector_env_equals_single_envs_for_any_thread_count(task):
    singles = [gym.make(f"sinew/{task}-v0") for _ in range(3)]
    obs = [s.reset(seed=10 + i)[0] for i, s in enumerate(singles)]
    for threads in (1, 2):
        venv = gym.make_vec(f"sinew/{task}-v0", num_envs=3, vectorization_mode="vector_entry_point",
                            num_threads=threads)
        vobs, _ = venv.reset(seed=10)
        np.testing.assert_array_equal(vobs, np.stack(obs))
    rng = np.random.default_rng(2)
    for _ in range(30):
        u = rng.uniform(-1, 1, (3, *singles[0].action_space.shape))
        vobs, vrew, *_ = venv.step(u)
        for i, s in enumerate(singles):
            o, r, *_ = s.step(u[i])
            np.testing.assert_array_equal(vobs[i], o)
            assert vrew[i] == r


def test_pixels_are_frames_of_the_domain_camera_stacked_oldest_first():
    env = gym.make("sinew/dmc-cartpole-swingup-v0", from_pixels=True, frame_stack=3, width=64, height=48)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (48, 64, 9) and obs.dtype == np.uint8
    # a fresh stack holds the reset frame three times
    np.testing.assert_array_equal(obs[..., :3], obs[..., 6:])
    frames = [obs[..., 6:]]
    for _ in range(2):
        obs, *_ = env.step(np.ones(1))
        np.testing.assert_array_equal(obs[..., :6], np.concatenate(frames[-2:] if len(frames) > 1 else frames * 2, axis=-1))
        frames.append(obs[..., 6:])
    assert not np.array_equal(frames[0], frames[-1]), "the cart moved: the frames differ"
    both = gym.make("sinew/dmc-cartpole-swingup-v0", from_pixels=True, pixels_only=False)
    obs, _ = both.reset(seed=0)
    assert list(obs) == ["pixels", "position", "velocity"] and obs["pixels"].shape == (84, 84, 3)


def test_targets_are_drawn_where_each_world_placed_them():
    venv = gym.make_vec("sinew/dmc-reacher-easy-v0", num_envs=2, vectorization_mode="vector_entry_point",
                        from_pixels=True, pixels_only=False, flat_observation=False)
    obs, _ = venv.reset(seed=0)
    assert not np.allclose(obs["to_target"][0], obs["to_target"][1])
    # the same arm pose in both worlds, the targets where each world put them: different frames
    core = venv.unwrapped._core
    core.batch.qpos[1] = core.batch.qpos[0]
    core.batch.forward_kinematics()
    frames = core.batch.render(84, 84, core.camera_id)
    assert not np.array_equal(frames[0], frames[1])


def test_point_mass_hard_drives_each_world_along_its_own_drawn_directions():
    venv = gym.make_vec("sinew/dmc-point_mass-hard-v0", num_envs=3, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    batch = venv.unwrapped._core.batch
    prm = batch.params("wrap_prm")
    assert prm.shape == (3, 4) and not np.allclose(prm[0], prm[1])
    assert np.allclose(np.linalg.norm(prm[:, :2], axis=1), 1) and np.all(np.abs(np.sum(prm[:, :2] * prm[:, 2:], axis=1)) <= 0.9)
    # from rest, the first control alone pushes the mass along the world's first direction
    batch.qvel[:] = 0
    batch.forward_kinematics()
    v0 = batch.qvel.copy()
    venv.step(np.tile([1.0, 0.0], (3, 1)))
    dv = batch.qvel - v0
    assert np.allclose(dv[:, 0] * prm[:, 1] - dv[:, 1] * prm[:, 0], 0, atol=1e-12) and np.all(np.sum(dv * prm[:, :2], axis=1) > 0)
    copy = pickle.loads(pickle.dumps(venv))
    np.testing.assert_array_equal(copy.unwrapped._core.batch.params("wrap_prm"), prm)


def test_quadruped_escape_starts_each_world_clear_of_its_own_terrain():
    venv = gym.make_vec("sinew/dmc-quadruped-escape-v0", num_envs=3, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    batch = venv.unwrapped._core.batch
    terrain = batch.params("hfield_data")
    assert not np.allclose(terrain[0], terrain[1])
    assert batch.penetrations().tolist() == [0, 0, 0]
    # lowered by a centimetre, each world touches its own bumps
    batch.qpos[:, 2] -= 0.01
    batch.forward_kinematics()
    assert all(n > 0 for n in batch.penetrations())


def test_copies_step_on_bit_identically():
    venv = gym.make_vec("sinew/dmc-fish-swim-v0", num_envs=2, vectorization_mode="vector_entry_point",
                        from_pixels=True, frame_stack=2, pixels_only=False)
    venv.reset(seed=4)
    u = np.full((2, venv.unwrapped._core.model.nu), 0.3)
    venv.step(u)
    copy = pickle.loads(pickle.dumps(venv))
    for _ in range(3):
        a, b = venv.step(u)[0], copy.step(u)[0]
        for k in a:
            np.testing.assert_array_equal(a[k], b[k])


def test_bad_actions_and_arguments_raise_value_errors():
    env = gym.make("sinew/dmc-walker-walk-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="not finite"):
        env.step(np.full(6, np.nan))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(5))
    for kwargs, words in (({"action_repeat": 0}, "action_repeat"), ({"camera_id": 9}, "camera_id"),
                          ({"camera_id": "nope"}, "no camera")):
        with pytest.raises(ValueError, match=words):
            gym.make("sinew/dmc-walker-walk-v0", **kwargs)


def test_sb3_vec_env_runs_a_dmc_task():
    import sinew.sb3
    venv = sinew.sb3.make_vec_env("sinew/dmc-walker-walk-v0", n_envs=4, seed=0, action_repeat=4)
    obs = venv.reset()
    assert obs.shape == (4, 24) and venv.max_episode_steps == 250
    obs, reward, done, info = venv.step(np.zeros((4, 6)))
    assert obs.shape == (4, 24) and reward.shape == (4,) and not done.any()


def test_placing_elements_checks_its_input():
    import sinew as s
    from sinew.dmc import suite_dir
    model = s.Model.from_mjcf(os.path.join(suite_dir(), "reacher.xml"))
    batch = s.Batch(model, 2)
    target = model.geom_names.index("target")
    for args, words in (((target, [np.nan, 0, 0]), "finite|NaN|nan"), ((99, [0, 0, 0]), "out of range"),
                        ((target, [[0, 0, 0]] * 3), "shape")):
        with pytest.raises(ValueError, match=words):
            batch.set_geom_pos(*args)
    # contacts are off in reacher: any geom may be placed; where it was placed is read back
    batch.set_geom_pos(target, [[0.1, 0, 0.01], [0, 0.1, 0.01]])
    np.testing.assert_array_equal(batch.geom_pos(target), [[0.1, 0, 0.01], [0, 0.1, 0.01]])
    with pytest.raises(ValueError, match="out of range"):
        batch.read_sensors([99])
