"""Domain randomization: model values drawn per world from the env's own seeded generators.

``params`` maps a field (``sinew.Batch.set_params`` names them: body_mass, geom_friction,
dof_damping, actuator_gear, gravity, ...) to ``(op, low, high)``: each element of the field is
drawn uniformly from [low, high] (broadcast to the field's shape) and the world's value is the
model's ``default × draw`` ("scale"), ``default + draw`` ("add") or the draw itself ("set").
Draws always start from the model's value, so repeated scaling does not compound. World i draws
from its own generator (the one ``reset(seed=...)`` seeds), field by field in the order given,
so the vector env equals single envs seeded ``seed, seed + 1, ...``.

``when``: "reset" (a world draws at each of its resets, before its first observation), "start"
(at its first reset only) or an integer k (every world draws after every k-th env step).
"""

from __future__ import annotations

import gymnasium
import numpy as np
from gymnasium.vector import VectorWrapper

OPS = ("scale", "add", "set")


class ParamSampler:
    """Draws the fields of ``params`` for worlds of a batch of ``model``, one generator each."""

    def __init__(self, model, params: dict):
        self.fields = []
        for field, spec in params.items():
            try:
                op, low, high = spec
            except (TypeError, ValueError):
                raise ValueError(f"{field}: expected (op, low, high), got {spec!r}") from None
            if op not in OPS:
                raise ValueError(f"{field}: op must be one of {OPS}, got {op!r}")
            default = model.param(field)
            try:
                low, high = (np.broadcast_to(np.asarray(x, dtype=np.float64), default.shape) for x in (low, high))
            except ValueError:
                raise ValueError(f"{field}: low and high must broadcast to the field's shape {default.shape}") from None
            if not (np.isfinite(low).all() and np.isfinite(high).all() and (low <= high).all()):
                raise ValueError(f"{field}: low and high must be finite with low <= high")
            self.fields.append((field, op, default, low, high))

    def __call__(self, batch, idx, rngs) -> None:
        """Gives the worlds ``idx`` new values, world ``idx[k]`` drawing from ``rngs[k]``."""
        if len(idx) == 0:
            return
        for field, op, default, low, high in self.fields:
            draw = np.stack([rng.uniform(low, high) for rng in rngs])
            values = default * draw if op == "scale" else default + draw if op == "add" else draw
            batch.set_params(field, values, list(idx))


class _Drawing:
    """What both wrappers share: installing the sampler and drawing every k steps."""

    def _install(self, params: dict, when):
        core = self.env.unwrapped._core
        self._sampler = ParamSampler(core.model, params)
        if when == "reset":
            core.randomize = self._sampler
        elif when == "start":
            fresh = np.ones(core.num_envs, dtype=bool)

            def first(batch, idx, rngs):
                todo = [k for k, i in enumerate(idx) if fresh[i]]
                self._sampler(batch, [idx[k] for k in todo], [rngs[k] for k in todo])
                fresh[list(idx)] = False

            core.randomize = first
        elif isinstance(when, (int, np.integer)) and not isinstance(when, bool) and when >= 1:
            self._every = int(when)
        else:
            raise ValueError(f'when must be "reset", "start" or a positive integer, got {when!r}')
        self._steps = 0

    def _params(self, field: str | None):
        """Every world's values now: of ``field``, or a dict of each randomized field's."""
        batch = self.env.unwrapped._core.batch
        if field is None:
            return {f: batch.params(f) for f, *_ in self._sampler.fields}
        return batch.params(field)

    def _after_step(self, rngs) -> None:
        self._steps += 1
        every = getattr(self, "_every", None)
        if every is not None and self._steps % every == 0:
            core = self.env.unwrapped._core
            self._sampler(core.batch, list(range(core.num_envs)), rngs)


class RandomizeParams(_Drawing, gymnasium.Wrapper):
    """A single sinew env whose model values are drawn from its generator (see the module)."""

    def __init__(self, env: gymnasium.Env, params: dict, when="reset"):
        gymnasium.Wrapper.__init__(self, env)
        self._install(params, when)

    def step(self, action):
        out = self.env.step(action)
        self._after_step([self.env.unwrapped.np_random])
        return out

    def params(self, field: str | None = None):
        """The env's values now (what it drew, for a randomized field): ``field``'s array in the
        field's shape (any field ``Batch.set_params`` names), or a dict of each randomized field's."""
        drawn = self._params(field)
        return {k: v[0] for k, v in drawn.items()} if field is None else drawn[0]


class VectorRandomizeParams(_Drawing, VectorWrapper):
    """A native sinew vector env whose worlds' model values are drawn from their generators."""

    def __init__(self, env, params: dict, when="reset"):
        VectorWrapper.__init__(self, env)
        self._install(params, when)

    def step(self, actions):
        out = self.env.step(actions)
        self._after_step(self.env.unwrapped._rngs)
        return out

    def params(self, field: str | None = None):
        """Every world's values now (what each drew, for a randomized field): ``field``'s array,
        (num_envs, ...) (any field ``Batch.set_params`` names), or a dict of each randomized field's."""
        return self._params(field)
