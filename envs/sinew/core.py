"""What every task's worlds share: one ``sinew.Batch``, checked actions, and resets that seed
each world's physics stream from its generator."""

from __future__ import annotations

import numpy as np

from sinew._core import MAX_STATE, Batch

#: Largest accepted action magnitude: the divergence bound on states.
MAX_ACTION = MAX_STATE


def camera_index(model, camera) -> int:
    """A model camera's index from its name or index (-1: the free camera); ``ValueError`` for
    one the model does not have."""
    cams = model.camera_names
    if isinstance(camera, str):
        if camera not in cams:
            raise ValueError(f"no camera named {camera!r}; the model's cameras: {[c for c in cams if c]}")
        camera = cams.index(camera)
    if isinstance(camera, bool) or not isinstance(camera, (int, np.integer)) or not -1 <= camera < len(cams):
        raise ValueError(f"camera_id must be -1 (free camera) or one of 0..{len(cams) - 1}, got {camera!r}")
    return int(camera)


class Worlds:
    """N worlds of one model: the batch, and the generator that last seeded each world."""

    def __init__(self, model, num_envs: int, num_threads: int | None = None):
        self.model = model
        self.num_envs = num_envs
        #: Each env's number of actions (the model's controls unless the task maps fewer).
        self.action_size = model.nu
        self.batch = Batch(model, num_envs, seed=0, num_threads=num_threads)
        # the generator that last seeded each world's physics stream
        self._seeded_by: list = [None] * num_envs
        #: Called as ``randomize(batch, idx, rngs)`` at each reset, before the worlds' first
        #: observation (``sinew.randomize.RandomizeParams`` sets it).
        self.randomize = None

    @property
    def dt(self) -> float:
        """Simulated time per env step."""
        return self.task.dt

    def check_actions(self, actions, single: bool = False) -> np.ndarray:
        """The actions as an (N, nu) float64 array; ``ValueError`` for a wrong shape or a value
        that is not finite or beyond ±MAX_ACTION. `single`: one env's action, (nu,) only."""
        a = np.asarray(actions, dtype=np.float64)
        shape = (self.num_envs, self.action_size)
        if single and a.shape != shape[1:]:
            raise ValueError(f"action shape mismatch: expected {shape[1:]}, got {a.shape}")
        if a.shape != shape:
            if self.num_envs == 1 and a.shape == shape[1:]:
                a = a[None]
            else:
                raise ValueError(f"action shape mismatch: expected {shape[1:] if self.num_envs == 1 else shape}, got {a.shape}")
        # beyond the divergence bound an action's control cost alone can overflow the reward
        within = np.abs(a) <= MAX_ACTION
        if not within.all():
            bad = ~within.all(axis=1)
            which = "" if self.num_envs == 1 else f" for env indices {np.flatnonzero(bad).tolist()}"
            raise ValueError(f"actions are not finite (NaN or inf) or beyond ±{MAX_ACTION:g}{which}")
        return a

    def reset_batch(self, idx: np.ndarray, rngs: list, qpos: np.ndarray, qvel: np.ndarray) -> None:
        """Sets the worlds `idx` (ascending) to (qpos, qvel), one row each. A world's physics
        stream (its random friction tangents) is seeded from its generator (``rngs``, in the same
        order) the first time that generator resets it, and continues through the episodes that
        follow."""
        fresh = [k for k, (i, r) in enumerate(zip(idx, rngs)) if self._seeded_by[i] is not r]
        seeds = [int(rngs[k].integers(2**63)) for k in fresh]
        for k in fresh:
            self._seeded_by[idx[k]] = rngs[k]
        if self.randomize is not None:
            self.randomize(self.batch, idx, rngs)
        if len(fresh) in (0, len(idx)):
            mask = np.zeros(self.num_envs, dtype=bool)
            mask[idx] = True
            self.batch.reset(mask, seeds or None, qpos, qvel)
            return
        # some worlds re-seeded, some continuing: one call each
        rows = np.zeros(len(idx), dtype=bool)
        rows[fresh] = True
        for part, part_seeds in ((rows, seeds), (~rows, None)):
            mask = np.zeros(self.num_envs, dtype=bool)
            mask[idx[part]] = True
            self.batch.reset(mask, part_seeds, qpos[part], qvel[part])

    def obs_cache(self):
        """What the observation keeps beyond the worlds' states (for pickling); None here."""
        return None

    def restore_obs(self, cache) -> None:
        """Takes back what ``obs_cache`` gave."""
