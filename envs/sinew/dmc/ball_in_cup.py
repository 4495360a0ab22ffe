"""dm_control's ball in cup: swing a ball on a string into the cup that holds the string."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.task import Task, draw_until_apart


class Catch(Task):
    """``ball_in_cup-catch``: the ball starts at x in U(−0.2, 0.2), z in U(0.2, 0.5), drawn again
    while it overlaps the cup."""

    xml = "ball_in_cup.xml"
    time_limit = 20
    control_timestep = .02

    def initialize_episode(self, phys, rngs):
        x, z = (phys.names.jnt_qposadr[phys.names.index("joint", j)] for j in ("ball_x", "ball_z"))

        def draw(q, r):
            q[x] = r.uniform(-0.2, 0.2)
            q[z] = r.uniform(0.2, 0.5)

        draw_until_apart(phys, rngs, draw)

    def observation(self, phys):
        return OrderedDict(position=phys.position().copy(), velocity=phys.velocity().copy())

    def reward(self, phys):
        offset = np.abs(phys.site_xpos("target")[:, [0, 2]] - phys.xpos("ball")[:, [0, 2]])
        room = phys.site_size("target")[[0, 2]] - phys.geom_size("ball")[0]
        return np.all(offset < room, axis=1).astype(np.float64)


TASKS = {"catch": Catch}
