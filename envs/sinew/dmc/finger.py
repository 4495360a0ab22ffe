"""dm_control's finger: a two-link planar finger spins a hinged body, or turns its tip to a
target. Every observation is a function of the file's sensors."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import randomize_joints
from sinew.dmc.task import Task, draw_until_apart, set_size


class Spin(Task):
    """``finger-spin``: joints drawn until the finger and spinner do not overlap; the hinge's
    damping 0.03 and the tip and target hidden (dm_control's changes at every reset, made once)."""

    xml = "finger.xml"
    time_limit = 20
    control_timestep = .02
    sensors = ("proximal", "distal", "proximal_velocity", "distal_velocity", "hinge_velocity", "tip", "spinner",
               "touchtop", "touchbottom")

    def model_xml(self):
        def edit(root):
            root.find(".//joint[@name='hinge']").set("damping", "0.03")
            for site in ("target", "tip"):
                root.find(f".//site[@name='{site}']").set("rgba", "0 0 0 0")
        return self.edited_model(edit)

    def initialize_episode(self, phys, rngs):
        draw_until_apart(phys, rngs, lambda q, r: randomize_joints(phys.names, q, r))

    @staticmethod
    def tip_position(phys):
        return phys.sensor("tip")[:, [0, 2]] - phys.sensor("spinner")[:, [0, 2]]

    def observation(self, phys):
        position = np.concatenate([phys.sensor("proximal"), phys.sensor("distal"), self.tip_position(phys)], axis=1)
        velocity = np.concatenate([phys.sensor(s) for s in ("proximal_velocity", "distal_velocity", "hinge_velocity")], axis=1)
        touch = np.log1p(np.concatenate([phys.sensor("touchtop"), phys.sensor("touchbottom")], axis=1))
        return OrderedDict(position=position, velocity=velocity, touch=touch)

    def reward(self, phys):
        return (phys.sensor("hinge_velocity")[:, 0] <= -15.0).astype(np.float64)


class TurnEasy(Spin):
    """``finger-turn_easy``: the target (radius 7 cm) on the spinner's circle at an angle
    U(−π, π), then the joints drawn as for spin."""

    target_radius = .07

    def model_xml(self):
        return self.edited_model(lambda root: set_size(root.find(".//site[@name='target']"), self.target_radius))

    def initialize_episode(self, phys, rngs):
        angle = np.array([r.uniform(-np.pi, np.pi) for r in rngs])
        # the hinge sits at the spinner's origin; cap1's radius plus half-length reach its end
        hinge = phys.xpos("spinner")
        radius = phys.geom_size("cap1").sum()
        target = np.tile(phys.names.site_pos[phys.names.index("site", "target")], (len(rngs), 1))
        target[:, 0] = hinge[:, 0] + radius * np.sin(angle)
        target[:, 2] = hinge[:, 2] + radius * np.cos(angle)
        phys.set_site_pos("target", target)
        super().initialize_episode(phys, rngs)

    @staticmethod
    def target_position(phys):
        # the target site is on the world body: its placed position is its reading
        return phys.site_xpos("target")[:, [0, 2]] - phys.sensor("spinner")[:, [0, 2]]

    def distance(self, phys):
        return np.linalg.norm(self.target_position(phys) - self.tip_position(phys), axis=1) - phys.site_size("target")[0]

    def observation(self, phys):
        obs = super().observation(phys)
        obs["target_position"] = self.target_position(phys)
        obs["dist_to_target"] = self.distance(phys)
        return obs

    def reward(self, phys):
        return (self.distance(phys) <= 0).astype(np.float64)


class TurnHard(TurnEasy):
    """``finger-turn_hard``: a target of radius 3 cm."""

    target_radius = .03


TASKS = {"spin": Spin, "turn_easy": TurnEasy, "turn_hard": TurnHard}
