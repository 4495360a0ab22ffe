"""Franka Emika Panda's Playground tasks (``mujoco_playground/_src/manipulation/franka_emika_panda``):
bring a cube to a target position (and orientation), pull a cabinet's handle open, written from
Playground's ``pick.py``, ``open_cabinet.py`` and ``panda.py`` (no domain randomization:
Playground has none for these tasks)."""

from __future__ import annotations

import numpy as np

from sinew._core import Model
from sinew.playground import panda_kinematics as kinematics
from sinew.playground.task import Task, site_rot, site_world

PANDA = "mujoco_playground/_src/manipulation/franka_emika_panda/xmls"
ARM = tuple(f"joint{i}" for i in range(1, 8))
FINGERS = ("finger_joint1", "finger_joint2")
#: The geoms whose touching the floor costs the ``no_floor_collision`` reward.
HAND = ("left_finger_pad", "right_finger_pad", "hand_capsule")
#: Reward scales of Playground's ``pick.default_config()`` and ``open_cabinet.default_config()``.
PICK_SCALES = dict(gripper_box=4.0, box_target=8.0, no_floor_collision=0.25, robot_target_qpos=0.3)
CABINET_SCALES = dict(gripper_box=4.0, box_target=8.0, no_barrier_collision=0.25, robot_target_qpos=0.3)
#: The contacts Playground's cabinet env enables by raising the hand capsule's conaffinity to 3:
#: the capsule against the handle, the shelf and the barrier (contype 2).
HAND_PAIRS = "<contact>" + "".join(f'<pair geom1="hand_capsule" geom2="{g}"/>' for g in ("handle", "shelf", "barrier")) + "</contact>"


def quat_to_mat(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of unit quaternions (k, 4: w, x, y, z)."""
    w, x, y, z = q.T
    return np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                     2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                     2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1).reshape(-1, 3, 3)


class PandaPickCube(Task):
    """``PandaPickCube``: bring the cube (placed at random within ±0.2 m) to a target 0.2–0.4 m
    above a random point; actions move the servo targets by ``action_scale`` · a from the last
    ones; the reward (not scaled by ``ctrl_dt``) pays for the gripper near the cube, the cube near
    the target once the gripper has reached it, no hand on the floor and the arm near its home
    pose; the episode ends when the cube leaves the 1 m box about the origin or sinks below the
    floor."""

    xml = f"{PANDA}/mjx_single_cube.xml"
    sim_dt, episode_length, action_scale = 0.005, 150, 0.04
    camera = dict(distance=1.6, elevation=-25.0, azimuth=150.0, trackbodyid=-1, lookat=np.array([0.45, 0.0, 0.2]))
    #: The file has no camera: pixels come from the free camera.
    pixels_camera = -1
    #: The contact sensors of the hand the ``keep_off`` term reads.
    touch = tuple(f"{g}_floor_found" for g in HAND)
    sensors = touch
    obs_sizes = (66, 66)
    reward_scales = PICK_SCALES
    state = ("target_pos", "target_quat", "reached_box")
    #: Whether the target's orientation is drawn (else the identity).
    sample_orientation = False
    #: The object brought to the target, the keyframe episodes start from, and the reward term
    #: for keeping the hand off (the floor, or the cabinet's barrier: ``sensors`` tell).
    obj, keyframe, keep_off = "box", "home", "no_floor_collision"

    def __init__(self, action_scale: float = 0.04, reward_scales: dict | None = None):
        self.kwargs = dict(action_scale=action_scale)
        defaults = type(self).reward_scales
        unknown = set(reward_scales or {}) - set(defaults)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(defaults)}")
        self.reward_scales = {**defaults, **(reward_scales or {})}
        self.action_scale = float(action_scale)

    def setup(self, model, n: int) -> None:
        self.model = model
        key = model.keyframe(self.keyframe)
        self.init_q, self.init_ctrl = np.asarray(key["qpos"], dtype=np.float64), np.asarray(key["ctrl"], dtype=np.float64)
        adr = {name: model.jnt_qposadr[k] for k, name in enumerate(model.joint_names)}
        self.arm = np.array([adr[j] for j in ARM])
        self.robot = np.array([adr[j] for j in ARM + FINGERS])
        self.gripper = model.site_names.index("gripper")
        self.box = model.body_names.index(self.obj)
        target = model.body_names.index("mocap_target")
        self.target_geom = next(g for g in range(model.ngeom) if model.geom_body[g] == target)
        # the body sits unrotated: its geom's place in its frame is the target less its origin
        self.target_origin = model.body_pos[target]
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.target_pos, self.target_quat = np.zeros((n, 3)), np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        self.reached_box = np.zeros(n)
        self.setup_object(model)

    def setup_object(self, model) -> None:
        # the cube's free joint, the file's only one
        self.box_adr = next(a for t, a in zip(model.joint_types, model.jnt_qposadr) if t == "free")
        self.init_box = self.init_q[self.box_adr:self.box_adr + 3].copy()

    def reset(self, idx: np.ndarray, rngs: list):
        """The home keyframe with the cube moved by U(±0.2, ±0.2, 0) and a target drawn."""
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        for j, rng in enumerate(rngs):
            i = idx[j]
            qpos[j, self.box_adr:self.box_adr + 3] = rng.uniform([-0.2, -0.2, 0.0], [0.2, 0.2, 0.0]) + self.init_box
            self.target_pos[i] = rng.uniform([-0.2, -0.2, 0.2], [0.2, 0.2, 0.4]) + self.init_box
            if self.sample_orientation:
                axis = rng.uniform(-1.0, 1.0, 3)
                axis /= np.linalg.norm(axis)
                half = 0.5 * rng.uniform(0.0, np.deg2rad(45))
                self.target_quat[i] = [np.cos(half), *(np.sin(half) * axis)]
        self.reached_box[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def place(self, batch, idx: np.ndarray) -> None:
        """The target's box (Playground's mocap body, without contacts) drawn at the episode's
        target position."""
        batch.set_geom_pos(self.target_geom, self.target_pos[idx] - self.target_origin, idx)

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The keyframe's controls, the arm's moved as its joints were."""
        ctrl = np.tile(self.init_ctrl, (len(qpos), 1))
        ctrl[:, :7] += qpos[:, self.arm] - self.init_q[self.arm]
        return ctrl

    def target_error(self, r, idx: np.ndarray, box: np.ndarray, box_mat: np.ndarray) -> np.ndarray:
        """How far the object is from the target: 0.9 · distance + 0.1 · the rotations' difference."""
        target_mat = quat_to_mat(self.target_quat[idx]).reshape(-1, 9)
        return 0.9 * np.linalg.norm(self.target_pos[idx] - box, axis=1) + 0.1 * np.linalg.norm(target_mat[:, :6] - box_mat[:, :6], axis=1)

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(ctrl + actions * self.action_scale, self.lowers, self.uppers)

    def observe(self, r, idx: np.ndarray, rngs: list):
        gripper, box = site_world(r, self.model, self.gripper), r.xpos(self.box)
        box_mat = r.xmat(self.box).reshape(-1, 9)
        target_mat = quat_to_mat(self.target_quat[idx]).reshape(-1, 9)
        state = np.hstack([r.qpos, r.qvel, gripper, site_rot(r, self.model, self.gripper).reshape(-1, 9)[:, 3:], box_mat[:, 3:],
                           box - gripper, self.target_pos[idx] - box, target_mat[:, :6] - box_mat[:, :6],
                           r.ctrl - r.qpos[:, self.robot[:-1]]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        box, gripper = r.xpos(self.box), site_world(r, self.model, self.gripper)
        error = self.target_error(r, idx, box, r.xmat(self.box).reshape(-1, 9))
        reach = np.linalg.norm(box - gripper, axis=1)
        self.reached_box[idx] = np.maximum(self.reached_box[idx], reach < 0.012)
        touching = np.any([r.sensor(s)[:, 0] > 0 for s in self.touch], axis=0)
        terms = {
            "gripper_box": 1 - np.tanh(5 * reach),
            "box_target": (1 - np.tanh(5 * error)) * self.reached_box[idx],
            self.keep_off: 1.0 - touching,
            "robot_target_qpos": 1 - np.tanh(np.linalg.norm(r.qpos[:, self.arm] - self.init_q[self.arm], axis=1)),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()), -1e4, 1e4)
        done = np.any(np.abs(box) > 1.0, axis=1) | (box[:, 2] < 0.0)
        state, priv = self.observe(r, idx, rngs)
        return state, priv, reward, done, terms


class PandaPickCubeOrientation(PandaPickCube):
    """``PandaPickCubeOrientation``: the same with the target turned by up to 45° about a random
    axis."""

    sample_orientation = True


class PandaOpenCabinet(PandaPickCube):
    """``PandaOpenCabinet``: pull the cabinet's handle (a slide joint) to a target 0.2 ± 0.1 m
    towards the robot, from the upright pose with the arm's joints moved by up to 30° (60° for two
    of them, one way); the hand capsule touches the handle, shelf and barrier (Playground raises
    its conaffinity), and touching the barrier costs ``no_barrier_collision``."""

    xml = f"{PANDA}/mjx_cabinet.xml"
    sensors = touch = tuple(f"barrier_{g}_found" for g in HAND)
    obs_sizes = (55, 55)
    reward_scales = CABINET_SCALES
    state = ("target_pos", "reached_box")
    pixels_camera = "side"
    obj, keyframe, keep_off = "handle", "upright", "no_barrier_collision"

    def load(self, path: str):
        with open(path) as f:
            xml = f.read()
        at = xml.rindex("</mujoco>")
        return Model.from_mjcf_string(xml[:at] + HAND_PAIRS + xml[at:], path)

    def setup_object(self, model) -> None:
        """Nothing: the handle slides on its joint (no free joint to place)."""

    def reset(self, idx: np.ndarray, rngs: list):
        """The upright keyframe, the arm's joints moved by U(−30°, 30°) (the fourth by U(−60°, 0),
        the sixth by U(0, 60°)); a target x of 0.3 ± 0.1 m."""
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        eps = np.deg2rad(30)
        lo, hi = np.array([-eps, -eps, -eps, -2 * eps, -eps, 0, -eps]), np.array([eps, eps, eps, 0, eps, 2 * eps, eps])
        for j, rng in enumerate(rngs):
            self.target_pos[idx[j]] = [0.3 + rng.uniform(-0.1, 0.1), 0.0, 0.5]
            qpos[j, self.arm] += rng.uniform(lo, hi)
        self.reached_box[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def target_error(self, r, idx: np.ndarray, box: np.ndarray, box_mat: np.ndarray) -> np.ndarray:
        return np.linalg.norm(self.target_pos[idx] - box, axis=1)


TASKS = {"PandaPickCube": PandaPickCube, "PandaPickCubeOrientation": PandaPickCubeOrientation,
         "PandaOpenCabinet": PandaOpenCabinet}


#: Reward scales of Playground's ``pick_cartesian.default_config()`` (``no_box_collision`` is
#: reported, not paid: Playground adds it to its terms after summing them).
CARTESIAN_SCALES = dict(gripper_box=4.0, box_target=8.0, no_floor_collision=0.25, no_box_collision=0.05, robot_target_qpos=0.0)


class PandaPickCubeCartesian(PandaPickCube):
    """``PandaPickCubeCartesian``: lift the cube (placed on a line in front of the hand) 20 cm, the
    hand moved in the y–z plane by 5 mm per unit action through Playground's analytic inverse
    kinematics (the third action closes the gripper below zero, else opens it, 2 cm a step); the
    reward is the progress of a dense reward plus bonuses for lifting (0.5) and success (2, which
    ends the episode); one episode in twenty starts from the file's "picked" keyframe."""

    xml = f"{PANDA}/mjx_single_cube_camera.xml"
    sim_dt, ctrl_dt, episode_length, action_scale, action_size = 0.005, 0.05, 200, 0.005, 3
    sensors = (*PandaPickCube.touch, "box_hand_found")
    obs_sizes = (70, 70)
    reward_scales = CARTESIAN_SCALES
    pixels_camera = "front"
    keyframe = "low_home"
    state = ("target_pos", "target_quat", "reached_box", "prev_reward", "current_pos", "prev_action", "steps", "start_ctrl")

    def __init__(self, action_scale: float = 0.005, box_init_range: float = 0.05, success_threshold: float = 0.05,
                 guide_sample_prob: float = 0.05, action_rate: float = -0.0005, no_soln_reward: float = -0.01,
                 lifted_reward: float = 0.5, success_reward: float = 2.0, reward_scales: dict | None = None):
        super().__init__(action_scale, reward_scales)
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        self.box_range, self.threshold, self.guide = float(box_init_range), float(success_threshold), float(guide_sample_prob)
        self.action_rate, self.no_soln_reward = float(action_rate), float(no_soln_reward)
        self.lifted_reward, self.success_reward = float(lifted_reward), float(success_reward)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        picked = model.keyframe("picked")
        self.guide_q, self.guide_ctrl = np.asarray(picked["qpos"], dtype=np.float64), np.asarray(picked["ctrl"], dtype=np.float64)
        self.start_tip = kinematics.forward(self.init_ctrl[None, :7])[0]
        self.prev_reward, self.current_pos = np.zeros(n), np.tile(self.start_tip[:3, 3], (n, 1))
        self.prev_action, self.steps, self.no_soln = np.zeros((n, 3)), np.zeros(n, dtype=np.int64), np.zeros(n)
        self.start_ctrl = np.tile(self.init_ctrl, (n, 1))

    def reset(self, idx: np.ndarray, rngs: list):
        """The cube at y ~ U(±0.05) on the line 3 cm short of the hand's x, its centre in the
        floor's plane (as Playground places it), the target 20 cm above the line's middle; with
        probability 0.05 the file's "picked" keyframe instead (Playground swaps it in at the
        episode's first step)."""
        k = len(idx)
        x_plane = self.start_tip[0, 3] - 0.03
        qpos = np.tile(self.init_q, (k, 1))
        for j, rng in enumerate(rngs):
            i = idx[j]
            qpos[j, self.box_adr:self.box_adr + 3] = [x_plane, rng.uniform(-self.box_range, self.box_range), 0.0]
            self.target_pos[i] = [x_plane, 0.0, 0.20]
            guided = rng.random() < self.guide
            if guided:
                qpos[j] = self.guide_q
            self.start_ctrl[i] = self.guide_ctrl if guided else self.init_ctrl
        self.current_pos[idx] = self.start_tip[:3, 3]
        for a in (self.reached_box, self.prev_reward, self.prev_action, self.steps, self.no_soln):
            a[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The keyframe's controls (the "picked" one's for a guided episode)."""
        return self.start_ctrl[idx]

    def motor_targets(self, actions, qpos, ctrl, idx):
        """Playground's ``_move_tip``: the tip moved by (0, a₀, a₁) · scale within its box, the arm's
        targets from the inverse kinematics (kept where the pose has none), the gripper's target
        2 cm more closed (a₂ < 0) or open."""
        tip = self.current_pos[idx] + np.hstack([np.zeros((len(idx), 1)), actions[:, :2]]) * self.action_scale
        tip = np.clip(tip, [0.25, -0.32, 0.02], [0.77, 0.32, 0.5])
        pose = np.tile(self.start_tip, (len(idx), 1, 1))
        pose[:, :3, 3] = tip
        q = kinematics.inverse(pose, ctrl[:, 6], ctrl[:, :7])
        none = np.isnan(q).any(axis=1)
        q[none] = ctrl[none, :7]
        self.current_pos[idx] = np.where(none[:, None], self.current_pos[idx], tip)
        self.no_soln[idx] = none
        new = ctrl.copy()
        new[:, :7] = q
        new[:, 7] += np.where(actions[:, 2] < 0, -0.02, 0.02)
        return np.clip(new, self.lowers, self.uppers)

    def observe(self, r, idx: np.ndarray, rngs: list):
        state, _ = super().observe(r, idx, rngs)
        state = np.hstack([state, self.no_soln[idx, None], self.prev_action[idx]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        fresh = self.steps[idx] == 0
        box = r.xpos(self.box)
        _, _, dense, _, terms = super().after_step(r, actions, idx, rngs)
        terms = dict(terms)
        terms["no_box_collision"] = self.reward_scales["no_box_collision"] * (r.sensor("box_hand_found")[:, 0] <= 0)
        total = dense + self.action_rate * np.linalg.norm(actions - self.prev_action[idx], axis=1)
        total += self.no_soln_reward * self.no_soln[idx] + self.lifted_reward * (box[:, 2] > 0.05)
        success = np.linalg.norm(box - self.target_pos[idx], axis=1) < self.threshold
        total += self.success_reward * success
        # the progress of the total, never negative, nothing on an episode's first step
        reward = np.where(fresh, 0.0, np.maximum(total - self.prev_reward[idx], 0.0))
        self.prev_reward[idx] = np.maximum(total, self.prev_reward[idx])
        self.prev_action[idx] = actions
        done = np.any(np.abs(box) > 1.0, axis=1) | (box[:, 2] < 0.0) | success
        self.steps[idx] += 1
        self.steps[idx] = np.where(done | (self.steps[idx] >= self.episode_length), 0, self.steps[idx])
        state, priv = self.observe(r, idx, rngs)
        return state, priv, reward, done, terms


TASKS["PandaPickCubeCartesian"] = PandaPickCubeCartesian
