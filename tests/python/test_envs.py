"""sinew's gymnasium environments against their MuJoCo v5 twins, gymnasium's and SB3's checkers,
the native vector env against single envs, determinism and bad input."""

import warnings

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import sinew
from sinew.tasks import TASKS

NAMES = list(TASKS)
#: observation entries that come from contact forces (soft in MuJoCo, exact in sinew)
CONTACT_OBS = {"Ant": slice(27, 105), "Humanoid": slice(270, 348)}


def twin(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gym.make(f"{name}-v5")


def test_reset_noise_is_the_generators_own_draws_bit_for_bit():
    """The tasks draw all worlds' noise into one array; each row is exactly what the world's
    generator's uniform and standard_normal give, as the twin draws them."""
    from sinew.tasks import normal, uniform

    for low, high, size in [(-0.005, 0.005, 11), (-0.1, 0.1, 15), (-0.2, 0.3, 2)]:
        ours = uniform([np.random.default_rng(s) for s in range(200)], low, high, size)
        theirs = np.stack([np.random.default_rng(s).uniform(low, high, size) for s in range(200)])
        np.testing.assert_array_equal(ours, theirs)
    ours = normal([np.random.default_rng(s) for s in range(200)], 14)
    np.testing.assert_array_equal(ours, np.stack([np.random.default_rng(s).standard_normal(14) for s in range(200)]))


@pytest.mark.parametrize("name", NAMES)
def test_spaces_and_reset_match_the_mujoco_twin(name):
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    assert env.observation_space == ref.observation_space
    assert env.action_space == ref.action_space
    assert env.spec.max_episode_steps == ref.spec.max_episode_steps
    assert env.unwrapped.dt == pytest.approx(ref.unwrapped.dt)
    obs, info = env.reset(seed=7)
    ref_obs, ref_info = ref.reset(seed=7)
    np.testing.assert_allclose(obs, ref_obs, rtol=0, atol=1e-12)
    assert set(info) == set(ref_info) - {"tendon_length", "tendon_velocity"}


@pytest.mark.parametrize("name", NAMES)
def test_reset_draws_the_twins_state_bit_for_bit(name):
    """What the README claims of reset(seed=s): the twin's qpos and qvel exactly, and the
    observation from them to round-off (sinew's own kinematics give body positions, cinert, cvel)."""
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        ref_obs, _ = ref.reset(seed=seed)
        np.testing.assert_array_equal(env.unwrapped.data.qpos, ref.unwrapped.data.qpos)
        np.testing.assert_array_equal(env.unwrapped.data.qvel, ref.unwrapped.data.qvel)
        np.testing.assert_allclose(obs, ref_obs, rtol=0, atol=1e-13)


@pytest.mark.parametrize("name", NAMES)
def test_observations_match_the_twin_at_the_same_state(name):
    """cinert, cvel, qfrc_actuator, site and body positions come from sinew's own physics."""
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    env.reset(seed=1)
    ref.reset(seed=1)
    rng = np.random.default_rng(0)
    for _ in range(15):
        a = rng.uniform(env.action_space.low, env.action_space.high)
        obs, *_ = env.step(a)
    u, r = env.unwrapped, ref.unwrapped
    r.set_state(u.data_qpos.copy(), u.data_qvel.copy())
    r.data.ctrl[:] = a
    mujoco.mj_forward(r.model, r.data)
    mujoco.mj_rnePostConstraint(r.model, r.data)
    ref_obs = r._get_obs()
    keep = np.ones(len(obs), bool)
    if name in CONTACT_OBS:
        keep[CONTACT_OBS[name]] = False
    if name == "InvertedDoublePendulum":
        keep[-1] = False  # slider limit force: soft in MuJoCo
    np.testing.assert_allclose(obs[keep], ref_obs[keep], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_reward_terms_are_reported_and_sum_to_the_reward(name):
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    env.reset(seed=0)
    ref.reset(seed=0)
    a = env.action_space.sample()
    _, reward, _, _, info = env.step(a)
    _, _, _, _, ref_info = ref.step(a)
    terms = [k for k in ref_info if k.startswith("reward_") or k.endswith("_penalty")]
    assert terms and set(terms) <= set(info)
    assert reward == pytest.approx(sum(info[k] for k in terms), abs=1e-12)
    assert info["sim_diverged"] is False or info["sim_diverged"] == np.False_


@pytest.mark.parametrize("name", NAMES)
def test_reward_terms_and_termination_match_the_twins_formulas(name):
    """sinew's step (reward terms and termination computed in Rust) against the twin's own
    `_get_rew` and `terminated` evaluated at sinew's states before and after the step; the contact
    cost is left out (it reads MuJoCo's soft contact forces)."""
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    u, r = env.unwrapped, ref.unwrapped
    env.reset(seed=2)
    ref.reset(seed=2)
    rng = np.random.default_rng(1)

    def twin_at(qpos, qvel, action):
        r.set_state(qpos, qvel)
        r.data.ctrl[:] = action
        mujoco.mj_forward(r.model, r.data)
        mujoco.mj_rnePostConstraint(r.model, r.data)

    def position():
        if name in ("Hopper", "Walker2d", "HalfCheetah", "Swimmer"):
            return np.array([r.data.qpos[0], 0.0])
        if name == "Ant":
            return r.data.body(r._main_body).xpos[:2].copy()
        if name == "Humanoid":
            from gymnasium.envs.mujoco.humanoid_v5 import mass_center

            return mass_center(r.model, r.data)
        return np.zeros(2)

    checked = 0
    for _ in range(30):
        a = rng.uniform(env.action_space.low, env.action_space.high)
        twin_at(u.data_qpos.copy(), u.data_qvel.copy(), a)
        before = position()
        obs, reward, terminated, _, info = env.step(a)
        twin_at(u.data_qpos.copy(), u.data_qvel.copy(), a)
        if name in ("InvertedPendulum",):
            ref_terminated = bool(not np.isfinite(obs).all() or abs(obs[1]) > 0.2)
            ref_info = {"reward_survive": float(not ref_terminated)}
        elif name == "InvertedDoublePendulum":
            x, _, y = r.data.site_xpos[0]
            ref_terminated = bool(y <= 1)
            ref_info = r._get_rew(x, y, ref_terminated)[1]
        elif name == "Reacher":
            ref_terminated, ref_info = False, r._get_rew(a)[1]
        else:
            x_velocity = (position() - before)[0] / r.dt
            ref_info = r._get_rew(x_velocity, a)[1]
            ref_terminated = bool(not r.is_healthy and r._terminate_when_unhealthy) if hasattr(r, "is_healthy") else False
        assert terminated == ref_terminated
        for k, v in ref_info.items():
            if k != "reward_contact":
                assert info[k] == pytest.approx(v, rel=1e-9, abs=1e-9), k
        checked += 1
        if terminated:
            break
    assert checked >= 3


@pytest.mark.parametrize("name", NAMES)
def test_checkers_warn_no_more_than_for_the_twin(name):
    from stable_baselines3.common.env_checker import check_env as sb3_check

    def warned(env, checker):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            checker(env)
        return {str(x.message).split(".")[0] for x in w if "render" not in str(x.message).lower()}

    env, ref = gym.make(f"sinew/{name}-v0").unwrapped, twin(name).unwrapped
    # rendering is skipped for both: the twin's renderer needs a display
    gym_check = lambda e: check_env(e, skip_render_check=True)  # noqa: E731
    assert warned(env, gym_check) <= warned(ref, gym_check)
    assert warned(env, sb3_check) <= warned(ref, sb3_check)


def rollout_single(name, seeds, steps, actions):
    out = []
    envs = [gym.make(f"sinew/{name}-v0") for _ in seeds]
    obs = [e.reset(seed=s)[0] for e, s in zip(envs, seeds)]
    out.append(np.stack(obs))
    pending = [False] * len(envs)
    for t in range(steps):
        row = []
        for i, e in enumerate(envs):
            if pending[i]:  # next-step autoreset, as the vector env does
                o, _ = e.reset()
                pending[i] = False
            else:
                o, r, term, trunc, _ = e.step(actions[t, i])
                pending[i] = term or trunc
            row.append(o)
        out.append(np.stack(row))
    return np.stack(out)


@pytest.mark.parametrize("name", ["Hopper", "InvertedPendulum"])
def test_vector_env_equals_gymnasiums_sync_vector_env(name):
    """Observations, rewards, flags and infos (entries, masks, values) with autoresets, against
    gymnasium's own SyncVectorEnv over single sinew envs."""
    n = 3
    ours = gym.make_vec(f"sinew/{name}-v0", num_envs=n, vectorization_mode="vector_entry_point")
    sync = gym.make_vec(f"sinew/{name}-v0", num_envs=n, vectorization_mode="sync")
    rng = np.random.default_rng(0)
    ours.reset(seed=10)
    sync.reset(seed=10)
    resets = 0
    for _ in range(150):
        a = rng.uniform(ours.single_action_space.low, ours.single_action_space.high, size=(n,) + ours.single_action_space.shape)
        mine, ref = ours.step(a), sync.step(a)
        for x, y in zip(mine[:4], ref[:4]):
            np.testing.assert_array_equal(x, y)
        info, ref_info = mine[4], ref[4]
        assert sorted(info) == sorted(ref_info)
        for k in (k for k in ref_info if not k.startswith("_")):
            mask = ref_info["_" + k]
            np.testing.assert_array_equal(info["_" + k], mask)
            np.testing.assert_array_equal(info[k][mask], ref_info[k][mask].astype(info[k].dtype))
        # envs that reset report no step entries (none at all when every env resets)
        stepped = info.get("_x_velocity" if name == "Hopper" else "_sim_diverged", np.zeros(n, dtype=bool))
        resets += int((~stepped).sum())
    assert resets > 0, "the rollout should exercise autoreset"


def test_partly_seeded_reset_equals_sync_vector_env():
    """reset(seed=[7, None, 9]) re-seeds worlds 0 and 2 (noise and physics streams) and lets
    world 1 go on with its generator, as gymnasium's SyncVectorEnv over single sinew envs does."""
    n = 3
    ours = gym.make_vec("sinew/Hopper-v0", num_envs=n, vectorization_mode="vector_entry_point")
    sync = gym.make_vec("sinew/Hopper-v0", num_envs=n, vectorization_mode="sync")
    rng = np.random.default_rng(1)
    for seed, steps in [(10, 20), ([7, None, 9], 60), (None, 30)]:
        for x, y in zip(ours.reset(seed=seed)[:1], sync.reset(seed=seed)[:1]):
            np.testing.assert_array_equal(x, y)
        for _ in range(steps):
            a = rng.uniform(-1, 1, size=(n, 3))
            for x, y in zip(ours.step(a)[:4], sync.step(a)[:4]):
                np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("name", ["Hopper", "InvertedPendulum"])
def test_vector_env_equals_single_envs_with_the_same_seeds(name):
    n, steps = 3, 120
    venv = gym.make_vec(f"sinew/{name}-v0", num_envs=n, vectorization_mode="vector_entry_point")
    assert isinstance(venv.unwrapped, gym.vector.VectorEnv)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, size=(steps, n, venv.single_action_space.shape[0]))
    obs, _ = venv.reset(seed=10)
    vec = [obs]
    ends = 0
    for t in range(steps):
        obs, r, term, trunc, info = venv.step(actions[t])
        ends += int((term | trunc).sum())
        vec.append(obs)
    assert ends > 0, "the rollout should exercise autoreset"
    np.testing.assert_array_equal(np.stack(vec), rollout_single(name, [10, 11, 12], steps, actions))


def batch_rollout(n, threads, seeds_from=0, steps=300):
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml").with_options(friction="one_tangent")
    b = sinew.Batch(m, n, seed=seeds_from, num_threads=threads)
    rng = np.random.default_rng(5)
    b.qpos[:] += rng.uniform(-0.1, 0.1, size=b.qpos.shape)
    b.forward_kinematics()
    traj = []
    for _ in range(steps):
        b.ctrl[:] = rng.uniform(-1, 1, size=b.ctrl.shape)
        b.step(4)
        traj.append(b.qpos.copy())
    return np.stack(traj)


def test_batch_is_bit_identical_for_any_thread_count():
    np.testing.assert_array_equal(batch_rollout(8, 1), batch_rollout(8, 2))
    np.testing.assert_array_equal(batch_rollout(8, 1), batch_rollout(8, 3))


def test_batch_rejects_absurd_sizes_with_value_errors():
    """Zero or absurd world and thread counts are ValueErrors naming the argument, raised before
    anything is allocated or spawned (a billion threads would otherwise hang the process)."""
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml")
    for kwargs, name in [({"num_envs": 0}, "num_envs"), ({"num_envs": 10**12}, "num_envs"),
                         ({"num_envs": 2, "num_threads": 0}, "num_threads"),
                         ({"num_envs": 2, "num_threads": 10**9}, "num_threads")]:
        with pytest.raises(ValueError, match=name):
            sinew.Batch(m, **kwargs)


def test_batch_world_does_not_depend_on_batch_size():
    # world 0 of a batch of 5 with seed s equals world 3 of a batch of 7 with seed s − 3,
    # given the same per-world inputs: the inputs here differ per batch, so compare one world
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml").with_options(friction="one_tangent")
    outs = []
    for n, seed, i in [(1, 4, 0), (5, 0, 4), (7, 2, 2)]:
        b = sinew.Batch(m, n, seed=seed, num_threads=2)
        rng = np.random.default_rng(9)
        b.qpos[i, 2] = 0.1
        b.forward_kinematics()
        traj = []
        for _ in range(400):
            b.ctrl[i] = rng.uniform(-1, 1, size=3)
            b.step(4)
            traj.append(b.qpos[i].copy())
        outs.append(np.stack(traj))
    np.testing.assert_array_equal(outs[0], outs[1])
    np.testing.assert_array_equal(outs[0], outs[2])


def test_batch_step_mask_leaves_other_worlds_untouched():
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml")
    a, b = sinew.Batch(m, 3, seed=0), sinew.Batch(m, 3, seed=0)
    mask = np.array([True, False, True])
    a.ctrl[:], b.ctrl[:] = 0.5, 0.5
    b.ctrl[1] = np.nan  # a world not stepped is not checked either
    a.step(4)
    before = [x.copy() for x in (b.qpos[1], b.qvel[1], b.xpos[1], b.cfrc_ext[1])]
    b.step(4, mask)
    np.testing.assert_array_equal(a.qpos[mask], b.qpos[mask])
    np.testing.assert_array_equal(a.xipos[mask], b.xipos[mask])
    for x, y in zip(before, (b.qpos[1], b.qvel[1], b.xpos[1], b.cfrc_ext[1])):
        np.testing.assert_array_equal(x, y)
    assert b.time.tolist() == [a.time[0], 0.0, a.time[2]]
    with pytest.raises(ValueError, match="worlds \\[1\\]"):
        b.step(4)


def test_batch_reset_to_given_states():
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml")
    b = sinew.Batch(m, 3, seed=0)
    b.qvel[:] = 1.0
    q = np.tile(m.qpos0, (2, 1)) + [[0.0, 0.1, 0, 0, 0, 0], [0.0, 0.2, 0, 0, 0, 0]]
    b.reset(np.array([True, False, True]), None, q, np.full((2, m.nv), 0.5))
    np.testing.assert_array_equal(b.qpos[[0, 2]], q)
    assert (b.qvel[[0, 2]] == 0.5).all() and (b.qvel[1] == 1.0).all()
    assert b.xpos[2, 1, 2] == pytest.approx(q[1, 1])  # the torso sits at rootz (outputs refreshed)
    with pytest.raises(ValueError, match="qpos"):
        b.reset(np.array([True, False, False]), None, q)  # two rows for one world
    with pytest.raises(ValueError, match="finite"):
        b.reset(None, None, None, np.full((3, m.nv), np.nan))


def test_constraint_mode_is_an_env_option():
    env = gym.make("sinew/Hopper-v0", constraint_mode="velocity")
    assert env.unwrapped.model.constraint_mode == "velocity"
    env.reset(seed=0)
    obs, reward, *_ = env.step(env.action_space.sample())
    assert np.isfinite(obs).all() and np.isfinite(reward)
    with pytest.raises(ValueError, match="constraint_mode"):
        gym.make("sinew/Hopper-v0", constraint_mode="implicit")


def test_set_task_rejects_bad_parameters():
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml")
    b = sinew.Batch(m, 2)
    good = sinew.tasks.Hopper(m).params()
    with pytest.raises(ValueError, match="unknown task"):
        b.set_task("Hoper", **good)
    with pytest.raises(ValueError, match="missing parameter 'healthy_reward'"):
        b.set_task("Hopper", forward_reward_weight=1.0)
    with pytest.raises(ValueError, match="unknown parameter 'colour'"):
        b.set_task("Hopper", colour=1, **good)
    with pytest.raises(ValueError, match="healthy_z_range"):
        b.set_task("Hopper", **{**good, "healthy_z_range": (2.0, 1.0)})
    with pytest.raises(ValueError, match="finite"):
        b.set_task("Hopper", **{**good, "ctrl_cost_weight": float("nan")})
    with pytest.raises(ValueError, match="free root"):
        b.set_task("Ant", **sinew.tasks.Ant(m, main_body=1).params())
    assert b.obs is None  # nothing was set
    b.set_task("Hopper", **good)
    assert b.obs.shape == (2, 11) and b.info_names[:b.reward_terms] == ["reward_forward", "reward_ctrl", "reward_survive"]


def test_diverging_world_is_reset_alone_and_reported():
    m = sinew.Model.from_mjcf(sinew.tasks.ASSETS + "/hopper.xml")
    a, b = sinew.Batch(m, 3, seed=0), sinew.Batch(m, 3, seed=0)
    b.qvel[1, 0] = 1e12  # world 1 starts beyond the 1e10 bound
    for _ in range(20):
        for x in (a, b):
            x.ctrl[:] = 0.5
            x.step(4)
        if _ == 0:
            assert b.diverged.tolist() == [False, True, False]
    assert np.isfinite(b.qpos).all()
    np.testing.assert_array_equal(a.qpos[[0, 2]], b.qpos[[0, 2]])


def test_pickled_env_is_the_same_env():
    import pickle

    env = gym.make("sinew/Walker2d-v0", forward_reward_weight=2.0)
    copy = pickle.loads(pickle.dumps(env))
    assert copy.unwrapped._core.task.params()["forward_reward_weight"] == 2.0
    a = env.action_space.sample()
    for e in (env, copy):
        e.reset(seed=3)
    np.testing.assert_array_equal(env.step(a)[0], copy.step(a)[0])


def test_bad_actions_raise_value_errors():
    env = gym.make("sinew/Hopper-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="not finite"):
        env.step(np.array([np.nan, 0, 0]))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(4))
    with pytest.raises(ValueError, match="beyond"):
        env.step(np.array([1e308, 0, 0]))  # its control cost would overflow the reward
    # odd but finite inputs are accepted and give finite results
    for a in (np.array([1e9, -1e9, -0.0]), np.full(3, 5e-324), np.array([1, 0, -1]), np.full(3, 0.5, np.float16)):
        obs, reward, *_ = env.step(a)
        assert np.isfinite(obs).all() and np.isfinite(reward)
    venv = gym.make_vec("sinew/Hopper-v0", num_envs=2, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    with pytest.raises(ValueError, match=r"\[1\]"):
        venv.step(np.array([[0, 0, 0], [0, np.inf, 0]]))
    with pytest.raises(ValueError, match="shape"):
        venv.step(np.zeros((3, 3)))
    with pytest.raises(gym.error.ResetNeeded):
        gym.make("sinew/Hopper-v0").unwrapped.step(np.zeros(3))


@pytest.mark.parametrize("name", NAMES)
def test_long_random_rollouts_never_produce_nan(name):
    from stable_baselines3.common.vec_env import VecCheckNan

    import sinew.sb3

    venv = VecCheckNan(sinew.sb3.make_vec_env(f"sinew/{name}-v0", 8, seed=0), raise_exception=True)
    venv.reset()
    low, high = venv.action_space.low, venv.action_space.high
    rng = np.random.default_rng(0)
    for _ in range(1000):
        obs, reward, done, infos = venv.step(rng.uniform(low, high, size=(8, len(low))))
    assert np.isfinite(obs).all()


def test_sb3_adapter_reports_terminal_observations():
    import sinew.sb3

    venv = sinew.sb3.make_vec_env("sinew/InvertedPendulum-v0", 2, seed=0)
    venv.reset()
    seen = 0
    for _ in range(200):
        obs, reward, done, infos = venv.step(np.full((2, 1), 3.0))
        for i in np.flatnonzero(done):
            assert "terminal_observation" in infos[i] and "TimeLimit.truncated" in infos[i]
            seen += 1
    assert seen > 0


@pytest.mark.parametrize("mode", ["pd", "trajectory"])
def test_position_action_modes_target_joint_positions(mode):
    env = gym.make("sinew/Hopper-v0", action_mode=mode)
    m = env.unwrapped.model
    np.testing.assert_allclose(env.action_space.low, m.jnt_range[3:, 0].astype(np.float32))
    np.testing.assert_allclose(env.action_space.high, m.jnt_range[3:, 1].astype(np.float32))
    env.reset(seed=0)
    target = np.array([-0.3, -0.3, 0.0], dtype=np.float32)
    for _ in range(40):
        env.step(target)
    q = env.unwrapped.data_qpos[3:]
    assert np.abs(q - target).max() < 0.15  # servo pulls the joints toward the targets under load
    with pytest.raises(ValueError, match="action_mode"):
        gym.make("sinew/Hopper-v0", action_mode="velocity")


def _same(a, b, path="info"):
    """Vector infos equal: the same entries and masks, and equal values wherever the mask says an
    env reports one (SyncVectorEnv leaves None or 0 elsewhere), nested dicts recursively."""
    assert set(a) == set(b), (path, set(a) ^ set(b))
    for k in (k for k in a if not k.startswith("_")):
        x, y, mask = a[k], b[k], np.asarray(b["_" + k])
        assert np.array_equal(np.asarray(a["_" + k]), mask), (path, "_" + k)
        if isinstance(x, dict):
            _same(x, y, f"{path}[{k}]")
            continue
        for i in np.flatnonzero(mask):
            assert np.array_equal(np.asarray(x[i], dtype=float), np.asarray(y[i], dtype=float)), (path, k, i)


@pytest.mark.parametrize("mode", ["SameStep", "Disabled", "NextStep"])
def test_vector_env_equals_sync_vector_env_in_each_autoreset_mode(mode):
    from gymnasium.vector import AutoresetMode, SyncVectorEnv

    n = 4
    ours = gym.make_vec("sinew/Hopper-v0", num_envs=n, vectorization_mode="vector_entry_point", autoreset_mode=mode)
    theirs = SyncVectorEnv([lambda: gym.make("sinew/Hopper-v0") for _ in range(n)], autoreset_mode=AutoresetMode(mode))
    assert ours.metadata["autoreset_mode"] == AutoresetMode(mode)
    o1, i1 = ours.reset(seed=3)
    o2, i2 = theirs.reset(seed=3)
    assert np.array_equal(o1, o2)
    _same(i1, i2)
    rng = np.random.default_rng(0)
    ended = 0
    for t in range(120):
        a = rng.uniform(-1, 1, size=(n, 3))
        r1, r2 = ours.step(a), theirs.step(a)
        for x, y in zip(r1[:4], r2[:4]):
            assert np.array_equal(x, y), t
        _same(r1[4], r2[4])
        done = r1[2] | r1[3]
        ended += done.sum()
        if mode == "Disabled" and done.any():
            with pytest.raises(ValueError, match="reset them"):
                ours.step(a)
            o1, i1 = ours.reset(options={"reset_mask": done})
            o2, i2 = theirs.reset(options={"reset_mask": done})
            assert np.array_equal(o1, o2)
            _same(i1, i2)
    assert ended >= 4, "episodes ended, so the autoreset path ran"


def test_reset_mask_is_checked_as_sync_vector_env_checks_it():
    env = gym.make_vec("sinew/Hopper-v0", num_envs=2, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    with pytest.raises(TypeError):
        env.reset(options={"reset_mask": [True, False]})
    with pytest.raises(ValueError):
        env.reset(options={"reset_mask": np.zeros(2, dtype=bool)})
    with pytest.raises(ValueError, match="autoreset_mode"):
        gym.make_vec("sinew/Hopper-v0", num_envs=2, vectorization_mode="vector_entry_point", autoreset_mode="sometimes")


def test_mujoco_env_parity_attributes_and_keywords():
    env = gym.make("sinew/Hopper-v0", frame_skip=2, xml_file="hopper.xml").unwrapped
    ref = gym.make("Hopper-v5", frame_skip=2).unwrapped
    assert env.frame_skip == 2 and env.dt == pytest.approx(ref.dt)
    assert env._forward_reward_weight == ref._forward_reward_weight
    assert env._healthy_z_range == ref._healthy_z_range and env._reset_noise_scale == ref._reset_noise_scale
    env.reset(seed=1)
    ref.reset(seed=1)
    assert np.array_equal(env.init_qpos, ref.init_qpos) and np.array_equal(env.init_qvel, ref.init_qvel)
    assert np.array_equal(env.state_vector(), ref.state_vector())
    env.set_state(ref.data.qpos, ref.data.qvel)
    for name in ("torso", "foot"):
        assert np.allclose(env.get_body_com(name), ref.get_body_com(name), atol=1e-12)
    assert np.allclose(env.data.xpos, ref.data.xpos, atol=1e-12)
    assert env.data.time == 0
    env.do_simulation(np.zeros(3), 5)
    assert env.data.time == pytest.approx(5 * env.model.timestep)
    with pytest.raises(ValueError, match="mismatch"):
        env.do_simulation(np.zeros(4), 1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'frameskip'"):
        gym.make("sinew/Hopper-v0", frameskip=1)
    with pytest.raises(ValueError, match="frame_skip"):
        gym.make("sinew/Hopper-v0", frame_skip=0)


@pytest.mark.parametrize("mode", ["NextStep", "SameStep"])
def test_termination_on_the_time_limits_step_reports_both_as_time_limit_does(mode):
    from gymnasium.vector import AutoresetMode, SyncVectorEnv

    # the step at which seed 5's pendulum falls with a steady push
    env = gym.make("sinew/InvertedPendulum-v0")
    env.reset(seed=5)
    fall = next(t for t in range(1, 1000) if env.step(np.array([0.5]))[2])
    ours = gym.make_vec("sinew/InvertedPendulum-v0", num_envs=2, vectorization_mode="vector_entry_point",
                        autoreset_mode=mode, max_episode_steps=fall)
    theirs = SyncVectorEnv([lambda: gym.make("sinew/InvertedPendulum-v0", max_episode_steps=fall) for _ in range(2)],
                           autoreset_mode=AutoresetMode(mode))
    ours.reset(seed=5)
    theirs.reset(seed=5)
    for _ in range(fall):
        r1, r2 = ours.step(np.full((2, 1), 0.5)), theirs.step(np.full((2, 1), 0.5))
        for x, y in zip(r1[:4], r2[:4]):
            assert np.array_equal(x, y)
    assert r1[2][0] and r1[3][0], "terminated and truncated together, as gymnasium's TimeLimit reports them"


def test_batch_worlds_with_lent_scratch_step_as_sims_with_their_own():
    """A batch lends each world its threads' scratch (kinematics, ABA, K, the LCP's buffers), so
    worlds with different contacts take turns in the same buffers: each still steps bit for bit as
    a Sim with scratch of its own does, touch sensors read between steps included."""
    site = '<site name="s" type="box" size=".11 .11 .02" pos="0 0 -.1"/>'
    boxes = "".join(f'<body pos="{0.05 * i} 0 {0.2 + 0.25 * i}"><freejoint/><geom type="box" size=".1 .1 .1"/>'
                    f'{site if i == 0 else ""}</body>' for i in range(3))
    xml = (f'<mujoco><worldbody><geom type="plane" size="5 5 .1"/>{boxes}</worldbody>'
           '<sensor><touch site="s"/></sensor></mujoco>')
    m = sinew.Model.from_mjcf_string(xml)
    for threads in (1, 2):
        b = sinew.Batch(m, 4, seed=3, num_threads=threads)
        rng = np.random.default_rng(1)
        b.qpos[:, 2::7] += rng.uniform(-0.05, 0.3, (4, 3))
        b.qvel[:] = rng.uniform(-1, 1, b.qvel.shape)
        b.forward_kinematics()
        sims = []
        for i in range(4):
            s = sinew.Sim(m)
            s.set_state(b.get_state(i, full=True))
            sims.append(s)
        for _ in range(150):
            b.step(2)
            touch = b.sensordata
            for i, s in enumerate(sims):
                s.step(2)
                np.testing.assert_array_equal(b.qpos[i], s.qpos)
                np.testing.assert_array_equal(touch[i], s.sensordata)
        assert touch[:, 0].max() > 0
