"""dm_control's point mass: drive a mass on a plane into a target at the centre."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import randomize_joints, tolerance
from sinew.dmc.task import Task, draw_qpos


class Easy(Task):
    """``point_mass-easy``: the mass starts uniform in the joints' ranges."""

    xml = "point_mass.xml"
    time_limit = 20

    def initialize_episode(self, phys, rngs):
        draw_qpos(phys, rngs, lambda q, r: randomize_joints(phys.names, q, r))

    def observation(self, phys):
        return OrderedDict(position=phys.position().copy(), velocity=phys.velocity().copy())

    def reward(self, phys):
        size = phys.geom_size("target")[0]
        distance = np.linalg.norm(phys.geom_xpos("target") - phys.geom_xpos("pointmass"), axis=1)
        near = tolerance(distance, bounds=(0, size), margin=size)
        control = tolerance(phys.control(), margin=1, value_at_margin=0, sigmoid="quadratic").mean(axis=1)
        return near * (control + 4) / 5


class Hard(Easy):
    """``point_mass-hard``: as easy, and each control drives a direction of the plane drawn per
    episode (the fixed tendons' coefficients, ``wrap_prm``), the two at least 25.8° apart."""

    def initialize_episode(self, phys, rngs):
        super().initialize_episode(phys, rngs)
        prm = []
        for rng in rngs:
            dir1 = rng.standard_normal(2)
            dir1 /= np.linalg.norm(dir1)
            while True:
                dir2 = rng.standard_normal(2)
                dir2 /= np.linalg.norm(dir2)
                if abs(dir1 @ dir2) <= 0.9:
                    break
            prm.append(np.concatenate([dir1, dir2]))
        phys.set_params("wrap_prm", np.array(prm))


TASKS = {"easy": Easy, "hard": Hard}
