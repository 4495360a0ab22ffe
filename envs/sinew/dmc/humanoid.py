"""dm_control's humanoids (``humanoid``, 21 joints, and ``humanoid_CMU``, 56): stand, walk at
1 m/s or run at 10 m/s."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import in_frame, randomize_joints, tolerance
from sinew.dmc.task import Task, draw_until_apart


class Stand(Task):
    """``humanoid-stand``: joints drawn as dm_control's ``randomize_limited_and_rotational_joints``
    until no geoms overlap."""

    xml = "humanoid.xml"
    time_limit = 25
    control_timestep = .025
    move_speed = 0.0
    pure_state = False
    torso, upright_axis = "torso", 2
    sensors = ("torso_subtreelinvel",)
    limbs = ("left_hand", "left_foot", "right_hand", "right_foot")

    def initialize_episode(self, phys, rngs):
        draw_until_apart(phys, rngs, lambda q, r: randomize_joints(phys.names, q, r))

    def com_velocity(self, phys):
        return phys.sensor(f"{self.torso}_subtreelinvel")

    def observation(self, phys):
        if self.pure_state:
            return OrderedDict(position=phys.position().copy(), velocity=phys.velocity().copy())
        frame, origin = phys.xmat(self.torso), phys.xpos(self.torso)
        # each limb's position relative to the torso, in the torso's frame
        limbs = [in_frame(phys.xpos(limb) - origin, frame) for limb in self.limbs]
        return OrderedDict(joint_angles=phys.position()[:, 7:].copy(), head_height=phys.xpos("head")[:, 2],
                           extremities=np.concatenate(limbs, axis=1), torso_vertical=frame[:, 2, :].copy(),
                           com_velocity=self.com_velocity(phys).copy(), velocity=phys.velocity().copy())

    def reward(self, phys):
        standing = tolerance(phys.xpos("head")[:, 2], bounds=(1.4, float("inf")), margin=1.4 / 4)
        upright = tolerance(phys.xmat(self.torso)[:, 2, self.upright_axis], bounds=(0.9, float("inf")),
                            sigmoid="linear", margin=1.9, value_at_margin=0)
        small_control = (4 + tolerance(phys.control(), margin=1, value_at_margin=0, sigmoid="quadratic").mean(axis=1)) / 5
        horizontal = self.com_velocity(phys)[:, :2]
        if self.move_speed == 0:
            return small_control * standing * upright * tolerance(horizontal, margin=2).mean(axis=1)
        move = tolerance(np.linalg.norm(horizontal, axis=1), bounds=(self.move_speed, float("inf")),
                         margin=self.move_speed, value_at_margin=0, sigmoid="linear")
        return small_control * standing * upright * (5 * move + 1) / 6


class Walk(Stand):
    """``humanoid-walk``."""

    move_speed = 1.0


class Run(Stand):
    """``humanoid-run``."""

    move_speed = 10.0


class RunPureState(Run):
    """``humanoid-run_pure_state``: qpos and qvel as the observation."""

    pure_state = True


class CmuStand(Stand):
    """``humanoid_CMU-stand``: the CMU motion-capture humanoid; uprightness is the thorax's zy."""

    xml = "humanoid_CMU.xml"
    time_limit = 20
    control_timestep = .02
    torso, upright_axis = "thorax", 1
    sensors = ("thorax_subtreelinvel",)
    limbs = ("lhand", "lfoot", "rhand", "rfoot")


class CmuWalk(CmuStand):
    """``humanoid_CMU-walk``."""

    move_speed = 1.0


class CmuRun(CmuStand):
    """``humanoid_CMU-run``."""

    move_speed = 10.0


TASKS = {"stand": Stand, "walk": Walk, "run": Run, "run_pure_state": RunPureState}
CMU_TASKS = {"stand": CmuStand, "walk": CmuWalk, "run": CmuRun}
