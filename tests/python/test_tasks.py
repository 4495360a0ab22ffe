"""Each task's declaration (src/tasks/, read through sinew._core.task_specs) against its gymnasium
v5 twin: the same model file, frame_skip, episode length, camera, keyword arguments with the same
defaults; and the reset info its declaration names, with the twin's values at the same state."""

import inspect
import warnings

import gymnasium as gym
import numpy as np
import pytest

import sinew
from sinew.tasks import TASKS

NAMES = list(TASKS)
#: keywords every MuJoCo env takes that are not the task's (sinew's env takes them too)
ENV_KEYWORDS = {"self", "xml_file", "frame_skip", "default_camera_config", "kwargs"}


def twin(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gym.make(f"{name}-v5")


@pytest.mark.parametrize("name", NAMES)
def test_declaration_matches_the_twins_constructor(name):
    spec = TASKS[name].spec
    ref = twin(name)
    sig = inspect.signature(type(ref.unwrapped).__init__).parameters
    assert spec["xml"] == sig["xml_file"].default
    assert spec["frame_skip"] == sig["frame_skip"].default
    assert spec["max_episode_steps"] == ref.spec.max_episode_steps
    defaults = {k: p.default for k, p in sig.items() if k not in ENV_KEYWORDS}
    assert list(spec["params"]) == list(defaults)
    for k, v in spec["params"].items():
        assert v == (tuple(defaults[k]) if isinstance(defaults[k], (tuple, list)) else defaults[k]), k
    if name != "InvertedDoublePendulum":  # its twin defines a camera but passes None
        camera = sig["default_camera_config"].default or {}  # Swimmer-v5 has none
        assert set(spec["camera"]) == set(camera)
        for k, v in camera.items():
            assert np.array_equal(np.asarray(spec["camera"][k]), np.asarray(v)), k


@pytest.mark.parametrize("name", NAMES)
def test_reset_info_is_the_twins_at_the_same_state(name):
    env, ref = gym.make(f"sinew/{name}-v0"), twin(name)
    _, info = env.reset(seed=3)
    _, ref_info = ref.reset(seed=3)
    assert set(info) == set(TASKS[name].spec["reset_info"])
    assert set(info) <= set(env.unwrapped._core.info_names)
    for k, v in info.items():
        assert v == pytest.approx(ref_info[k], rel=1e-12, abs=1e-12), k


def test_unknown_task_keyword_names_it():
    m = sinew.Model.from_mjcf(f"{sinew.tasks.ASSETS}/ant.xml")
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        TASKS["Ant"](m, colour=1)
    assert TASKS["Ant"](m, main_body="torso").params()["main_body"] == 1
