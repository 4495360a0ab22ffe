"""The declaration every dm_control suite task of ``sinew.dmc`` makes."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import Physics


class Task:
    """One task of dm_control's suite: its model file, timing, how an episode starts, what it
    observes and how it rewards, as dm_control's task of the same name computes them. Methods
    read and write many worlds at once through a :class:`Physics`; ``rngs`` holds one numpy
    generator per world of ``phys.rows``, each drawn from in dm_control's order."""

    #: The model file, in dm_control's suite directory.
    xml: str = ""
    #: Episode length in seconds (dm_control's ``time_limit``).
    time_limit: float = 20.0
    #: Seconds per control step; None: one physics step.
    control_timestep: float | None = None
    #: The camera pixel observations use by default (dm_control's conventional one).
    pixels_camera: int = 0
    #: The free camera's settings for ``render()`` without a camera (none: the model's own view).
    camera: dict = {}
    #: Keyword arguments (dm_control's tasks take none beyond the env's).
    kwargs: dict = {}
    #: The file sensors the task reads (read together once per state; others one by one).
    sensors: tuple = ()

    def model_xml(self) -> str | None:
        """The model's MJCF text when the task builds it (None: the file as it is)."""
        return None

    def edited_model(self, edit) -> str:
        """The model file's text after ``edit(root)`` changed its XML tree."""
        from sinew.dmc import suite_dir
        root = ET.parse(os.path.join(suite_dir(), self.xml)).getroot()
        edit(root)
        return ET.tostring(root, encoding="unicode")

    def initialize_episode(self, phys: Physics, rngs: list) -> None:
        """Draws the initial state of the worlds of ``phys`` (reset to qpos0 at rest)."""

    def observation(self, phys: Physics) -> OrderedDict:
        """The named observations, one row per world, in dm_control's key order."""
        raise NotImplementedError

    def reward(self, phys: Physics) -> np.ndarray:
        """The reward of each world at its current state (n,)."""
        raise NotImplementedError

    def termination(self, phys: Physics) -> np.ndarray:
        """Which worlds' episodes end before the time limit (dm_control's discount 0)."""
        return np.zeros(len(phys.position()), dtype=bool)


def draw_qpos(phys: Physics, rngs: list, draw) -> None:
    """Sets each world's qpos to ``draw(qpos, rng)`` applied to a copy of its current qpos."""
    qpos = phys.position().copy()
    for q, rng in zip(qpos, rngs):
        draw(q, rng)
    phys.set_state(qpos)


def draw_until_apart(phys: Physics, rngs: list, draw) -> None:
    """dm_control's ``while penetrating`` reset: each world draws its qpos from qpos0 with
    ``draw(qpos, rng)`` until no two of its geoms overlap."""
    start = phys.position().copy()
    pending = np.arange(len(start))
    qpos = start.copy()
    while len(pending):
        for k in pending:
            qpos[k] = start[k]
            draw(qpos[k], rngs[k])
        phys.set_state(qpos)
        pending = pending[phys.penetrations()[pending] > 0]


def remove(root, tag: str, name: str | None = None) -> None:
    """Removes every `tag` element of the tree (only the one named `name`, when given)."""
    for parent in list(root.iter()):
        for child in [c for c in parent if c.tag == tag and (name is None or c.get("name") == name)]:
            parent.remove(child)


def set_size(node, first: float) -> None:
    """Sets the first number of an element's ``size`` (a geom's or site's radius)."""
    size = node.get("size").split()
    node.set("size", " ".join([repr(first), *size[1:]]))
