"""What a new user meets first, from a fresh clone: the README's commands and the messages of
their first mistakes."""

import os
import pathlib
import subprocess
import re
import sys

import gymnasium as gym
import numpy as np
import pytest

import sinew

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_the_video_extra_brings_what_record_video_needs():
    video = re.search(r"^video = \[(.*)\]$", (ROOT / "pyproject.toml").read_text(), re.M)
    # gymnasium's RecordVideo raises DependencyNotInstalled without moviepy
    assert video and '"moviepy"' in video.group(1)


def test_an_unknown_keyword_names_only_the_callers_keywords():
    with pytest.raises(TypeError) as e:
        gym.make("sinew/Hopper-v0", foo=1)
    assert "'foo'" in str(e.value)
    assert "task" not in str(e.value)
    with pytest.raises(TypeError) as e:
        gym.make_vec("sinew/Hopper-v0", num_envs=2, vectorization_mode="vector_entry_point", foo=1)
    assert "task" not in str(e.value)


def test_a_single_envs_bad_action_names_no_env_indices():
    env = gym.make("sinew/Hopper-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError) as e:
        env.step(np.full(3, np.nan))
    assert "env indices" not in str(e.value)
    venv = gym.make_vec("sinew/Hopper-v0", num_envs=3, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    a = np.zeros((3, 3))
    a[1, 0] = np.inf
    with pytest.raises(ValueError, match=r"env indices \[1\]"):
        venv.step(a)


def test_an_error_in_a_model_file_names_the_file(tmp_path):
    bad = tmp_path / "my_hopper.xml"
    bad.write_text('<mujoco>\n<worldbody><body><joint/><geom size="a"/></body></worldbody></mujoco>')
    with pytest.raises(sinew.ModelError, match="my_hopper.xml: <geom> attribute 'size' at line 2") as e:
        gym.make("sinew/Hopper-v0", xml_file=str(bad))
    assert e.value.line == 2
    with pytest.raises(sinew.ModelError, match="my_hopper.xml"):
        sinew.Model.from_mjcf(str(bad))


def test_the_one_tangent_friction_keeps_its_old_name():
    m = sinew.Model.from_mjcf(f"{sinew.tasks.ASSETS}/hopper.xml")
    assert m.with_options(friction="one_tangent").friction == "one_tangent"
    assert m.with_options(friction="seed").friction == "one_tangent"
    with pytest.raises(ValueError, match="one_tangent"):
        m.with_options(friction="cone")
    env = gym.make("sinew/Hopper-v0", friction="seed")
    assert env.unwrapped.model.friction == "one_tangent"


def test_check_env_on_a_headless_machine_prints_no_display_error():
    code = ("import gymnasium as gym, sinew; from gymnasium.utils.env_checker import check_env; "
            "check_env(gym.make('sinew/Hopper-v0').unwrapped)")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "XDG_RUNTIME_DIR", "SDL_VIDEODRIVER")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "XDG_RUNTIME_DIR" not in out.stdout + out.stderr
    assert "no display" in out.stderr


def test_evaluate_names_the_runs_there_are_when_the_path_is_wrong(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "training" / "evaluate.py"), "runs/nowhere/ppo_0"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 2
    assert "holds no finished run" in out.stderr and "Traceback" not in out.stderr
