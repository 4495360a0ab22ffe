"""dm_control's stacker: the manipulator's arm stacks boxes onto a target whose height asks for
a stack."""

from __future__ import annotations

import numpy as np

from sinew.dmc.manipulator import TOUCH, Arm, pose_2d
from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, remove

CLOSE = 0.01


class Stack2(Task):
    """``stacker-stack_2``: the arm in a random pose, the target at a random x and at the height
    of a stack of 1, 3, … boxes, the boxes at random places and angles, drawn again until nothing
    overlaps; reward for a box near the target with the hand away from it."""

    xml = "stacker.xml"
    time_limit = 10
    control_timestep = 0.01
    sensors = tuple(TOUCH)
    n_boxes = 2

    @property
    def boxes(self):
        return [f"box{b}" for b in range(self.n_boxes)]

    def model_xml(self):
        """stacker.xml with ``n_boxes`` boxes (dm_control's ``make_model``)."""
        def edit(root):
            for b in range(self.n_boxes, 4):
                remove(root, "body", f"box{b}")
        return self.edited_model(edit)

    def initialize_episode(self, phys, rngs):
        names = phys.names
        arm = Arm(names)
        box = [[names.jnt_qposadr[names.index("joint", f"{b}_{d}")] for d in "xzy"] for b in self.boxes]
        target, size = names.index("body", "target"), phys.geom_size("target")[0]
        qpos = phys.position().copy()
        pos = phys.batch.params("body_pos")[phys.rows]
        pending = np.arange(len(rngs))
        while len(pending):
            for k in pending:
                r = rngs[k]
                arm.draw(qpos[k], r)
                pos[k, target, 2] = size * (2 * r.integers(self.n_boxes) + 1)
                pos[k, target, 0] = r.uniform(-.37, .37)
                for b in box:
                    qpos[k, b] = r.uniform(.1, .3), r.uniform(0, .7), r.uniform(0, 2 * np.pi)
            phys.set_params("body_pos", pos)
            phys.set_state(qpos)
            pending = pending[phys.penetrations()[pending] > 0]

    def observation(self, phys):
        names = phys.names
        obs = Arm(names).observation(phys)
        box_v = [names.jnt_dofadr[names.index("joint", f"{b}_{d}")] for b in self.boxes for d in "xyz"]
        obs["box_pos"] = np.concatenate([pose_2d(phys, b, phys.joint_qpos(f"{b}_y")) for b in self.boxes], axis=1)
        obs["box_vel"] = phys.velocity()[:, box_v].copy()
        obs["target_pos"] = phys.xpos("target")[:, [0, 2]].copy()
        return obs

    def reward(self, phys):
        size = phys.geom_size("target")[0]
        distance = lambda a, b: np.linalg.norm(phys.site_xpos(a) - phys.site_xpos(b), axis=1)
        nearest = np.min([distance(b, "target") for b in self.boxes], axis=0)
        box_is_close = tolerance(nearest, margin=2 * size)
        hand_is_far = tolerance(distance("grasp", "target"), bounds=(.1, float("inf")), margin=CLOSE)
        return box_is_close * hand_is_far


class Stack4(Stack2):
    """``stacker-stack_4``: four boxes."""

    n_boxes = 4


TASKS = {"stack_2": Stack2, "stack_4": Stack4}
