"""The Panda arm with a Robotiq gripper's Playground task
(``mujoco_playground/_src/manipulation/franka_emika_panda_robotiq``): push a box to a target pose
by joint torques, through delayed actions and observations, written from Playground's
``push_cube.py`` and ``panda_robotiq.py`` (no domain randomization: Playground has none)."""

from __future__ import annotations

import numpy as np

from sinew.playground.aloha import tolerance
from sinew.playground.leap import quat_mul
from sinew.playground.panda import quat_to_mat
from sinew.playground.task import Task, draws, site_rot, site_world

ROBOTIQ = "mujoco_playground/_src/manipulation/franka_emika_panda_robotiq/xmls"
GRIPPER_GEOMS = ("left_coupler_col_1", "left_coupler_col_2", "left_follower_pad2", "right_coupler_col_1", "right_coupler_col_2",
                 "right_follower_pad2")
HAND = ("left_finger_pad", "right_finger_pad", "hand_capsule")
GEAR = np.array([150.0, 150.0, 150.0, 150.0, 20.0, 20.0, 20.0])
#: The arm's joint and velocity ranges Playground's env sets out (``jnt_range``, ``jnt_vel_range``).
JNT_RANGE = np.array([[-2.8973, 2.8973], [-1.7628, 1.7628], [-2.8973, 2.8973], [-3.0718, -0.0698], [-2.8973, 2.8973],
                      [-0.0175, 3.7525], [-2.8973, 2.8973]])
JNT_VEL_RANGE = np.array([[-2.175, 2.175]] * 4 + [[-2.61, 2.61]] * 3)
WORKSPACE_MIN, WORKSPACE_MAX = np.array([0.3, -0.5, 0.0]), np.array([0.75, 0.7, 0.5])
OBJ_SAMPLE_MIN, OBJ_SAMPLE_MAX = np.array([0.4, -0.2, -0.005]), np.array([0.65, 0.2, 0.04])
#: Reward scales of Playground's ``push_cube.default_config()``.
PUSH_SCALES = dict(gripper_box=2.0, box_target=8.0, box_orientation=6.0, gripper_collision_side=1.0, robot_target_qpos=0.75,
                   joint_vel=1.0, joint_vel_limit=3.0, total_command=-0.1, action_rate=-0.1)
#: The curriculum of target distances and turns (degrees) a success steps through.
POS_CURRICULUM, ANGLE_CURRICULUM = np.array([0.05, 0.05, 0.1, 0.2, 0.2]), np.array([45.0, 45.0, 90.0, 135.0, 180.0])


def reciprocal(x: np.ndarray, upper: float, margin: float) -> np.ndarray:
    """``reward.tolerance(x, (0, upper), margin, sigmoid="reciprocal")``."""
    d = np.maximum(x - upper, 0.0) / margin
    return np.where(x <= upper, 1.0, 1.0 / (1.0 + 9.0 * d))


def axis_angle_quat(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    return np.hstack([np.cos(angle / 2)[:, None], np.sin(angle / 2)[:, None] * axis])


def rand_dir(u: np.ndarray) -> np.ndarray:
    """``get_rand_dir``: a direction from normally drawn spherical angles (θ ~ 2π N, φ ~ π N), the
    two normals by Box–Muller from the uniforms ``u`` (worlds, 2) in [0, 1)."""
    radius, turn = np.sqrt(-2.0 * np.log1p(-u[:, 0])), 2.0 * np.pi * u[:, 1]
    theta, phi = radius * np.cos(turn) * 2 * np.pi, radius * np.sin(turn) * np.pi
    return np.stack([np.sin(phi) * np.cos(theta), np.sin(phi) * np.sin(theta), np.cos(phi)], axis=1)


#: Uniforms a physics step draws per world: the observation's 11 (``single_obs``), then the
#: observation's and the next action's delays.
OBS_DRAWS, STEP_DRAWS = 11, 13


class PandaRobotiqPushCube(Task):
    """``PandaRobotiqPushCube``: push the box (placed and turned at random) to a target pose nearby
    with the closed gripper, by the arm's seven joint torques; each action is held for four
    physics steps of 5 ms, and acts one or two of them late; each observation is 6–11 physics
    steps old and noisy; a success (within 3 cm and 10° for 30 steps) pays 500 and moves the
    target farther by a curriculum; the episode ends when the box or hand leaves the workspace, the
    hand touches the wall or floor, or a joint nears its limit (−50)."""

    xml = f"{ROBOTIQ}/scene_panda_robotiq_cube.xml"
    sim_dt = ctrl_dt = 0.005
    action_repeat, episode_length, action_size = 4, 750, 7
    camera = dict(distance=1.6, elevation=-30.0, azimuth=-40.0, trackbodyid=-1, lookat=np.array([0.5, 0.0, 0.1]))
    pixels_camera = -1
    sensors = (*(f"{g}_box_normal" for g in GRIPPER_GEOMS), *(f"wall_{g}_found" for g in HAND), *(f"floor_{g}_found" for g in HAND))
    obs_sizes = (48, 48)
    reward_scales = PUSH_SCALES
    state = ("target_pos", "target_quat", "last_action", "action_history", "obs_history", "success_step_count", "curriculum_id",
             "delay")

    def __init__(self, action_scale: float = 0.1, action_delay=(1, 3), obs_delay=(6, 12), obj_pos_noise: float = 0.015,
                 obj_angle_noise: float = 7.5, robot_qpos_noise: float = 0.1, robot_qvel_noise: float = 0.1, eef_pos_noise: float = 0.02,
                 eef_angle_noise: float = 5.0, termination_reward: float = -50.0, success_reward: float = 500.0,
                 success_wait_reward: float = 3.0, success_step_count: int = 30, reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(PUSH_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(PUSH_SCALES)}")
        self.reward_scales = {**PUSH_SCALES, **(reward_scales or {})}
        self.action_scale = float(action_scale)
        self.action_delay, self.obs_delay = tuple(map(int, action_delay)), tuple(map(int, obs_delay))
        self.noise = dict(obj_pos=float(obj_pos_noise), obj_angle=np.deg2rad(float(obj_angle_noise)), qpos=float(robot_qpos_noise),
                          qvel=float(robot_qvel_noise), eef_pos=float(eef_pos_noise), eef_angle=np.deg2rad(float(eef_angle_noise)))
        self.termination_reward, self.success_reward = float(termination_reward), float(success_reward)
        self.success_wait_reward, self.success_steps = float(success_wait_reward), int(success_step_count)

    def setup(self, model, n: int) -> None:
        self.model = model
        key = model.keyframe("home")
        self.init_q, self.init_ctrl = np.asarray(key["qpos"], dtype=np.float64), np.asarray(key["ctrl"], dtype=np.float64)
        adr = {name: model.jnt_qposadr[k] for k, name in enumerate(model.joint_names)}
        self.arm = np.array([adr[f"joint{i}"] for i in range(1, 8)])
        self.box_adr = adr["box_joint"]
        self.init_box = self.init_q[self.box_adr:self.box_adr + 3].copy()
        self.box = model.body_names.index("box")
        self.gripper = model.site_names.index("gripper")
        target = model.body_names.index("mocap_target")
        self.target_geom = next(g for g in range(model.ngeom) if model.geom_body[g] == target)
        self.target_origin = model.body_pos[target]
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.torque_limit = 8.0 / GEAR
        self.target_pos, self.target_quat = np.zeros((n, 3)), np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        self.last_action, self.action_history = np.zeros((n, 7)), np.zeros((n, 35))
        self.obs_history = np.zeros((n, 30 * 48))
        self.success_step_count, self.curriculum_id = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
        #: How many physics steps late each world's next action acts (drawn after each step).
        self.delay = np.ones(n, dtype=np.int64)

    def sample_pos(self, rng, offset: float) -> np.ndarray:
        """``_get_rand_target_pos``: within (±0.4 offset, ±offset, ±0.005) of the box's home spot,
        clipped to the sampling box."""
        lo = np.array([-offset * 0.4, -offset, -0.005]) + self.init_box
        hi = np.array([offset * 0.4, offset, 0.005]) + self.init_box
        return np.clip(rng.uniform(lo, hi), OBJ_SAMPLE_MIN, OBJ_SAMPLE_MAX)

    @staticmethod
    def sample_turn(rng, degrees: float) -> np.ndarray:
        """A turn about z by U(0, degrees)."""
        half = 0.5 * rng.uniform(0.0, np.deg2rad(degrees))
        return np.array([np.cos(half), 0.0, 0.0, np.sin(half)])

    def reset(self, idx: np.ndarray, rngs: list):
        """The box placed within 0.15 m and turned at random, a target within 0.05 m and 45° of it,
        the arm's joints moved by 0.3 · U(20–30% of their ranges)."""
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        pct = np.array([0.2, 0.2, 0.2, 0.2, 0.3, 0.3, 0.3])
        for j, rng in enumerate(rngs):
            i = idx[j]
            box = self.sample_pos(rng, 0.15)
            box[2] = self.init_box[2]
            box_quat = self.sample_turn(rng, 360.0)
            self.target_pos[i] = self.sample_pos(rng, 0.05)
            self.target_quat[i] = quat_mul(box_quat[None], self.sample_turn(rng, 45.0)[None])[0]
            qpos[j, self.box_adr:self.box_adr + 7] = [*box, *box_quat]
            qpos[j, self.arm] += 0.3 * rng.uniform(JNT_RANGE[:, 0] * pct, JNT_RANGE[:, 1] * pct)
            self.delay[i] = rng.integers(*self.action_delay)
        for a in (self.last_action, self.action_history, self.obs_history, self.success_step_count, self.curriculum_id):
            a[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def place(self, batch, idx: np.ndarray) -> None:
        """The target's box (Playground's mocap body) drawn at the target's position, unturned."""
        batch.set_geom_pos(self.target_geom, self.target_pos[idx] - self.target_origin, idx)

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The keyframe's controls: no torque, the gripper closed."""
        return np.tile(self.init_ctrl, (len(qpos), 1))

    def motor_targets(self, actions, qpos, ctrl, idx):
        """The torques of an action one or two physics steps old (its history holds the last
        five), scaled and limited to 8 N·m, and the gripper held closed."""
        self.action_history[idx] = np.hstack([actions, self.action_history[idx][:, :-7]])
        delayed = self.delayed(idx)
        torque = np.clip(delayed * self.action_scale, -self.torque_limit, self.torque_limit)
        return np.clip(np.hstack([torque, np.full((len(idx), 1), 0.82)]), self.lowers, self.uppers)

    def delayed(self, idx: np.ndarray) -> np.ndarray:
        """The action each world's servos act on: ``delay`` entries back in its history."""
        return self.action_history[idx].reshape(len(idx), 5, 7)[np.arange(len(idx)), self.delay[idx]]

    def single_obs(self, r, idx: np.ndarray, u: np.ndarray) -> np.ndarray:
        """``_get_single_obs``: the target's pose, the last action, the arm's joints and velocities
        and the hand's pose (each shifted by one draw U(0, scale): Playground draws a scalar per
        vector, and the hand's turn angle from the joints' key), the box's pose (turned by U(0,
        7.5°) about a random direction, moved by U(±0.015) per axis), from each world's
        ``OBS_DRAWS`` uniforms ``u``."""
        k = len(idx)
        dirs = np.hstack([rand_dir(u[:, 7:9]), rand_dir(u[:, 9:11])])
        nz = self.noise
        noisy_box_mat = quat_to_mat(axis_angle_quat(dirs[:, :3], u[:, 0] * nz["obj_angle"])) @ r.xmat(self.box)
        box_pos = r.xpos(self.box) + (2 * u[:, 1:4] - 1) * nz["obj_pos"]
        q = r.qpos[:, self.arm] + u[:, 4:5] * nz["qpos"]
        qd = r.qvel[:, :7] + u[:, 5:6] * nz["qvel"]
        grip = site_world(r, self.model, self.gripper) + u[:, 6:7] * nz["eef_pos"]
        hand_turn = quat_to_mat(axis_angle_quat(dirs[:, 3:], u[:, 4] * nz["eef_angle"]))
        grip_mat = hand_turn @ site_rot(r, self.model, self.gripper)
        target_mat = quat_to_mat(self.target_quat[idx]).reshape(k, 9)
        return np.hstack([self.target_pos[idx], target_mat[:, 3:], self.last_action[idx], q, qd, grip,
                          grip_mat.reshape(k, 9)[:, 3:], noisy_box_mat.reshape(k, 9)[:, 3:], box_pos])

    def observe(self, r, idx: np.ndarray, rngs: list):
        """At reset, the readings themselves (Playground starts the history empty)."""
        state = self.single_obs(r, idx, draws(rngs, OBS_DRAWS)).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        k = len(idx)
        delayed = self.delayed(idx)
        box, grip = r.xpos(self.box), site_world(r, self.model, self.gripper)
        target = self.target_pos[idx]
        away = box - target
        dist = np.linalg.norm(away, axis=1, keepdims=True)
        side = np.where(dist > 1e-3, away / np.maximum(dist, 1e-12) * 0.1, 0.0)
        target_mat = quat_to_mat(self.target_quat[idx])
        relative = r.xmat(self.box) @ np.transpose(target_mat, (0, 2, 1))
        ori_err = np.arccos(np.clip((np.trace(relative, axis1=1, axis2=2) - 1) / 2, -1.0, 1.0))
        normal = np.mean([r.sensor(f"{g}_box_normal") for g in GRIPPER_GEOMS], axis=0)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True) + 1e-6
        q, qd = r.qpos[:, self.arm], r.qvel[:, self.arm]
        near_vel_limit = np.any((qd > 0.9 * JNT_VEL_RANGE[:, 1]) | (qd < 0.9 * JNT_VEL_RANGE[:, 0]), axis=1)
        terms = {
            "box_target": reciprocal(np.linalg.norm(box[:, :2] - target[:, :2], axis=1), 0.005, 0.4),
            "box_orientation": reciprocal(ori_err, 0.2, np.pi),
            "gripper_box": tolerance(np.linalg.norm(box + side - grip, axis=1), 0.0, 0.1, 1.0, "linear"),
            "gripper_collision_side": np.linalg.norm(np.cross([0.0, 0.0, 1.0], normal), axis=1),
            "robot_target_qpos": tolerance(np.linalg.norm(q - self.init_q[self.arm], axis=1), 0.0, 0.5, 4.5, "linear"),
            "joint_vel": reciprocal(np.linalg.norm(r.qvel[:, :7], axis=1), 0.5, 2.0),
            "joint_vel_limit": 1.0 - near_vel_limit,
            "total_command": np.linalg.norm(actions, axis=1),
            "action_rate": np.linalg.norm(actions - self.last_action[idx], axis=1),
        }
        terms = {key: v * self.reward_scales[key] for key, v in terms.items()}
        reward = np.clip(sum(terms.values()), -1e4, 1e4) / sum(self.reward_scales.values())
        touching = np.any([r.sensor(f"{w}_{g}_found")[:, 0] > 0 for w in ("wall", "floor") for g in HAND], axis=0)
        done = (box[:, 2] < -0.01) | np.any((box[:, :2] > WORKSPACE_MAX[:2]) | (box[:, :2] < WORKSPACE_MIN[:2]), axis=1)
        done |= (grip[:, 2] > WORKSPACE_MAX[2]) | np.any((grip[:, :2] > WORKSPACE_MAX[:2]) | (grip[:, :2] < WORKSPACE_MIN[:2]), axis=1)
        done |= touching | np.any((q > JNT_RANGE[:, 1] * 0.9) | (q < JNT_RANGE[:, 0] * 0.9), axis=1)
        reward = reward + self.termination_reward * done
        # success: within 3 cm and 10° for 30 steps running
        near = (np.linalg.norm(target - box, axis=1) < 0.03) & (ori_err < np.deg2rad(10))
        success = near & (self.success_step_count[idx] >= self.success_steps)
        self.success_step_count[idx] = np.where(near & ~success, self.success_step_count[idx] + 1, 0)
        reward = (reward + self.success_wait_reward * near + self.success_reward * success) * self.dt
        # a success moves the target on, farther and turned more as the curriculum advances
        self.curriculum_id[idx] += success
        box_mat = r.xmat(self.box)
        for j in np.flatnonzero(success):
            i, rng, level = idx[j], rngs[j], min(self.curriculum_id[idx[j]], len(POS_CURRICULUM) - 1)
            self.target_pos[i] = self.sample_pos(rng, POS_CURRICULUM[level])
            self.target_quat[i] = quat_mul(mat_to_quat(box_mat[j])[None], self.sample_turn(rng, ANGLE_CURRICULUM[level])[None])[0]
        # the observation: one 6–11 physics steps old
        u = draws(rngs, STEP_DRAWS)
        self.obs_history[idx] = np.hstack([self.single_obs(r, idx, u), self.obs_history[idx][:, :-48]])
        late = self.obs_delay[0] + (u[:, 11] * (self.obs_delay[1] - self.obs_delay[0])).astype(np.int64)
        state = self.obs_history[idx].reshape(k, 30, 48)[np.arange(k), late].astype(np.float32)
        self.last_action[idx] = delayed
        self.delay[idx] = self.action_delay[0] + (u[:, 12] * (self.action_delay[1] - self.action_delay[0])).astype(np.int64)
        return state, state.copy(), reward, done, terms


def mat_to_quat(m: np.ndarray) -> np.ndarray:
    """A rotation matrix's unit quaternion (w, x, y, z), w ≥ 0."""
    w = np.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1.0 + m[0, 0] - m[1, 1] - m[2, 2])) / 2, m[2, 1] - m[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - m[0, 0] + m[1, 1] - m[2, 2])) / 2, m[0, 2] - m[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - m[0, 0] - m[1, 1] + m[2, 2])) / 2, m[1, 0] - m[0, 1])
    q = np.array([w, x, y, z])
    return q / np.linalg.norm(q)


TASKS = {"PandaRobotiqPushCube": PandaRobotiqPushCube}
