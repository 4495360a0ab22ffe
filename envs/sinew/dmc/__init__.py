"""dm_control's suite as sinew environments: ``sinew/dmc-<domain>-<task>-v0``.

Each task is dm_control's task of that name, written here (dm_control is not imported at run
time): the same model file (read from the installed ``dm-control`` package's suite directory),
control timestep and physics substeps, episode length, initial-state distribution, reward and
named observations. Observations are flattened into one float64 ``Box`` in dm_control's key
order (``flat_observation=False``: a ``Dict``); ``from_pixels=True`` observes RGB frames
(``height`` × ``width``, 84 × 84 by default) from ``camera_id`` (dm_control's conventional camera
of the domain by default), with the state beside them when ``pixels_only=False``;
``action_repeat`` repeats an action over that many control steps, summing their rewards;
``frame_stack`` stacks the last frames along the channel axis (H, W, 3k). Episodes end only at
the time limit (``truncated``), as dm_control's discount of 1 says.
"""

from __future__ import annotations

import importlib.util
import os

from sinew.dmc import (acrobot, ball_in_cup, cartpole, cheetah, dog, finger, fish, hopper, humanoid, lqr, manipulator, pendulum,
                       point_mass, quadruped, reacher, stacker, swimmer, walker)
from sinew.dmc.task import Task

_DOMAINS = {
    "acrobot": acrobot.TASKS, "ball_in_cup": ball_in_cup.TASKS, "cartpole": cartpole.TASKS, "cheetah": cheetah.TASKS, "dog": dog.TASKS,
    "hopper": hopper.TASKS, "humanoid": humanoid.TASKS, "humanoid_CMU": humanoid.CMU_TASKS,
    "finger": finger.TASKS, "fish": fish.TASKS, "lqr": lqr.TASKS, "manipulator": manipulator.TASKS, "pendulum": pendulum.TASKS, "point_mass": point_mass.TASKS, "quadruped": quadruped.TASKS,
    "reacher": reacher.TASKS, "stacker": stacker.TASKS,
    "swimmer": swimmer.TASKS, "walker": walker.TASKS,
}

#: Every task's class by its name ``dmc-<domain>-<task>``, in dm_control's order.
TASKS: dict[str, type[Task]] = {f"dmc-{d}-{t}": cls for d in sorted(_DOMAINS) for t, cls in _DOMAINS[d].items()}


def suite_dir() -> str:
    """The directory of dm_control's suite model files, found without importing dm_control."""
    spec = importlib.util.find_spec("dm_control")
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError("sinew's dmc tasks read dm_control's model files: pip install dm-control")
    return os.path.join(list(spec.submodule_search_locations)[0], "suite")
