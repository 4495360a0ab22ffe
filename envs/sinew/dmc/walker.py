"""dm_control's planar walker: stand, walk at 1 m/s or run at 8 m/s."""

from __future__ import annotations

from collections import OrderedDict

from sinew.dmc.physics import randomize_joints, tolerance
from sinew.dmc.task import Task, draw_qpos


class Stand(Task):
    """``walker-stand``: joints drawn as dm_control's ``randomize_limited_and_rotational_joints``."""

    xml = "walker.xml"
    time_limit = 25
    control_timestep = .025
    move_speed = 0.0
    sensors = ("torso_subtreelinvel",)

    def initialize_episode(self, phys, rngs):
        draw_qpos(phys, rngs, lambda q, r: randomize_joints(phys.names, q, r))

    def observation(self, phys):
        xmat = phys.batch.xmat[phys.rows, 1:]
        return OrderedDict(orientations=xmat[:, :, [0, 2]].reshape(len(xmat), -1), height=phys.xpos("torso")[:, 2],
                           velocity=phys.velocity().copy())

    def reward(self, phys):
        standing = tolerance(phys.xpos("torso")[:, 2], bounds=(1.2, float("inf")), margin=1.2 / 2)
        upright = (1 + phys.xmat("torso")[:, 2, 2]) / 2
        stand = (3 * standing + upright) / 4
        if self.move_speed == 0:
            return stand
        move = tolerance(phys.sensor("torso_subtreelinvel")[:, 0], bounds=(self.move_speed, float("inf")),
                         margin=self.move_speed / 2, value_at_margin=0.5, sigmoid="linear")
        return stand * (5 * move + 1) / 6


class Walk(Stand):
    """``walker-walk``."""

    move_speed = 1.0


class Run(Stand):
    """``walker-run``."""

    move_speed = 8.0


TASKS = {"stand": Stand, "walk": Walk, "run": Run}
