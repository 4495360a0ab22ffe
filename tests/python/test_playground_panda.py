"""Panda's Playground tasks: the observation Playground's ``pick.py`` computes (against MuJoCo at
the same state), its targets and reward terms, and a grasp that holds (exact contact: the lifted
cube does not slide in the fingers)."""

import gymnasium as gym
import mujoco
import numpy as np

import sinew  # noqa: F401  (registers the envs)
from sinew import Batch, Model
from sinew.playground import assets_dir
from sinew.playground.panda import quat_to_mat

XML = "mujoco_playground/_src/manipulation/franka_emika_panda/xmls/mjx_single_cube.xml"


def test_pick_observes_what_mujoco_reads_and_draws_its_cube_and_target():
    env = gym.make_vec("sinew/playground-PandaPickCubeOrientation-v0", num_envs=32, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    task = core.task
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{XML}")
    d = mujoco.MjData(mj)
    home = mj.keyframe("home")
    box = mj.body("box").id
    offsets = core.batch.qpos[:, 9:12] - home.qpos[9:12]
    assert (np.abs(offsets[:, :2]) <= 0.2).all() and (offsets[:, 2] == 0).all() and offsets[:, :2].std() > 0.05
    lift = task.target_pos - home.qpos[9:12]
    assert ((lift[:, 2] >= 0.2) & (lift[:, 2] <= 0.4)).all()
    np.testing.assert_allclose(core.batch.geom_pos(task.target_geom), task.target_pos)    # drawn there
    angle = 2 * np.arccos(np.clip(task.target_quat[:, 0], -1, 1))
    assert (angle <= np.deg2rad(45) + 1e-9).all() and angle.max() > np.deg2rad(20)
    obs, reward, term, _, info = env.step(np.random.default_rng(0).uniform(-1, 1, (32, 8)))
    for i in (0, 7):
        d.qpos[:], d.qvel[:], d.ctrl[:] = core.batch.qpos[i], core.batch.qvel[i], core.batch.ctrl[i]
        mujoco.mj_forward(mj, d)
        g = mj.site("gripper").id
        target_mat = quat_to_mat(task.target_quat[i:i + 1]).reshape(9)
        expect = np.concatenate([d.qpos, d.qvel, d.site_xpos[g], d.site_xmat[g][3:], d.xmat[box][3:], d.xpos[box] - d.site_xpos[g],
                                 task.target_pos[i] - d.xpos[box], target_mat[:6] - d.xmat[box][:6], d.ctrl - d.qpos[:8]])
        np.testing.assert_allclose(obs[i], expect, atol=2e-5)
        reach = np.linalg.norm(d.xpos[box] - d.site_xpos[g])
        np.testing.assert_allclose(info["gripper_box"][i], 4.0 * (1 - np.tanh(5 * reach)), rtol=1e-9)
        q = d.qpos[:7] - home.qpos[:7]
        np.testing.assert_allclose(info["robot_target_qpos"][i], 0.3 * (1 - np.tanh(np.linalg.norm(q))), rtol=1e-9)
    np.testing.assert_allclose(reward, info["gripper_box"] + info["box_target"] + info["no_floor_collision"]
                               + info["robot_target_qpos"], rtol=1e-12)
    assert (info["box_target"] == 0).all(), "no gripper reached its cube in one step"
    # each action moves the servo targets from the last ones
    lo, hi = mj.actuator_ctrlrange.T
    before = core.batch.ctrl.copy()
    env.step(np.ones((32, 8)))
    np.testing.assert_allclose(core.batch.ctrl, np.clip(before + 0.04, lo, hi))


def test_a_grasped_cube_is_lifted_and_held_without_sliding():
    """From the file's "pickup" keyframe: close the fingers, raise the arm 40 cm, hold 1 s: the
    cube rises with the hand and stays put in the fingers (MuJoCo's soft contacts let it slide
    by about a millimetre over the same second)."""
    model = Model.from_mjcf(f"{assets_dir()}/{XML}").with_options(timestep=0.005)
    b = Batch(model, 1)
    key = model.keyframe("pickup")
    b.reset(qpos=np.asarray(key["qpos"])[None], qvel=np.zeros((1, model.nv)))
    box = model.body_names.index("box")
    ctrl = np.array(key["ctrl"], dtype=float)
    ctrl[7] = 0.0
    b.ctrl[0] = ctrl
    b.step(100)
    ctrl[1] -= 0.4
    ctrl[3] += 0.3
    b.ctrl[0] = ctrl
    b.step(200)
    lifted = b.xpos[0, box].copy()
    assert lifted[2] > 0.4
    b.step(200)
    np.testing.assert_allclose(b.xpos[0, box], lifted, atol=2e-4)


def test_cabinet_starts_from_a_moved_arm_and_lets_the_hand_touch_the_handle_and_barrier():
    """PandaOpenCabinet: the arm's joints moved within Playground's bounds, the servos' targets
    with them; the hand capsule's contacts with the handle, shelf and barrier that Playground's
    env enables (conaffinity 3) are the file's pairs here; the observation is MuJoCo's at the same
    state (with that conaffinity)."""
    env = gym.make_vec("sinew/playground-PandaOpenCabinet-v0", num_envs=32, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    model, task, b = core.model, core.task, core.batch
    eps = np.deg2rad(30)
    moved = b.qpos[:, :7]
    assert (moved >= np.array([-eps, -eps, -eps, -2 * eps, -eps, 0, -eps]) - 1e-12).all()
    assert (moved <= np.array([eps, eps, eps, 0, eps, 2 * eps, eps]) + 1e-12).all() and moved.std() > 0.1
    np.testing.assert_allclose(b.ctrl[:, :7], moved)
    assert ((task.target_pos[:, 0] >= 0.2) & (task.target_pos[:, 0] <= 0.4)).all()
    names = model.geom_names
    pairs = {tuple(sorted((names[g1], names[g2]))) for g1, g2 in model.pair_geoms}
    assert {("hand_capsule", "handle"), ("hand_capsule", "shelf"), ("barrier", "hand_capsule")} <= pairs
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/mujoco_playground/_src/manipulation/franka_emika_panda/xmls/mjx_cabinet.xml")
    mj.geom("hand_capsule").conaffinity = 3
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:], d.ctrl[:] = b.qpos[3], b.qvel[3], b.ctrl[3]
    mujoco.mj_forward(mj, d)
    g, h = mj.site("gripper").id, mj.body("handle").id
    expect = np.concatenate([d.qpos, d.qvel, d.site_xpos[g], d.site_xmat[g][3:], d.xmat[h][3:], d.xpos[h] - d.site_xpos[g],
                             task.target_pos[3] - d.xpos[h], np.eye(3).ravel()[:6] - d.xmat[h][:6], d.ctrl - d.qpos[:8]])
    np.testing.assert_allclose(obs[3], expect, atol=2e-5)


def test_cartesian_pick_moves_the_hand_through_the_inverse_kinematics():
    """PandaPickCubeCartesian: each action moves the tip target by (0, a₀, a₁) · 5 mm and the arm's
    servo targets are the inverse kinematics' solution, which Playground's forward kinematics puts
    back at that tip (to round-off); the third action closes the gripper 2 cm below zero; the cube
    placed with its centre in the floor's plane is eased up onto it, not flung."""
    from sinew.playground import panda_kinematics as kinematics
    env = gym.make_vec("sinew/playground-PandaPickCubeCartesian-v0", num_envs=8, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    task, b = core.task, core.batch
    assert env.single_action_space.shape == (3,) and obs.shape == (8, 70)
    plain = (b.ctrl == task.init_ctrl).all(axis=1)
    assert plain.sum() >= 6, "one episode in twenty starts from the picked keyframe"
    start = task.current_pos.copy()
    np.testing.assert_allclose(kinematics.forward(b.ctrl[plain, :7])[:, :3, 3], start[plain], atol=1e-12)
    gripper = b.ctrl[:, 7].copy()
    a = np.tile([1.0, 0.5, -1.0], (8, 1))
    obs, *_ = env.step(a)
    moved = ~task.no_soln.astype(bool)
    assert moved.all()
    np.testing.assert_allclose(task.current_pos, start + [0.0, 0.005, 0.0025], atol=1e-12)
    np.testing.assert_allclose(kinematics.forward(b.ctrl[:, :7])[:, :3, 3], task.current_pos, atol=1e-9)
    lo = core.model.actuator_ctrlrange[7, 0]
    np.testing.assert_allclose(b.ctrl[:, 7], np.maximum(gripper - 0.02, lo))
    np.testing.assert_array_equal(obs[:, 66], 0.0)                 # a solution was found
    np.testing.assert_allclose(obs[:, 67:70], a, atol=1e-7)         # the action, observed
    for _ in range(20):
        env.step(np.zeros((8, 3)))
    cube = b.qpos[:, task.box_adr:task.box_adr + 3]
    assert (np.abs(cube[plain, 2] - 0.03) < 2e-3).all() and (np.abs(b.qvel[plain, -6:]) < 0.5).all()


def test_robotiq_push_acts_late_observes_late_and_holds_the_gripper_closed():
    """PandaRobotiqPushCube: an action's torques act one or two physics steps late, scaled by 0.1
    and limited to 8 N·m (over the gears), the gripper's target held at 0.82; an observation is
    6–11 physics steps old, so the first env step (four physics steps) observes the empty history;
    at reset the readings themselves: the target's pose and the arm's joints shifted by one draw
    in [0, 0.1)."""
    from sinew.playground.panda_robotiq import GEAR
    env = gym.make_vec("sinew/playground-PandaRobotiqPushCube-v0", num_envs=16, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    task, b = core.task, core.batch
    assert env.single_action_space.shape == (7,) and obs.shape == (16, 48)
    np.testing.assert_allclose(obs[:, :3], task.target_pos, atol=1e-6)
    np.testing.assert_array_equal(obs[:, 9:16], 0.0)
    shift = obs[:, 16:23] - b.qpos[:, :7]
    assert (shift >= -1e-6).all() and (shift < 0.1 + 1e-6).all() and np.allclose(shift, shift[:, :1], atol=1e-6)
    a = np.random.default_rng(0).uniform(-1, 1, (16, 7))
    obs, *_ = env.step(a)
    np.testing.assert_array_equal(obs, 0.0)
    torque = np.clip(a * 0.1, -8.0 / GEAR, 8.0 / GEAR)
    np.testing.assert_allclose(b.ctrl[:, :7], torque)       # the fourth physics step acts on a
    np.testing.assert_allclose(b.ctrl[:, 7], 0.82)
    np.testing.assert_allclose(task.last_action, a)
    for _ in range(3):
        obs, *_ = env.step(a)
    assert (np.abs(obs).sum(axis=1) > 0).all(), "by then the observations are 6–11 steps old readings"


def test_the_inverse_kinematics_inverts_the_forward_kinematics():
    """Playground's analytic Franka IK, on the branch of the arm's current angles, returns the
    angles whose forward kinematics gave the pose (200 poses about the home configuration), and
    NaN for a pose out of reach."""
    from sinew.playground import panda_kinematics as kinematics
    rng = np.random.default_rng(1)
    q = np.array([0.0, 0.3, 0.0, -1.57079, 0.0, 2.0, -0.7853]) + rng.uniform(-0.2, 0.2, (200, 7))
    pose = kinematics.forward(q)
    np.testing.assert_allclose(kinematics.inverse(pose, q[:, 6], q), q, atol=1e-9)
    far = pose[:1].copy()
    far[0, :3, 3] = [2.0, 0.0, 0.5]
    assert np.isnan(kinematics.inverse(far, q[:1, 6], q[:1])).any()
