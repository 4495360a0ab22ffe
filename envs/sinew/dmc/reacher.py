"""dm_control's reacher: a two-link planar arm touches a target placed at random."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import randomize_joints, tolerance
from sinew.dmc.task import Task, set_size


class Easy(Task):
    """``reacher-easy``: joints drawn as dm_control draws them, the target (radius 5 cm) at an
    angle U(0, 2π) and distance U(0.05, 0.2) from the centre."""

    xml = "reacher.xml"
    time_limit = 20
    target_size = .05

    def model_xml(self):
        # dm_control sets the target's size at every reset; here once
        return self.edited_model(lambda root: set_size(root.find(".//geom[@name='target']"), self.target_size))

    def initialize_episode(self, phys, rngs):
        qpos = phys.position().copy()
        target = np.tile(phys.names.geom_pos[phys.names.index("geom", "target")], (len(rngs), 1))
        for q, r, t in zip(qpos, rngs, target):
            randomize_joints(phys.names, q, r)
            angle, radius = r.uniform(0, 2 * np.pi), r.uniform(.05, .2)
            t[:2] = radius * np.sin(angle), radius * np.cos(angle)
        phys.set_state(qpos)
        phys.set_geom_pos("target", target)

    def observation(self, phys):
        to_target = phys.geom_xpos("target")[:, :2] - phys.geom_xpos("finger")[:, :2]
        return OrderedDict(position=phys.position().copy(), to_target=to_target, velocity=phys.velocity().copy())

    def reward(self, phys):
        radii = phys.geom_size("target")[0] + phys.geom_size("finger")[0]
        distance = np.linalg.norm(phys.geom_xpos("target")[:, :2] - phys.geom_xpos("finger")[:, :2], axis=1)
        return tolerance(distance, (0, radii))


class Hard(Easy):
    """``reacher-hard``: a target of radius 1.5 cm."""

    target_size = .015


TASKS = {"easy": Easy, "hard": Hard}
