"""The gymnasium tasks of sinew's environments, built from their declarations in Rust.

Each task is declared once, in its file of ``src/tasks/`` (model file, frame_skip, episode
length, camera, keyword arguments with gymnasium's MuJoCo v5 defaults, how a reset draws the
initial state, which info the reset reports) beside its per-step logic (observation, reward terms,
termination), and registered in ``src/tasks/mod.rs``. This module turns each declaration into a
class (``sinew.tasks.Hopper``, ...) and draws the reset noise, which must come from each world's
numpy generator in the same order as the twin draws it, so that a seed gives the twin's initial
state.
"""

from __future__ import annotations

import os

import gymnasium
import numpy as np

from sinew._core import task_specs

ASSETS = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")


def uniform(rngs, low, high, size):
    """One row of U(low, high) per generator: ``r.uniform(low, high, size)``'s numbers (it computes
    low + (high − low) · u from the same u), drawn into one array."""
    u = np.empty((len(rngs), size))
    for r, row in zip(rngs, u):
        r.random(out=row)
    return low + (high - low) * u


def normal(rngs, size):
    """One row of standard normals per generator, drawn into one array."""
    x = np.empty((len(rngs), size))
    for r, row in zip(rngs, x):
        r.standard_normal(out=row)
    return x


def _reset_uniform(task, rngs):
    """qpos0 + U(±s) and U(±s) velocities: the twin's two draws as one (the same numbers)."""
    s = task.kwargs["reset_noise_scale"]
    x = uniform(rngs, -s, s, task.nq + task.nv)
    return task.qpos0 + x[:, :task.nq], x[:, task.nq:]


def _reset_uniform_normal(task, rngs):
    """qpos0 + U(±s), then s · N(0, 1) velocities."""
    s = task.kwargs["reset_noise_scale"]
    return task.qpos0 + uniform(rngs, -s, s, task.nq), s * normal(rngs, task.nv)


def _reset_reacher_goal(task, rngs):
    """The arm at qpos0 + U(±0.1), the goal drawn in U(±0.2)² until within 0.2 of the origin,
    U(±0.005) arm velocities (Reacher-v5's ``reset_model``)."""
    qpos, qvel = [], []
    for r in rngs:
        q = r.uniform(low=-0.1, high=0.1, size=task.nq) + task.qpos0
        while True:
            goal = r.uniform(low=-0.2, high=0.2, size=2)
            if np.linalg.norm(goal) < 0.2:
                break
        q[-2:] = goal
        qv = r.uniform(low=-0.005, high=0.005, size=task.nv)
        qv[-2:] = 0
        qpos.append(q)
        qvel.append(qv)
    return np.stack(qpos), np.stack(qvel)


_RESETS = {"uniform": _reset_uniform, "uniform_normal": _reset_uniform_normal, "reacher_goal": _reset_reacher_goal}


class Task:
    """A task for one model: its declaration, its keyword arguments (defaults filled in) and its
    reset noise. Subclasses (one per declared task) carry the declaration as ``spec``."""

    spec: dict = {}

    def __init__(self, model, **kwargs):
        params = self.spec["params"]
        unknown = sorted(set(kwargs) - set(params))
        if unknown:
            # Python's own wording, which wrappers such as TorchRL's GymEnv recognise
            raise TypeError(f"{type(self).__name__}.__init__() got an unexpected keyword argument '{unknown[0]}'")
        self.model = model
        self.qpos0 = model.qpos0
        self.nq, self.nv = model.nq, model.nv
        self.kwargs = {}
        for k, default in params.items():
            v = kwargs.get(k, default)
            if isinstance(default, tuple):
                v = tuple(v)
            elif k == "main_body" and isinstance(v, str):
                v = model.body_names.index(v)
            self.kwargs[k] = v
        self.frame_skip = self.spec["frame_skip"]

    @property
    def kind(self) -> str:
        return self.spec["name"]

    @property
    def dt(self) -> float:
        """Seconds per env step."""
        return self.model.timestep * self.frame_skip

    def params(self) -> dict:
        """The keyword arguments of ``Batch.set_task`` (the v5 env's, defaults filled in)."""
        return dict(self.kwargs)

    def reset_state(self, rngs) -> tuple[np.ndarray, np.ndarray]:
        """Initial (qpos, qvel) of the worlds whose generators are ``rngs``, as the twin draws them."""
        return _RESETS[self.spec["reset"]](self, rngs)


def _task_class(spec: dict) -> type[Task]:
    """The class of one declared task: its spec, model file, episode length and the twin's
    ``DEFAULT_CAMERA_CONFIG`` as class attributes."""
    attrs = {"spec": spec, "xml": spec["xml"], "max_episode_steps": spec["max_episode_steps"],
             "camera": spec["camera"], "__doc__": f"{spec['name']}-v5's task.", "__module__": __name__}
    return type(spec["name"], (Task,), attrs)


#: Every task's class by name, in registration order.
TASKS: dict[str, type[Task]] = {s["name"]: _task_class(s) for s in task_specs()}
globals().update(TASKS)
