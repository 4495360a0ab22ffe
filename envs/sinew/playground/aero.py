"""The TetherIA Aero hand's Playground task (``mujoco_playground/_src/manipulation/aero_hand``): spin a
cube about the vertical in a tendon-driven hand without dropping it, written from Playground's
``rotate_z.py`` and ``base.py``, with its domain randomization."""

from __future__ import annotations

import numpy as np

from sinew.playground.leap import LeapCubeRotateZAxis
from sinew.playground.task import uniform_noise

AERO = "mujoco_playground/_src/manipulation/aero_hand/xmls"
JOINTS = tuple(f"right_{f}_{j}" for f in ("index", "middle", "ring", "pinky") for j in ("mcp_flex", "pip", "dip")) + (
    "right_thumb_cmc_abd", "right_thumb_cmc_flex", "right_thumb_mcp", "right_thumb_ip")
TIPS = ("if_tip", "mf_tip", "rf_tip", "pf_tip", "th_tip")
HAND_BODIES = ("palm", *(f"right_{f}_{p}_link" for f in ("index", "middle", "ring", "pinky") for p in ("f", "proximal", "middle", "distal")),
               "right_t_link", "right_thumb_mcp_link", "right_thumb_proximal_link", "right_thumb_distal_link")
#: The tendons' length sensors the state reads, then the thumb's abduction angle's.
TENDONS = ("len_if", "len_mf", "len_rf", "len_pf", "len_th1", "len_th2")
#: Each actuator's length sensor, in the actuators' order (four finger tendons, the thumb's
#: abduction joint, its two tendons).
ACTUATED = ("len_if", "len_mf", "len_rf", "len_pf", "len_th_abd", "len_th1", "len_th2")
#: Reward scales of Playground's ``rotate_z.default_config()`` (its ``energy`` term, weighted 0, is
#: left out: it reads the tendons' joint forces, which sinew does not expose).
ROTATE_SCALES = dict(angvel=1.0, linvel=0.0, pose=0.0, torques=0.0, termination=-100.0, action_rate=-1.0)


class AeroCubeRotateZAxis(LeapCubeRotateZAxis):
    """``AeroCubeRotateZAxis``: the LEAP task's goal with the Aero hand: seven actions (four finger
    tendons, the thumb's abduction and two thumb tendons) move the servo targets from the
    keyframe's by per-actuator scales; the state holds the noisy tendon lengths and thumb
    abduction and the last action; the action rate costs 1 per unit²."""

    xml = f"{AERO}/scene_mjx_cube.xml"
    sensors = ("cube_position", "cube_orientation", "cube_linvel", "cube_angvel", "palm_position",
               *(f"{t}_position" for t in TIPS), *ACTUATED)
    reward_scales = ROTATE_SCALES
    joints, tips, hand_bodies = JOINTS, TIPS, HAND_BODIES
    cube_friction = (0.1, 0.5)

    def __init__(self, action_scale=(0.02, 0.02, 0.02, 0.02, 0.7, 0.003, 0.012), history_len: int = 1,
                 noise_level: float = 1.0, joint_pos_noise: float = 0.05, tendon_length_noise: float = 0.005,
                 reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(ROTATE_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(ROTATE_SCALES)}")
        self.reward_scales = {**ROTATE_SCALES, **(reward_scales or {})}
        self.action_scale, self.history_len = np.asarray(action_scale, dtype=np.float64), int(history_len)
        level = float(noise_level)
        self.noise = np.concatenate([np.full(6, level * float(tendon_length_noise)), [level * float(joint_pos_noise)]])
        self.obs_sizes = (14 * self.history_len, 81)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.history = np.zeros((n, 14 * self.history_len))
        self.default_ctrl = np.asarray(model.keyframe("home")["ctrl"], dtype=np.float64)
        # a reset's hand pose is clamped to the joints' ranges
        self.pose_range = tuple(model.jnt_range[[model.joint_names.index(j) for j in JOINTS]].T)

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The keyframe's controls (the tendons' and the thumb's rest targets)."""
        return np.tile(self.default_ctrl, (len(qpos), 1))

    def motor_targets(self, actions, qpos, ctrl, idx):
        return self.default_ctrl + actions * self.action_scale

    def actuator_force(self, r) -> np.ndarray:
        """The servos' forces: gain · clamped target + bias₁ · length (the file's servos have no
        velocity gain), each actuator's length its tendon's or joint's sensor."""
        length = np.hstack([r.sensor(s) for s in ACTUATED])
        target = np.clip(r.ctrl, self.lowers, self.uppers)
        gain, bias = self.gain[r.rows], self.bias[r.rows]
        return np.clip(gain * target + bias[..., 0] + bias[..., 1] * length, *self.forces)

    def observe(self, r, idx: np.ndarray, rngs: list):
        readings = np.hstack([r.sensor(s) for s in (*TENDONS, "len_th_abd")])
        state = np.hstack([readings + uniform_noise(rngs, 7, 1.0) * self.noise, self.last_act[idx]])
        self.history[idx] = np.hstack([state, self.history[idx][:, :-14]])
        tips = np.hstack([r.sensor(f"{t}_position") for t in self.tips])
        priv = np.hstack([state, r.qpos[:, self.q_ids], r.qvel[:, self.v_ids], self.actuator_force(r), tips,
                          r.sensor("palm_position") - r.sensor("cube_position"), r.sensor("cube_orientation"),
                          r.sensor("cube_angvel"), r.sensor("cube_linvel")])
        return self.history[idx].astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        done = r.sensor("cube_position")[:, 2] < -0.05
        terms = {
            "angvel": r.sensor("cube_angvel")[:, 2],
            "linvel": np.sum(np.abs(r.sensor("cube_linvel")), axis=1),
            "termination": done.astype(np.float64),
            "action_rate": np.sum((actions - self.last_act[idx]) ** 2, axis=1),
            "pose": np.sum((r.qpos[:, self.q_ids] - self.default_pose) ** 2, axis=1),
            "torques": np.sum(self.actuator_force(r) ** 2, axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = sum(terms.values()) * self.dt
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        return state, priv, reward, done, terms


TASKS = {"AeroCubeRotateZAxis": AeroCubeRotateZAxis}
