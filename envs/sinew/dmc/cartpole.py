"""dm_control's cartpole: balance or swing up one, two or three poles on a cart."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import tolerance
from sinew.dmc.task import Task, draw_qpos


class Balance(Task):
    """``cartpole-balance``: the poles start near upright, the cart near the middle."""

    xml = "cartpole.xml"
    time_limit = 10
    swing_up, sparse, poles = False, False, 1

    def model_xml(self):
        """cartpole.xml with ``poles`` poles, each hinged on the one below (dm_control's
        ``_make_model``)."""
        if self.poles == 1:
            return None

        def add_poles(root):
            parent = root.find("./worldbody/body/body")
            for k in range(2, self.poles + 1):
                child = ET.SubElement(parent, "body", name=f"pole_{k}", pos="0 0 1", childclass="pole")
                ET.SubElement(child, "joint", name=f"hinge_{k}")
                ET.SubElement(child, "geom", name=f"pole_{k}")
                parent = child
            root.find("./worldbody/geom").set("pos", f"0 0 {1 - self.poles - .05}")
            cameras = root.findall("./worldbody/camera")
            cameras[0].set("pos", f"0 {-1 - 2 * self.poles} 1")
            cameras[1].set("pos", f"0 {-2 * self.poles} 2")
        return self.edited_model(add_poles)

    def initialize_episode(self, phys, rngs):
        nv = len(phys.velocity()[0])

        def draw(q, r):
            if self.swing_up:
                q[0] = .01 * r.standard_normal()
                q[1] = np.pi + .01 * r.standard_normal()
                q[2:] = .1 * r.standard_normal(nv - 2)
            else:
                q[0] = r.uniform(-.1, .1)
                q[1:] = r.uniform(-.034, .034, nv - 1)

        draw_qpos(phys, rngs, draw)
        phys.set_state(phys.position(), np.stack([.01 * r.standard_normal(nv) for r in rngs]))

    @staticmethod
    def _poles(phys):
        """The poles' rotations (n, poles, 3, 3)."""
        return phys.batch.xmat[phys.rows, 2:].reshape(len(phys.position()), -1, 3, 3)

    def observation(self, phys):
        poles = self._poles(phys)
        position = np.concatenate([phys.position()[:, :1], poles[:, :, [2, 0], 2].reshape(len(poles), -1)], axis=1)
        return OrderedDict(position=position, velocity=phys.velocity().copy())

    def reward(self, phys):
        cart = phys.position()[:, 0]
        cosine = self._poles(phys)[:, :, 2, 2]
        if self.sparse:
            return tolerance(cart, (-.25, .25)) * tolerance(cosine, (.995, 1)).prod(axis=1)
        upright = (cosine + 1) / 2
        centered = (1 + tolerance(cart, margin=2)) / 2
        small_control = (4 + tolerance(phys.control()[:, 0], margin=1, value_at_margin=0, sigmoid="quadratic")) / 5
        small_velocity = (1 + tolerance(phys.velocity()[:, 1:], margin=5).min(axis=1)) / 2
        return upright.mean(axis=1) * small_control * small_velocity * centered


class BalanceSparse(Balance):
    """``cartpole-balance_sparse``: reward 1 while the cart and poles are within bounds."""

    sparse = True


class SwingUp(Balance):
    """``cartpole-swingup``: the pole starts hanging down."""

    swing_up = True


class SwingUpSparse(SwingUp):
    """``cartpole-swingup_sparse``."""

    sparse = True


class TwoPoles(SwingUp):
    """``cartpole-two_poles``: a second pole hinged on the first."""

    poles = 2


class ThreePoles(SwingUp):
    """``cartpole-three_poles``."""

    poles = 3


TASKS = {"balance": Balance, "balance_sparse": BalanceSparse, "swingup": SwingUp, "swingup_sparse": SwingUpSparse,
         "two_poles": TwoPoles, "three_poles": ThreePoles}
