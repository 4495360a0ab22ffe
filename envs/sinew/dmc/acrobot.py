"""dm_control's acrobot: swing a two-link underactuated arm's tip into a target above it."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, draw_qpos


class SwingUp(Task):
    """``acrobot-swingup``: shoulder and elbow start at angles in [−π, π)."""

    xml = "acrobot.xml"
    time_limit = 10
    sparse = False

    def initialize_episode(self, phys, rngs):
        adr = [phys.names.jnt_qposadr[phys.names.index("joint", j)] for j in ("shoulder", "elbow")]
        draw_qpos(phys, rngs, lambda q, r: q.__setitem__(adr, r.uniform(-np.pi, np.pi, 2)))

    def observation(self, phys):
        arms = np.stack([phys.xmat("upper_arm"), phys.xmat("lower_arm")], axis=1)
        return OrderedDict(orientations=np.concatenate([arms[:, :, 0, 2], arms[:, :, 2, 2]], axis=1),
                           velocity=phys.velocity().copy())

    def reward(self, phys):
        distance = np.linalg.norm(phys.site_xpos("target") - phys.site_xpos("tip"), axis=1)
        radius = phys.site_size("target")[0]
        return tolerance(distance, bounds=(0, radius), margin=0 if self.sparse else 1)


class SwingUpSparse(SwingUp):
    """``acrobot-swingup_sparse``: reward 1 while the tip is inside the target."""

    sparse = True


TASKS = {"swingup": SwingUp, "swingup_sparse": SwingUpSparse}
