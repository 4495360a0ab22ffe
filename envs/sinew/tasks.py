"""The gymnasium tasks of sinew's environments: their model files, frame_skip, episode length,
keyword arguments (with gymnasium's MuJoCo v5 defaults) and reset noise.

Each task reproduces gymnasium's MuJoCo v5 environment of the same name. Reset noise is drawn
here, in the same order from the same per-world numpy generator as the twin, so a seed gives the
twin's initial state. Everything computed per step (observation, reward terms, termination) runs
in Rust inside the batch's parallel step (``src/tasks/``, one file per task), from sinew's own physics; a task hands
it the env's keyword arguments through ``Batch.set_task(kind, **params())``.
"""

from __future__ import annotations

import os

import gymnasium
import numpy as np

ASSETS = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")


class Task:
    """Base class: the task's name, model file, timing, parameters and reset noise."""

    xml: str = ""
    frame_skip: int = 1
    max_episode_steps: int = 1000
    #: The twin's ``DEFAULT_CAMERA_CONFIG``.
    camera: dict = {}

    def __init__(self, model, **kwargs):
        if kwargs:
            # Python's own wording, which wrappers such as TorchRL's GymEnv recognise
            raise TypeError(f"{type(self).__name__}.__init__() got an unexpected keyword argument '{min(kwargs)}'")
        self.model = model
        self.dt = model.timestep * self.frame_skip
        self.qpos0 = model.qpos0
        self.nq, self.nv = model.nq, model.nv
        self.kwargs: dict = {}

    @property
    def kind(self) -> str:
        return type(self).__name__

    def params(self) -> dict:
        """The keyword arguments of ``Batch.set_task`` (the v5 env's, defaults filled in)."""
        return self.kwargs

    def reset_state(self, rngs) -> tuple[np.ndarray, np.ndarray]:
        """Initial (qpos, qvel) of the worlds whose generators are ``rngs``, as the twin draws them."""
        raise NotImplementedError

    def reset_info(self, qpos: np.ndarray) -> dict:
        """The twin's ``reset`` info for worlds at ``qpos`` (N, nq)."""
        return {}


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


def uniform_state(task, rngs):
    """qpos0 + U(±noise) and U(±noise) velocities: the twin's two draws as one (the same numbers)."""
    n = task.noise
    x = uniform(rngs, -n, n, task.nq + task.nv)
    return task.qpos0 + x[:, :task.nq], x[:, task.nq:]


def planar_info(qpos):
    """Where a free-floating body's root is in the ground plane (Ant's and Humanoid's info)."""
    return {"x_position": qpos[:, 0].copy(), "y_position": qpos[:, 1].copy(),
            "distance_from_origin": np.linalg.norm(qpos[:, :2], axis=1)}


class InvertedPendulum(Task):
    xml, frame_skip = "inverted_pendulum.xml", 2
    camera = {"trackbodyid": 0, "distance": 2.04}

    def __init__(self, model, reset_noise_scale=0.01, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale

    def reset_state(self, rngs):
        return uniform_state(self, rngs)


class InvertedDoublePendulum(Task):
    xml, frame_skip = "inverted_double_pendulum.xml", 5
    # the twin defines a DEFAULT_CAMERA_CONFIG but passes None: the viewer's own defaults apply
    camera: dict = {}

    def __init__(self, model, healthy_reward=10.0, reset_noise_scale=0.1, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale
        self.kwargs = {"healthy_reward": healthy_reward}

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), normal(rngs, self.nv) * n


class Reacher(Task):
    xml, frame_skip, max_episode_steps = "reacher.xml", 2, 50
    camera = {"trackbodyid": 0}

    def __init__(self, model, reward_dist_weight=1.0, reward_control_weight=1.0, **kw):
        super().__init__(model, **kw)
        self.kwargs = {"reward_dist_weight": reward_dist_weight, "reward_control_weight": reward_control_weight}

    def reset_state(self, rngs):
        qpos, qvel = [], []
        for r in rngs:
            q = r.uniform(low=-0.1, high=0.1, size=self.nq) + self.qpos0
            while True:
                goal = r.uniform(low=-0.2, high=0.2, size=2)
                if np.linalg.norm(goal) < 0.2:
                    break
            q[-2:] = goal
            qv = r.uniform(low=-0.005, high=0.005, size=self.nv)
            qv[-2:] = 0
            qpos.append(q)
            qvel.append(qv)
        return np.stack(qpos), np.stack(qvel)


class _Planar(Task):
    """Hopper, Walker2d, HalfCheetah: forward progress of qpos[0]."""

    def __init__(self, model, forward_reward_weight=1.0, ctrl_cost_weight=1e-3, reset_noise_scale=5e-3,
                 exclude_current_positions_from_observation=True, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale
        self.kwargs = {"forward_reward_weight": forward_reward_weight, "ctrl_cost_weight": ctrl_cost_weight,
                       "exclude_current_positions_from_observation": exclude_current_positions_from_observation}

    def reset_state(self, rngs):
        return uniform_state(self, rngs)

    def reset_info(self, qpos):
        return {"x_position": qpos[:, 0].copy(), "z_distance_from_origin": qpos[:, 1] - self.qpos0[1]}


class _Healthy(_Planar):
    def __init__(self, model, healthy_reward=1.0, terminate_when_unhealthy=True, healthy_z_range=(0.7, np.inf),
                 healthy_angle_range=(-0.2, 0.2), **kw):
        super().__init__(model, **kw)
        self.kwargs |= {"healthy_reward": healthy_reward, "terminate_when_unhealthy": terminate_when_unhealthy,
                        "healthy_z_range": tuple(healthy_z_range), "healthy_angle_range": tuple(healthy_angle_range)}


class Hopper(_Healthy):
    xml, frame_skip = "hopper.xml", 4
    camera = {"trackbodyid": 2, "distance": 3.0, "lookat": (0.0, 0.0, 1.15), "elevation": -20.0}

    def __init__(self, model, healthy_state_range=(-100.0, 100.0), **kw):
        super().__init__(model, **kw)
        self.kwargs["healthy_state_range"] = tuple(healthy_state_range)


class Walker2d(_Healthy):
    xml, frame_skip = "walker2d_v5.xml", 4
    camera = {"trackbodyid": 2, "distance": 4.0, "lookat": (0.0, 0.0, 1.15), "elevation": -20.0}

    def __init__(self, model, healthy_z_range=(0.8, 2.0), healthy_angle_range=(-1.0, 1.0), **kw):
        super().__init__(model, healthy_z_range=healthy_z_range, healthy_angle_range=healthy_angle_range, **kw)


class HalfCheetah(_Planar):
    xml, frame_skip = "half_cheetah.xml", 5
    camera = {"distance": 4.0}

    def __init__(self, model, ctrl_cost_weight=0.1, reset_noise_scale=0.1, **kw):
        super().__init__(model, ctrl_cost_weight=ctrl_cost_weight, reset_noise_scale=reset_noise_scale, **kw)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), n * normal(rngs, self.nv)

    def reset_info(self, qpos):
        return {"x_position": qpos[:, 0].copy()}


class Ant(Task):
    xml, frame_skip = "ant.xml", 5
    camera = {"distance": 4.0}

    def __init__(self, model, forward_reward_weight=1.0, ctrl_cost_weight=0.5, contact_cost_weight=5e-4,
                 healthy_reward=1.0, main_body=1, terminate_when_unhealthy=True, healthy_z_range=(0.2, 1.0),
                 contact_force_range=(-1.0, 1.0), reset_noise_scale=0.1,
                 exclude_current_positions_from_observation=True, include_cfrc_ext_in_observation=True, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale
        main = main_body if isinstance(main_body, int) else model.body_names.index(main_body)
        self.kwargs = {
            "forward_reward_weight": forward_reward_weight, "ctrl_cost_weight": ctrl_cost_weight,
            "contact_cost_weight": contact_cost_weight, "healthy_reward": healthy_reward, "main_body": main,
            "terminate_when_unhealthy": terminate_when_unhealthy, "healthy_z_range": tuple(healthy_z_range),
            "contact_force_range": tuple(contact_force_range),
            "exclude_current_positions_from_observation": exclude_current_positions_from_observation,
            "include_cfrc_ext_in_observation": include_cfrc_ext_in_observation,
        }

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), n * normal(rngs, self.nv)

    def reset_info(self, qpos):
        return planar_info(qpos)


class Humanoid(Task):
    xml, frame_skip = "humanoid.xml", 5
    camera = {"trackbodyid": 1, "distance": 4.0, "lookat": (0.0, 0.0, 2.0), "elevation": -20.0}

    def __init__(self, model, forward_reward_weight=1.25, ctrl_cost_weight=0.1, contact_cost_weight=5e-7,
                 contact_cost_range=(-np.inf, 10.0), healthy_reward=5.0, terminate_when_unhealthy=True,
                 healthy_z_range=(1.0, 2.0), reset_noise_scale=1e-2, exclude_current_positions_from_observation=True,
                 include_cinert_in_observation=True, include_cvel_in_observation=True,
                 include_qfrc_actuator_in_observation=True, include_cfrc_ext_in_observation=True, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale
        self.kwargs = {
            "forward_reward_weight": forward_reward_weight, "ctrl_cost_weight": ctrl_cost_weight,
            "contact_cost_weight": contact_cost_weight, "contact_cost_range": tuple(contact_cost_range),
            "healthy_reward": healthy_reward, "terminate_when_unhealthy": terminate_when_unhealthy,
            "healthy_z_range": tuple(healthy_z_range),
            "exclude_current_positions_from_observation": exclude_current_positions_from_observation,
            "include_cinert_in_observation": include_cinert_in_observation,
            "include_cvel_in_observation": include_cvel_in_observation,
            "include_qfrc_actuator_in_observation": include_qfrc_actuator_in_observation,
            "include_cfrc_ext_in_observation": include_cfrc_ext_in_observation,
        }

    def reset_state(self, rngs):
        return uniform_state(self, rngs)

    def reset_info(self, qpos):
        return planar_info(qpos)


TASKS = {
    "InvertedPendulum": InvertedPendulum,
    "InvertedDoublePendulum": InvertedDoublePendulum,
    "Reacher": Reacher,
    "Hopper": Hopper,
    "Walker2d": Walker2d,
    "HalfCheetah": HalfCheetah,
    "Ant": Ant,
    "Humanoid": Humanoid,
}
