"""dm_control's lqr: a chain of sliders on springs, some actuated, driven to rest at the origin
(an infinite horizon: an episode ends when the state's norm falls below 1e-6)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import OrderedDict

import numpy as np

from sinew.dmc.task import Task


class Lqr21(Task):
    """``lqr-lqr_2_1``: two bodies, one actuated. dm_control draws the joints' stiffnesses
    (U(15, 25)) from the task's seed when it builds the env; here from ``model_seed`` (0 by
    default), once per env. Each episode starts at a uniformly random direction in qpos, at norm √2."""

    xml = "lqr.xml"
    time_limit = float("inf")
    bodies, actuators = 2, 1

    def __init__(self, model_seed: int = 0):
        self.model_seed = model_seed

    def model_xml(self):
        """lqr.xml with the chain of bodies, motors and tendons (dm_control's ``lqr._make_model``)."""
        rng = np.random.default_rng(self.model_seed)

        def build(root):
            parent = root.find("./worldbody")
            actuator, tendon = ET.SubElement(root, "actuator"), ET.SubElement(root, "tendon")
            for k in range(self.bodies):
                child = ET.SubElement(parent, "body", name=f"body_{k}", pos=".25 0 .1" if k == 0 else ".25 0 0")
                ET.SubElement(child, "joint", name=f"joint_{k}", stiffness=str(rng.uniform(15, 25)), damping=str(rng.uniform(0, 0)))
                ET.SubElement(child, "geom", name=f"geom_{k}")
                ET.SubElement(child, "site", name=f"site_{k}")
                if k < self.actuators:
                    ET.SubElement(actuator, "motor", name=f"motor_{k}", joint=f"joint_{k}")
                if k < self.bodies - 1:
                    spatial = ET.SubElement(tendon, "spatial", name=f"tendon_{k}")
                    ET.SubElement(spatial, "site", site=f"site_{k}")
                    ET.SubElement(spatial, "site", site=f"site_{k + 1}")
                parent = child
        return self.edited_model(build)

    def initialize_episode(self, phys, rngs):
        qpos = phys.position().copy()
        for q, r in zip(qpos, rngs):
            unit = r.standard_normal(len(q))
            q[:] = np.sqrt(2) * unit / np.linalg.norm(unit)
        phys.set_state(qpos)

    def observation(self, phys):
        return OrderedDict(position=phys.position().copy(), velocity=phys.velocity().copy())

    def reward(self, phys):
        q, u = phys.position(), phys.control()
        return 1 - (0.5 * np.einsum("ni,ni->n", q, q) + 0.1 * 0.5 * np.einsum("ni,ni->n", u, u))

    def termination(self, phys):
        return np.linalg.norm(np.concatenate([phys.position(), phys.velocity()], axis=1), axis=1) < 1e-6


class Lqr62(Lqr21):
    """``lqr-lqr_6_2``: six bodies, two actuated."""

    bodies, actuators = 6, 2


TASKS = {"lqr_2_1": Lqr21, "lqr_6_2": Lqr62}
