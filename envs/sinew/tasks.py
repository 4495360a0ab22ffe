"""Task logic of sinew's environments, vectorised over a batch of worlds.

Each task reproduces gymnasium's MuJoCo v5 environment of the same name: model file, frame_skip,
observation, reward terms (reported by name), termination and reset noise (drawn in the same order
from the same generator, so a seed gives the same initial state as the twin). Quantities MuJoCo's
observations use (cfrc_ext, cinert, cvel, qfrc_actuator, qfrc_constraint) come from sinew's own
physics (``sinew.Batch``). Every function works on arrays with a leading batch axis.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import gymnasium
import numpy as np

ASSETS = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")


@dataclass
class View:
    """What a task reads of a batch of worlds (all arrays have a leading batch axis)."""

    qpos: np.ndarray
    qvel: np.ndarray
    ctrl: np.ndarray
    xpos: np.ndarray  # (N, nbody, 3)
    xmat: np.ndarray  # (N, nbody, 3, 3)
    xipos: np.ndarray  # (N, nbody, 3): body centres of mass
    xvel: np.ndarray  # (N, nbody, 6): world angular velocity, origin linear velocity
    cfrc_ext: np.ndarray  # (N, nbody, 6)
    qfrc_constraint: np.ndarray  # (N, nv)
    cinert: np.ndarray  # (N, nbody, 10): MuJoCo's cinert
    cvel: np.ndarray  # (N, nbody, 6): MuJoCo's cvel


class Task:
    """Base class: constants of the model that tasks use, and gymnasium's conventions."""

    xml: str = ""
    frame_skip: int = 1
    max_episode_steps: int = 1000

    def __init__(self, model, **kwargs):
        if kwargs:
            raise TypeError(f"{type(self).__name__} got unexpected keyword arguments {sorted(kwargs)}")
        self.model = model
        self.dt = model.timestep * self.frame_skip
        self.qpos0 = model.qpos0
        self.nq, self.nv, self.nu = model.nq, model.nv, model.nu
        self.body_mass = model.body_mass

    # helpers shared by tasks
    @staticmethod
    def planar_info(v: View) -> dict:
        """Where a free-floating body's root is in the ground plane (Ant's and Humanoid's info)."""
        return {"x_position": v.qpos[:, 0].copy(), "y_position": v.qpos[:, 1].copy(),
                "distance_from_origin": np.linalg.norm(v.qpos[:, :2], axis=1)}

    def body_id(self, name: str) -> int:
        return self.model.body_names.index(name)

    def reset_info(self, v: View) -> dict:
        return {}


def uniform(rngs, low, high, size):
    return np.stack([r.uniform(low=low, high=high, size=size) for r in rngs])


def normal(rngs, size):
    return np.stack([r.standard_normal(size) for r in rngs])


class InvertedPendulum(Task):
    xml, frame_skip = "inverted_pendulum.xml", 2

    def __init__(self, model, reset_noise_scale=0.01, **kw):
        super().__init__(model, **kw)
        self.noise = reset_noise_scale

    def obs_dim(self):
        return self.nq + self.nv

    def observe(self, v):
        return np.concatenate([v.qpos, v.qvel], axis=1)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), uniform(rngs, -n, n, self.nv)

    def before(self, v):
        return None

    def after(self, v, before, action, obs):
        terminated = ~np.isfinite(obs).all(axis=1) | (np.abs(obs[:, 1]) > 0.2)
        reward = (~terminated).astype(np.float64)
        return reward, terminated, {"reward_survive": reward}


class InvertedDoublePendulum(Task):
    xml, frame_skip = "inverted_double_pendulum.xml", 5

    def __init__(self, model, healthy_reward=10.0, reset_noise_scale=0.1, **kw):
        super().__init__(model, **kw)
        self.healthy, self.noise = healthy_reward, reset_noise_scale
        self.tip_body = model.site_body[0]
        self.tip_pos = model.site_pos[0]

    def obs_dim(self):
        return 1 + 2 * (self.nq - 1) + self.nv + 1

    def observe(self, v):
        return np.concatenate(
            [
                v.qpos[:, :1],
                np.sin(v.qpos[:, 1:]),
                np.cos(v.qpos[:, 1:]),
                np.clip(v.qvel, -10, 10),
                np.clip(v.qfrc_constraint, -10, 10)[:, :1],
            ],
            axis=1,
        )

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), normal(rngs, self.nv) * n

    def before(self, v):
        return None

    def after(self, v, before, action, obs):
        tip = v.xpos[:, self.tip_body] + v.xmat[:, self.tip_body] @ self.tip_pos
        x, y = tip[:, 0], tip[:, 2]
        terminated = y <= 1
        v1, v2 = v.qvel[:, 1], v.qvel[:, 2]
        dist = 0.01 * x**2 + (y - 2) ** 2
        vel = 1e-3 * v1**2 + 5e-3 * v2**2
        alive = self.healthy * (~terminated)
        return alive - dist - vel, terminated, {"reward_survive": alive, "distance_penalty": -dist, "velocity_penalty": -vel}


class Reacher(Task):
    xml, frame_skip, max_episode_steps = "reacher.xml", 2, 50

    def __init__(self, model, reward_dist_weight=1.0, reward_control_weight=1.0, **kw):
        super().__init__(model, **kw)
        self.wd, self.wc = reward_dist_weight, reward_control_weight
        self.tip, self.target = self.body_id("fingertip"), self.body_id("target")

    def obs_dim(self):
        return 10

    def _vec(self, v):
        c = v.xipos
        return c[:, self.tip] - c[:, self.target]

    def observe(self, v):
        theta = v.qpos[:, :2]
        return np.concatenate([np.cos(theta), np.sin(theta), v.qpos[:, 2:], v.qvel[:, :2], self._vec(v)[:, :2]], axis=1)

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

    def before(self, v):
        return None

    def after(self, v, before, action, obs):
        dist = -np.linalg.norm(self._vec(v), axis=1) * self.wd
        ctrl = -np.square(action).sum(axis=1) * self.wc
        return dist + ctrl, np.zeros(len(dist), bool), {"reward_dist": dist, "reward_ctrl": ctrl}


class _Planar(Task):
    """Hopper, Walker2d, HalfCheetah: forward progress of qpos[0]."""

    clip_qvel = True
    ctrl_weight = 1e-3

    def __init__(self, model, forward_reward_weight=1.0, ctrl_cost_weight=None, reset_noise_scale=5e-3,
                 exclude_current_positions_from_observation=True, **kw):
        super().__init__(model, **kw)
        self.wf = forward_reward_weight
        self.wc = self.ctrl_weight if ctrl_cost_weight is None else ctrl_cost_weight
        self.noise = reset_noise_scale
        self.skip = 1 if exclude_current_positions_from_observation else 0

    def obs_dim(self):
        return self.nq - self.skip + self.nv

    def observe(self, v):
        vel = np.clip(v.qvel, -10, 10) if self.clip_qvel else v.qvel
        return np.concatenate([v.qpos[:, self.skip:], vel], axis=1)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), uniform(rngs, -n, n, self.nv)

    def before(self, v):
        return v.qpos[:, 0].copy()

    def progress(self, v, before):
        return (v.qpos[:, 0] - before) / self.dt

    def reset_info(self, v):
        return {"x_position": v.qpos[:, 0].copy(), "z_distance_from_origin": v.qpos[:, 1] - self.qpos0[1]}


class _Healthy(_Planar):
    healthy_reward_default = 1.0

    def __init__(self, model, healthy_reward=1.0, terminate_when_unhealthy=True, healthy_z_range=(0.7, np.inf),
                 healthy_angle_range=(-0.2, 0.2), **kw):
        super().__init__(model, **kw)
        self.wh, self.terminate = healthy_reward, terminate_when_unhealthy
        self.z_range, self.angle_range = healthy_z_range, healthy_angle_range

    def healthy(self, v):
        z, angle = v.qpos[:, 1], v.qpos[:, 2]
        return (self.z_range[0] < z) & (z < self.z_range[1]) & (self.angle_range[0] < angle) & (angle < self.angle_range[1])

    def after(self, v, before, action, obs):
        xv = self.progress(v, before)
        healthy = self.healthy(v)
        forward = self.wf * xv
        survive = self.wh * healthy
        ctrl = self.wc * np.square(action).sum(axis=1)
        info = {
            "x_position": v.qpos[:, 0].copy(),
            "z_distance_from_origin": v.qpos[:, 1] - self.qpos0[1],
            "x_velocity": xv,
            "reward_forward": forward,
            "reward_ctrl": -ctrl,
            "reward_survive": survive,
        }
        return forward + survive - ctrl, (~healthy) & self.terminate, info


class Hopper(_Healthy):
    xml, frame_skip = "hopper.xml", 4

    def __init__(self, model, healthy_state_range=(-100.0, 100.0), **kw):
        kw.setdefault("healthy_z_range", (0.7, np.inf))
        kw.setdefault("healthy_angle_range", (-0.2, 0.2))
        super().__init__(model, **kw)
        self.state_range = healthy_state_range

    def healthy(self, v):
        state = np.concatenate([v.qpos, v.qvel], axis=1)[:, 2:]
        ok = ((self.state_range[0] < state) & (state < self.state_range[1])).all(axis=1)
        return ok & super().healthy(v)


class Walker2d(_Healthy):
    xml, frame_skip = "walker2d_v5.xml", 4

    def __init__(self, model, **kw):
        kw.setdefault("healthy_z_range", (0.8, 2.0))
        kw.setdefault("healthy_angle_range", (-1.0, 1.0))
        super().__init__(model, **kw)


class HalfCheetah(_Planar):
    xml, frame_skip = "half_cheetah.xml", 5
    clip_qvel, ctrl_weight = False, 0.1

    def __init__(self, model, reset_noise_scale=0.1, **kw):
        super().__init__(model, reset_noise_scale=reset_noise_scale, **kw)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), n * normal(rngs, self.nv)

    def after(self, v, before, action, obs):
        xv = self.progress(v, before)
        forward = self.wf * xv
        ctrl = self.wc * np.square(action).sum(axis=1)
        info = {"x_position": v.qpos[:, 0].copy(), "x_velocity": xv, "reward_forward": forward, "reward_ctrl": -ctrl}
        return forward - ctrl, np.zeros(len(xv), bool), info

    def reset_info(self, v):
        return {"x_position": v.qpos[:, 0].copy()}


class Ant(Task):
    xml, frame_skip = "ant.xml", 5

    def __init__(self, model, forward_reward_weight=1.0, ctrl_cost_weight=0.5, contact_cost_weight=5e-4,
                 healthy_reward=1.0, main_body=1, terminate_when_unhealthy=True, healthy_z_range=(0.2, 1.0),
                 contact_force_range=(-1.0, 1.0), reset_noise_scale=0.1,
                 exclude_current_positions_from_observation=True, include_cfrc_ext_in_observation=True, **kw):
        super().__init__(model, **kw)
        self.wf, self.wc, self.wk, self.wh = forward_reward_weight, ctrl_cost_weight, contact_cost_weight, healthy_reward
        self.main = main_body if isinstance(main_body, int) else self.body_id(main_body)
        self.terminate, self.z_range, self.force_range = terminate_when_unhealthy, healthy_z_range, contact_force_range
        self.noise = reset_noise_scale
        self.skip = 2 if exclude_current_positions_from_observation else 0
        self.cfrc = include_cfrc_ext_in_observation

    def obs_dim(self):
        return self.nq - self.skip + self.nv + (6 * (self.model.nbody - 1) if self.cfrc else 0)

    def contact_forces(self, v):
        return np.clip(v.cfrc_ext, *self.force_range)

    def observe(self, v):
        parts = [v.qpos[:, self.skip:], v.qvel]
        if self.cfrc:
            parts.append(self.contact_forces(v)[:, 1:].reshape(len(v.qpos), -1))
        return np.concatenate(parts, axis=1)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), n * normal(rngs, self.nv)

    def before(self, v):
        return v.xpos[:, self.main, :2].copy()

    def after(self, v, before, action, obs):
        vel = (v.xpos[:, self.main, :2] - before) / self.dt
        state = np.concatenate([v.qpos, v.qvel], axis=1)
        healthy = np.isfinite(state).all(axis=1) & (self.z_range[0] <= v.qpos[:, 2]) & (v.qpos[:, 2] <= self.z_range[1])
        forward = vel[:, 0] * self.wf
        survive = healthy * self.wh
        ctrl = self.wc * np.square(action).sum(axis=1)
        contact = self.wk * np.square(self.contact_forces(v)).sum(axis=(1, 2))
        info = {
            **self.planar_info(v),
            "x_velocity": vel[:, 0],
            "y_velocity": vel[:, 1],
            "reward_forward": forward,
            "reward_ctrl": -ctrl,
            "reward_contact": -contact,
            "reward_survive": survive,
        }
        return forward + survive - ctrl - contact, (~healthy) & self.terminate, info

    def reset_info(self, v):
        return self.planar_info(v)


class Humanoid(Task):
    xml, frame_skip = "humanoid.xml", 5

    def __init__(self, model, forward_reward_weight=1.25, ctrl_cost_weight=0.1, contact_cost_weight=5e-7,
                 contact_cost_range=(-np.inf, 10.0), healthy_reward=5.0, terminate_when_unhealthy=True,
                 healthy_z_range=(1.0, 2.0), reset_noise_scale=1e-2, exclude_current_positions_from_observation=True,
                 include_cinert_in_observation=True, include_cvel_in_observation=True,
                 include_qfrc_actuator_in_observation=True, include_cfrc_ext_in_observation=True, **kw):
        super().__init__(model, **kw)
        self.wf, self.wc, self.wk, self.wh = forward_reward_weight, ctrl_cost_weight, contact_cost_weight, healthy_reward
        self.cost_range, self.terminate, self.z_range = contact_cost_range, terminate_when_unhealthy, healthy_z_range
        self.noise = reset_noise_scale
        self.skip = 2 if exclude_current_positions_from_observation else 0
        self.parts = (include_cinert_in_observation, include_cvel_in_observation,
                      include_qfrc_actuator_in_observation, include_cfrc_ext_in_observation)
        self.gear = model.actuator_gear
        self.act_dof = np.array(model.actuator_dofadr)
        self.ctrlrange = model.actuator_ctrlrange
        self.limited = np.array(model.actuator_ctrllimited)

    def obs_dim(self):
        nb = self.model.nbody - 1
        sizes = (10 * nb, 6 * nb, self.nv - 6, 6 * nb)
        return self.nq - self.skip + self.nv + sum(s for s, on in zip(sizes, self.parts) if on)

    def qfrc_actuator(self, v):
        ctrl = np.where(self.limited, np.clip(v.ctrl, self.ctrlrange[:, 0], self.ctrlrange[:, 1]), v.ctrl)
        out = np.zeros((len(ctrl), self.nv))
        out[:, self.act_dof] = ctrl * self.gear
        return out

    def observe(self, v):
        n = len(v.qpos)
        parts = [v.qpos[:, self.skip:], v.qvel]
        extra = (lambda: v.cinert[:, 1:].reshape(n, -1), lambda: v.cvel[:, 1:].reshape(n, -1),
                 lambda: self.qfrc_actuator(v)[:, 6:], lambda: v.cfrc_ext[:, 1:].reshape(n, -1))
        parts += [f() for f, on in zip(extra, self.parts) if on]
        return np.concatenate(parts, axis=1)

    def reset_state(self, rngs):
        n = self.noise
        return self.qpos0 + uniform(rngs, -n, n, self.nq), uniform(rngs, -n, n, self.nv)

    def mass_center(self, v):
        return np.einsum("b,nbj->nj", self.body_mass, v.xipos)[:, :2] / self.body_mass.sum()

    def before(self, v):
        return self.mass_center(v)

    def after(self, v, before, action, obs):
        vel = (self.mass_center(v) - before) / self.dt
        healthy = (self.z_range[0] < v.qpos[:, 2]) & (v.qpos[:, 2] < self.z_range[1])
        forward = self.wf * vel[:, 0]
        survive = self.wh * healthy
        ctrl = self.wc * np.square(v.ctrl).sum(axis=1)
        contact = np.clip(self.wk * np.square(v.cfrc_ext).sum(axis=(1, 2)), *self.cost_range)
        info = {
            **self.planar_info(v),
            "x_velocity": vel[:, 0],
            "y_velocity": vel[:, 1],
            "reward_survive": survive,
            "reward_forward": forward,
            "reward_ctrl": -ctrl,
            "reward_contact": -contact,
        }
        return forward + survive - ctrl - contact, (~healthy) & self.terminate, info

    def reset_info(self, v):
        return self.planar_info(v)


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
