"""dm_control's hopper: stand up, or hop forward at 2 m/s."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import randomize_joints, tolerance
from sinew.dmc.task import Task, draw_qpos


class Stand(Task):
    """``hopper-stand``: joints drawn as dm_control's ``randomize_limited_and_rotational_joints``."""

    xml = "hopper.xml"
    time_limit = 20
    control_timestep = .02
    hopping = False
    sensors = ("torso_subtreelinvel", "touch_toe", "touch_heel")

    def initialize_episode(self, phys, rngs):
        draw_qpos(phys, rngs, lambda q, r: randomize_joints(phys.names, q, r))

    def observation(self, phys):
        touch = np.log1p(np.concatenate([phys.sensor("touch_toe"), phys.sensor("touch_heel")], axis=1))
        return OrderedDict(position=phys.position()[:, 1:].copy(), velocity=phys.velocity().copy(), touch=touch)

    def reward(self, phys):
        standing = tolerance(phys.xipos("torso")[:, 2] - phys.xipos("foot")[:, 2], (0.6, 2))
        if self.hopping:
            hopping = tolerance(phys.sensor("torso_subtreelinvel")[:, 0], bounds=(2, float("inf")), margin=1,
                                value_at_margin=0.5, sigmoid="linear")
            return standing * hopping
        small_control = tolerance(phys.control(), margin=1, value_at_margin=0, sigmoid="quadratic").mean(axis=1)
        return standing * (small_control + 4) / 5


class Hop(Stand):
    """``hopper-hop``."""

    hopping = True


TASKS = {"stand": Stand, "hop": Hop}
