"""The declaration every Playground task of ``sinew.playground`` makes."""

from __future__ import annotations

import numpy as np


class Task:
    """One Playground task: its model file, timing and action mapping, and how it resets, observes
    and rewards N worlds at once (arrays with one row per world). ``rngs`` holds one numpy
    generator per world of the rows it is given."""

    #: The model file, under Playground's assets directory (``sinew.playground.assets_dir()``).
    xml: str = ""
    #: Physics and control timesteps (Playground's ``sim_dt`` and ``ctrl_dt``).
    sim_dt: float = 0.004
    ctrl_dt: float = 0.02
    #: Control steps per episode.
    episode_length: int = 1000
    #: Position targets are ``default_pose + action_scale * action``.
    action_scale: float = 0.5
    #: The free camera's settings for ``render()`` without a camera.
    camera: dict = {}
    #: The model camera pixel observations use by default.
    pixels_camera: str = "track"
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

    def setup(self, model, num_envs: int) -> None:
        """Reads what the task needs from the compiled model and allocates its per-world state."""

    def model_edits(self) -> dict:
        """The per-model values Playground's env sets after loading (``Batch.set_params`` fields)."""
        return {}

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """Playground's domain randomization for the worlds ``idx``."""

    def reset(self, idx: np.ndarray, rngs: list) -> tuple[np.ndarray, np.ndarray]:
        """The initial (qpos, qvel) of the worlds ``idx``; resets their task state."""
        raise NotImplementedError

    #: Physics steps a reset lets the worlds settle for, holding the servos at the drawn pose.
    settle_steps: int = 0
    #: Whether ``after_step`` reads joint accelerations (``sim.qacc``).
    needs_qacc: bool = False

    def motor_targets(self, actions: np.ndarray, qpos: np.ndarray, ctrl: np.ndarray) -> np.ndarray:
        """The position servos' targets of actions in [-1, 1] at the worlds' state (qpos) and
        last targets (ctrl): here default pose + scale · action."""
        return self.default_pose + actions * self.action_scale

    def observe(self, sim, idx: np.ndarray, rngs: list) -> tuple[np.ndarray, np.ndarray]:
        """The (state, privileged_state) rows of the worlds ``idx`` at ``sim``'s readings."""
        raise NotImplementedError

    def after_step(self, sim, actions: np.ndarray, idx: np.ndarray, rngs: list):
        """Advances the task state of the stepped worlds ``idx`` from ``sim``'s readings:
        (state, privileged_state, reward, terminated, reward terms by name)."""
        raise NotImplementedError
