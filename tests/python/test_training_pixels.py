"""training/pixels.py: the replay's n-step windows stay within an episode and sum its discounted
rewards; a short DrQ-v2 run on sinew's pixels completes an episode and writes its record."""

import importlib.util
import json
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load():
    spec = importlib.util.spec_from_file_location("pixels", ROOT / "training" / "pixels.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_n_step_windows_stay_within_an_episode():
    pixels = load()
    replay = pixels.Replay(40, (1, 2, 2), 1, n=3, gamma=0.5)
    for t in range(40):
        # episodes of 10 steps; reward = step index, next_obs marks the step
        replay.add(np.zeros((1, 2, 2)), [0.0], float(t), np.full((1, 2, 2), t), t // 10)
    obs, action, reward, discount, next_obs = replay.sample(np.random.default_rng(0), 500)
    last = next_obs[:, 0, 0, 0].astype(int)
    first = last - 2
    assert (first // 10 == last // 10).all(), "a window crossed an episode's end"
    assert np.allclose(reward, first + 0.5 * (first + 1) + 0.25 * (first + 2))
    assert np.allclose(discount, 0.125)


def test_a_short_run_on_sinew_writes_its_curve(tmp_path, monkeypatch):
    pixels = load()
    monkeypatch.setattr(sys, "argv", ["pixels.py", "--task", "cartpole-swingup", "--steps", "520", "--seed-steps", "500",
                                      "--batch", "8", "--hidden", "16", "--out", str(tmp_path)])
    pixels.main()
    record = json.loads((tmp_path / "sinew_cartpole-swingup_0.json").read_text())
    assert record["frames"] == 1040 and len(record["curve"]) == 1
    episode = record["curve"][0]
    assert episode["frames"] == 1000 and np.isfinite(episode["return"]) and 0 <= episode["env_s"] <= record["wall_s"]
