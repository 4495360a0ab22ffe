"""Mutated MJCF (gymnasium's own files with values replaced by NaN, inf, huge, negative or garbage,
spans deleted, numbers scaled): loading either succeeds or raises ModelError, and what loads steps
to a finite state or raises SimulationError. A panic would surface as pyo3's PanicException, which
is not an Exception subclass, and fail the test."""

import random
import re
import warnings

import numpy as np
import pytest

import sinew
from sinew.tasks import ASSETS

FILES = ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid", "humanoidstandup", "reacher", "swimmer",
         "inverted_pendulum", "inverted_double_pendulum"]
VALUES = ["nan", "inf", "-inf", "-1", "0", "-0", "1e308", "-1e308", "1e-320", "1e20", "abc", "", "1 2",
          "0 0 0", "0 0 1", "2 2 2", "0 0 0 0 0 0 0 0 0 0"]


def mutate(xml: str, rnd: random.Random) -> str:
    kind = rnd.randrange(4)
    if kind == 1:  # delete a span
        i = rnd.randrange(len(xml))
        return xml[:i] + xml[i + rnd.randrange(1, 40):]
    if kind == 2:  # scale a number
        a = rnd.choice(list(re.finditer(r"-?\d+\.?\d*", xml)))
        return xml[:a.start()] + repr(float(a.group()) * rnd.choice([-1, 0, 1e6, 1e-9, 3])) + xml[a.end():]
    for _ in range(1 if kind == 0 else 5):  # replace attribute values
        a = rnd.choice(list(re.finditer(r'(\w+)="([^"]*)"', xml)))
        xml = xml[:a.start(2)] + rnd.choice(VALUES) + xml[a.end(2):]
    return xml


@pytest.mark.parametrize("seed", range(4))
def test_mutated_mjcf_raises_model_error_or_simulates_finitely(seed):
    rnd = random.Random(seed)
    sources = {f: open(f"{ASSETS}/{f}.xml").read() for f in FILES}
    loaded = rejected = 0
    for _ in range(500):
        name = rnd.choice(FILES)
        xml = mutate(sources[name], rnd)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                m = sinew.Model.from_mjcf_string(xml)
        except sinew.ModelError:
            rejected += 1
            continue
        loaded += 1
        sim = sinew.Sim(m)
        sim.ctrl[:] = 1.0
        try:
            sim.step(200)
            assert np.isfinite(sim.qpos).all() and np.isfinite(sim.qvel).all(), name
        except sinew.SimulationError:
            pass
        if m.nq == 0:  # Batch refuses a model with nothing to simulate (a ValueError)
            continue
        b = sinew.Batch(m, 2, num_threads=1)
        b.ctrl[:] = -1.0
        b.step(20)
        for arr in (b.qpos, b.qvel, b.xpos, b.xipos, b.cfrc_ext, b.cinert, b.cvel):
            assert np.isfinite(arr).all(), name
    # both outcomes are exercised
    assert loaded > 50 and rejected > 50
