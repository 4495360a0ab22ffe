"""dm_control's planar manipulator: a four-joint arm with a two-finger hand brings a ball or a
peg to a target, or into a cup or slot, placed anew in each world at each episode."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, remove

ARM_JOINTS = ["arm_root", "arm_shoulder", "arm_elbow", "arm_wrist", "finger", "fingertip", "thumb", "thumbtip"]
TOUCH = ["palm_touch", "finger_touch", "thumb_touch", "fingertip_touch", "thumbtip_touch"]
PROPS = ["ball", "target_ball", "cup", "peg", "target_peg", "slot"]
#: Probabilities of the object starting in the hand, in the target, anywhere.
P_IN_HAND, P_IN_TARGET = 0.1, 0.1
CLOSE = 0.01


def pose_2d(phys, body: str, angle: np.ndarray) -> np.ndarray:
    """dm_control's ``body_2d_pose``: x, z and the quaternion's w and y of a body turned by
    `angle` about +y (every rotation of this domain and stacker's is about ±y)."""
    xz = phys.xpos(body)[:, [0, 2]]
    return np.concatenate([xz, np.cos(angle / 2)[:, None], np.sin(angle / 2)[:, None]], axis=1)


class Arm:
    """The arm's joints as dm_control's manipulator and stacker draw and observe them."""

    def __init__(self, names):
        joint = [names.index("joint", j) for j in ARM_JOINTS]
        self.qpos = [names.jnt_qposadr[j] for j in joint]
        self.qvel = [names.jnt_dofadr[j] for j in joint]
        limited, ranges = np.asarray(names.jnt_limited)[joint], np.asarray(names.jnt_range)[joint]
        self.lo, self.hi = np.where(limited, ranges[:, 0], -np.pi), np.where(limited, ranges[:, 1], np.pi)
        self.finger, self.thumb = (names.jnt_qposadr[names.index("joint", j)] for j in ("finger", "thumb"))

    def draw(self, q: np.ndarray, rng) -> None:
        """A random pose into one world's qpos `q`, the hand symmetric."""
        q[self.qpos] = rng.uniform(self.lo, self.hi)
        q[self.finger] = q[self.thumb]

    def observation(self, phys) -> OrderedDict:
        """arm_pos (each joint's sine and cosine), arm_vel, touch (log(1 + force)) and hand_pos."""
        q, v = phys.position(), phys.velocity()
        pairs = np.stack([np.sin(q[:, self.qpos]), np.cos(q[:, self.qpos])], axis=2).reshape(len(q), -1)
        touch = np.concatenate([phys.sensor(s) for s in TOUCH], axis=1)
        # the hand turns about −y by the sum of the arm's four joint angles
        hand = pose_2d(phys, "hand", -q[:, self.qpos[:4]].sum(axis=1))
        return OrderedDict(arm_pos=pairs, arm_vel=v[:, self.qvel].copy(), touch=np.log1p(touch), hand_pos=hand)


class BringBall(Task):
    """``manipulator-bring_ball``: the arm in a random pose, the target at a random place and
    angle, the ball in the hand, in the target or anywhere (thrown sideways), drawn again until
    nothing overlaps; reward for the ball at the target."""

    xml = "manipulator.xml"
    time_limit = 10
    control_timestep = 0.01
    sensors = tuple(TOUCH)
    use_peg, insert = False, False

    @property
    def target(self):
        return "target_peg" if self.use_peg else "target_ball"

    @property
    def object(self):
        return "peg" if self.use_peg else "ball"

    @property
    def receptacle(self):
        return "slot" if self.use_peg else "cup"

    def model_xml(self):
        """manipulator.xml with only this task's props (dm_control's ``make_model``)."""
        keep = {self.object, self.target} | ({self.receptacle} if self.insert else set())

        def edit(root):
            for prop in set(PROPS) - keep:
                remove(root, "body", prop)
        return self.edited_model(edit)

    def initialize_episode(self, phys, rngs):
        names = phys.names
        arm = Arm(names)
        obj = [names.jnt_qposadr[names.index("joint", f"{self.object}_{d}")] for d in "xzy"]
        obj_vx = names.jnt_dofadr[names.index("joint", f"{self.object}_x")]
        placed = [names.index("body", b) for b in ([self.receptacle] if self.insert else []) + [self.target]]
        qpos, qvel = phys.position().copy(), phys.velocity().copy()
        pos, quat = phys.batch.params("body_pos")[phys.rows], phys.batch.params("body_quat")[phys.rows]
        pending, start = np.arange(len(rngs)), [None] * len(rngs)
        while len(pending):
            for k in pending:
                r = rngs[k]
                arm.draw(qpos[k], r)
                tx, tz = r.uniform(-.4, .4), r.uniform(.1, .4)
                angle = r.uniform(-np.pi / 3, np.pi / 3) if self.insert else r.uniform(-np.pi, np.pi)
                pos[k, placed, 0], pos[k, placed, 2] = tx, tz
                quat[k, placed, 0], quat[k, placed, 2] = np.cos(angle / 2), np.sin(angle / 2)
                kind = r.choice(["in_hand", "in_target", "uniform"], p=[P_IN_HAND, P_IN_TARGET, 1 - P_IN_HAND - P_IN_TARGET])
                if kind == "in_target":
                    start[k] = (tx, tz, angle)
                elif kind == "uniform":
                    start[k] = (r.uniform(-.5, .5), r.uniform(0, .7), r.uniform(0, 2 * np.pi))
                    qvel[k, obj_vx] = r.uniform(-5, 5)
                else:
                    start[k] = None
            phys.set_params("body_pos", pos)
            phys.set_params("body_quat", quat)
            # an object in the hand takes the grasp site's place in the arm's pose
            phys.set_state(qpos, qvel)
            grasp, frame = phys.site_xpos("grasp"), phys.site_xmat("grasp")
            for k in pending:
                if start[k] is None:
                    start[k] = (grasp[k, 0], grasp[k, 2], np.pi - np.arctan2(frame[k, 2, 0], frame[k, 0, 0]))
                qpos[k, obj] = start[k]
            phys.set_state(qpos, qvel)
            pending = pending[phys.penetrations()[pending] > 0]

    def observation(self, phys):
        names = phys.names
        obs = Arm(names).observation(phys)
        obj_v = [names.jnt_dofadr[names.index("joint", f"{self.object}_{d}")] for d in "xzy"]
        w, y = (phys.batch.params("body_quat")[phys.rows, names.index("body", self.target), c] for c in (0, 2))
        obs["object_pos"] = pose_2d(phys, self.object, phys.joint_qpos(f"{self.object}_y"))
        obs["object_vel"] = phys.velocity()[:, obj_v].copy()
        obs["target_pos"] = np.concatenate([phys.xpos(self.target)[:, [0, 2]], w[:, None], y[:, None]], axis=1)
        return obs

    @staticmethod
    def close(phys, a: str, b: str) -> np.ndarray:
        return tolerance(np.linalg.norm(phys.site_xpos(a) - phys.site_xpos(b), axis=1), (0, CLOSE), CLOSE * 2)

    def reward(self, phys):
        if not self.use_peg:
            return self.close(phys, "ball", "target_ball")
        grasping = (self.close(phys, "peg_grasp", "grasp") + self.close(phys, "peg_pinch", "pinch")) / 2
        bringing = (self.close(phys, "peg", "target_peg") + self.close(phys, "target_peg_tip", "peg_tip")) / 2
        return np.maximum(bringing, grasping / 3)


class BringPeg(BringBall):
    """``manipulator-bring_peg``: the peg to its target, grasped on the way."""

    use_peg = True


class InsertBall(BringBall):
    """``manipulator-insert_ball``: the ball into the cup, placed with the target."""

    insert = True


class InsertPeg(BringBall):
    """``manipulator-insert_peg``: the peg into the slot, placed with the target."""

    use_peg, insert = True, True


TASKS = {"bring_ball": BringBall, "bring_peg": BringPeg, "insert_ball": InsertBall, "insert_peg": InsertPeg}
