"""dm_control's swimmer: an n-link planar snake in a viscous fluid swims its nose to a target."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import in_frame, randomize_joints, tolerance
from sinew.dmc.task import Task


class Swimmer6(Task):
    """``swimmer-swimmer6``: six links; joints drawn as dm_control draws them, the target at x, y
    uniform in ±0.3 (one episode in five) or ±2."""

    xml = "swimmer.xml"
    time_limit = 30
    control_timestep = .03
    bodies = 6

    def model_xml(self):
        """swimmer.xml with ``bodies`` links, a motor, velocimeter and gyro per joint (dm_control's
        ``swimmer._make_model``)."""
        def build(root):
            parent = root.find("./worldbody/body")
            actuator, sensor = ET.SubElement(root, "actuator"), ET.SubElement(root, "sensor")
            for k in range(self.bodies - 1):
                child = ET.SubElement(parent, "body", name=f"segment_{k}", pos="0 .1 0")
                ET.SubElement(child, "geom", {"class": "visual", "name": f"visual_{k}"})
                ET.SubElement(child, "geom", {"class": "inertial", "name": f"inertial_{k}"})
                ET.SubElement(child, "site", name=f"site_{k}")
                limit = 360.0 / self.bodies
                ET.SubElement(child, "joint", name=f"joint_{k}", range=f"{-limit} {limit}")
                ET.SubElement(actuator, "motor", name=f"motor_{k}", joint=f"joint_{k}")
                ET.SubElement(sensor, "velocimeter", name=f"velocimeter_{k}", site=f"site_{k}")
                ET.SubElement(sensor, "gyro", name=f"gyro_{k}", site=f"site_{k}")
                parent = child
            for cam in root.findall("./worldbody/body/camera"):
                if cam.get("mode") == "trackcom":
                    cam.set("pos", " ".join(str(float(x) * self.bodies / 6.0) for x in cam.get("pos").split(" ")))
        return self.edited_model(build)

    def initialize_episode(self, phys, rngs):
        qpos = phys.position().copy()
        target = np.tile(phys.names.geom_pos[phys.names.index("geom", "target")], (len(rngs), 1))
        for q, r, t in zip(qpos, rngs, target):
            randomize_joints(phys.names, q, r)
            box = .3 if r.random() < .2 else 2
            t[:2] = r.uniform(-box, box, size=2)
        phys.set_state(qpos)
        phys.set_geom_pos("target", target)

    @staticmethod
    def nose_to_target(phys):
        """The target in the head's frame, x and y."""
        d = phys.geom_xpos("target") - phys.geom_xpos("nose")
        return in_frame(d, phys.xmat("head"))[:, :2]

    @property
    def sensors(self):
        """The head's velocimeter and gyro, then each link's."""
        return ("head_vel", "head_gyro", *(f"{kind}_{k}" for k in range(self.bodies - 1) for kind in ("velocimeter", "gyro")))

    def observation(self, phys):
        # each link's velocimeter and gyro side by side (n, links, 6): its local forward and
        # sideways velocity and its turning rate
        readings = np.stack([phys.sensor(s) for s in self.sensors], axis=1).reshape(-1, self.bodies, 6)
        return OrderedDict(joints=phys.position()[:, 3:].copy(), to_target=self.nose_to_target(phys),
                           body_velocities=readings[:, :, [0, 1, 5]].reshape(-1, 3 * self.bodies))

    def reward(self, phys):
        size = phys.geom_size("target")[0]
        distance = np.linalg.norm(self.nose_to_target(phys), axis=1)
        return tolerance(distance, bounds=(0, size), margin=5 * size, sigmoid="long_tail")


class Swimmer15(Swimmer6):
    """``swimmer-swimmer15``: fifteen links."""

    bodies = 15


TASKS = {"swimmer6": Swimmer6, "swimmer15": Swimmer15}
