"""dm_control's cheetah: run forward as fast as 10 m/s."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, draw_qpos


class Run(Task):
    """``cheetah-run``: limited joints start uniform in their ranges, then the model settles for
    200 physics steps with zero control and the clock restarts."""

    xml = "cheetah.xml"
    time_limit = 10
    sensors = ("torso_subtreelinvel",)

    def initialize_episode(self, phys, rngs):
        n = phys.names
        limited = [n.jnt_qposadr[j] for j in range(len(n.joint_types)) if n.jnt_limited[j]]
        lo, hi = n.jnt_range[[j for j in range(len(n.joint_types)) if n.jnt_limited[j]]].T
        draw_qpos(phys, rngs, lambda q, r: q.__setitem__(limited, r.uniform(lo, hi)))
        phys.step(200)
        phys.batch.time[phys.rows] = 0.0

    def observation(self, phys):
        return OrderedDict(position=phys.position()[:, 1:].copy(), velocity=phys.velocity().copy())

    def reward(self, phys):
        speed = phys.sensor("torso_subtreelinvel")[:, 0]
        return tolerance(speed, bounds=(10, float("inf")), margin=10, value_at_margin=0, sigmoid="linear")


TASKS = {"run": Run}
