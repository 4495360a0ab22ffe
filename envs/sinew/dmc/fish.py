"""dm_control's fish: a fish in a fluid (no gravity, no contacts) keeps upright, or swims its
mouth to a target."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import in_frame, tolerance
from sinew.dmc.task import Task, remove

JOINTS = ["tail1", "tail_twist", "tail2", "finright_roll", "finright_pitch", "finleft_roll", "finleft_pitch"]


class Upright(Task):
    """``fish-upright``: a random orientation (normalised N(0, 1)⁴), fin and tail joints in
    U(−0.2, 0.2); the target is not drawn."""

    xml = "fish.xml"
    time_limit = 40
    control_timestep = .04

    def model_xml(self):
        # dm_control makes the target transparent; it has no contacts, so leaving it out is the same
        return self.edited_model(lambda root: remove(root, "geom", "target")) if type(self) is Upright else None

    def _draw(self, phys, rngs):
        """The orientation and joints each world draws; its qpos."""
        names = phys.names
        root = names.jnt_qposadr[names.index("joint", "root")]
        joints = [names.jnt_qposadr[names.index("joint", j)] for j in JOINTS]
        qpos = phys.position().copy()
        for q, r in zip(qpos, rngs):
            quat = r.standard_normal(4)
            q[root + 3:root + 7] = quat / np.linalg.norm(quat)
            for a in joints:
                q[a] = r.uniform(-.2, .2)
        return qpos

    def initialize_episode(self, phys, rngs):
        phys.set_state(self._draw(phys, rngs))

    def joint_angles(self, phys):
        names = phys.names
        return phys.position()[:, [names.jnt_qposadr[names.index("joint", j)] for j in JOINTS]]

    def observation(self, phys):
        return OrderedDict(joint_angles=self.joint_angles(phys), upright=phys.xmat("torso")[:, 2, 2],
                           velocity=phys.velocity().copy())

    def reward(self, phys):
        return tolerance(phys.xmat("torso")[:, 2, 2], bounds=(1, 1), margin=1)


class Swim(Upright):
    """``fish-swim``: as upright, and the target at x, y in U(−0.4, 0.4), z in U(0.1, 0.3)."""

    def initialize_episode(self, phys, rngs):
        qpos = self._draw(phys, rngs)
        target = np.stack([[r.uniform(-.4, .4), r.uniform(-.4, .4), r.uniform(.1, .3)] for r in rngs])
        phys.set_state(qpos)
        phys.set_geom_pos("target", target)

    @staticmethod
    def mouth_to_target(phys):
        """The target in the mouth's frame."""
        return in_frame(phys.geom_xpos("target") - phys.geom_xpos("mouth"), phys.geom_xmat("mouth"))

    def observation(self, phys):
        return OrderedDict(joint_angles=self.joint_angles(phys), upright=phys.xmat("torso")[:, 2, 2],
                           target=self.mouth_to_target(phys), velocity=phys.velocity().copy())

    def reward(self, phys):
        radii = phys.geom_size("mouth")[0] + phys.geom_size("target")[0]
        distance = np.linalg.norm(self.mouth_to_target(phys), axis=1)
        in_target = tolerance(distance, bounds=(0, radii), margin=2 * radii)
        return (7 * in_target + 0.5 * (phys.xmat("torso")[:, 2, 2] + 1)) / 8


TASKS = {"upright": Upright, "swim": Swim}
