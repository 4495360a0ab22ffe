"""training/playground.py: the command and body velocity it reads for the tracking error lie where
each task puts them (the command in the state, the clean body-frame velocity in the privileged
state)."""

import importlib.util
import pathlib

import gymnasium as gym
import numpy as np
import pytest

import sinew  # noqa: F401  (registers the envs)

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("playground_training", ROOT / "training" / "playground.py")
training = importlib.util.module_from_spec(spec)
spec.loader.exec_module(training)

#: One task per entry of the script's layouts, with the sensor of its body-frame velocity.
TASKS = {"Go1": ("Go1JoystickFlatTerrain", "local_linvel"), "G1": ("G1JoystickFlatTerrain", "local_linvel_pelvis"),
         "T1": ("T1JoystickFlatTerrain", "local_linvel"), "BerkeleyHumanoid": ("BerkeleyHumanoidJoystickFlatTerrain", "local_linvel"),
         "Apollo": ("ApolloJoystickFlatTerrain", "local_linvel"), "SpotFlatTerrainJoystick": ("SpotFlatTerrainJoystick", "local_linvel")}


@pytest.mark.parametrize("robot", sorted(training.LAYOUT))
def test_the_tracking_error_reads_the_command_and_the_body_velocity(robot):
    task, sensor = TASKS[robot]
    env = gym.make(f"sinew/playground-{task}-v0")
    env.reset(seed=0)
    obs, _, _, _, info = env.step(env.action_space.sample())
    command, linvel = training.layout(task)
    np.testing.assert_allclose(obs[command], info["command"], atol=1e-6)
    core = env.unwrapped._core
    k = core.model.sensor_names.index(sensor)
    np.testing.assert_allclose(info["privileged_state"][linvel], core.batch.read_sensors([k])[0], atol=1e-5)


def test_a_task_without_a_body_velocity_is_refused():
    with pytest.raises(ValueError, match="joystick"):
        training.layout("SpotJoystickGaitTracking")
