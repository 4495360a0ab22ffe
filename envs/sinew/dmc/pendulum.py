"""dm_control's pendulum: swing a pole up and hold it within 8° of vertical."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, draw_qpos


class SwingUp(Task):
    """``pendulum-swingup``: the pole starts at an angle in [−π, π)."""

    xml = "pendulum.xml"
    time_limit = 20

    def initialize_episode(self, phys, rngs):
        hinge = phys.names.jnt_qposadr[phys.names.index("joint", "hinge")]
        draw_qpos(phys, rngs, lambda q, r: q.__setitem__(hinge, r.uniform(-np.pi, np.pi)))

    def observation(self, phys):
        pole = phys.xmat("pole")
        return OrderedDict(orientation=pole[:, [2, 0], 2], velocity=phys.velocity()[:, :1].copy())

    def reward(self, phys):
        return tolerance(phys.xmat("pole")[:, 2, 2], (np.cos(np.deg2rad(8)), 1))


TASKS = {"swingup": SwingUp}
