"""<keyframe>: keys read with the model (absent arrays are qpos0 and zeros, wrong sizes an error
naming the line), Sim.reset(key) and the envs' reset(options={"keyframe": ...})."""

import os

import gymnasium as gym
import numpy as np
import pytest

import sinew
from sinew.tasks import ASSETS

ARM = """<mujoco><worldbody><body><joint name="a" axis="0 1 0"/><geom type="capsule" size=".05" fromto="0 0 0 .4 0 0"/>
  <body pos=".4 0 0"><joint name="b" axis="0 1 0"/><geom size=".05"/></body></body></worldbody>
  <actuator><motor joint="a"/></actuator>
  <keyframe><key name="bent" time="1.5" qpos="0.3 -0.7" qvel="1 2" ctrl="0.5"/><key qpos="0.1 0.2"/></keyframe></mujoco>"""


def test_keys_are_read_with_defaults():
    m = sinew.Model.from_mjcf_string(ARM)
    assert m.key_names == ["bent", ""]
    k = m.keyframe("bent")
    assert k["time"] == 1.5 and list(k["qpos"]) == [0.3, -0.7] and list(k["qvel"]) == [1, 2] and list(k["ctrl"]) == [0.5]
    k = m.keyframe(1)
    assert list(k["qvel"]) == [0, 0] and list(k["ctrl"]) == [0] and k["time"] == 0
    with pytest.raises(ValueError, match="bent"):
        m.keyframe("straight")


def test_a_key_of_the_wrong_size_names_its_line():
    with pytest.raises(sinew.ModelError, match=r"<key> attribute 'qpos' at line 4: expected 2 numbers, got 3"):
        sinew.Model.from_mjcf_string(ARM.replace('qpos="0.1 0.2"', 'qpos="0.1 0.2 0.3"'))


def test_sim_resets_to_a_key_and_steps_as_a_new_sim_there():
    m = sinew.Model.from_mjcf_string(ARM)
    s = sinew.Sim(m)
    s.step(10)
    s.reset(key="bent")
    assert s.time == 1.5 and list(s.qpos) == [0.3, -0.7] and list(s.qvel) == [1, 2] and list(s.ctrl) == [0.5]
    fresh = sinew.Sim(m)
    fresh.set_state(np.concatenate([[1.5], [0.3, -0.7], [1, 2], [0.5]]))
    s.step(20)
    fresh.step(20)
    assert np.array_equal(s.qpos, fresh.qpos)


def test_envs_reset_to_a_keyframe(tmp_path):
    text = open(os.path.join(ASSETS, "hopper.xml")).read()
    key = '<keyframe><key name="crouch" qpos="0 1.1 0 -0.3 -0.4 0.2" qvel="0.5 0 0 0 0 0"/></keyframe></mujoco>'
    path = tmp_path / "hopper_keys.xml"
    path.write_text(text[: text.rindex("</mujoco>")] + key)
    env = gym.make("sinew/Hopper-v0", xml_file=str(path))
    obs, _ = env.reset(seed=0, options={"keyframe": "crouch"})
    np.testing.assert_array_equal(obs, [1.1, 0, -0.3, -0.4, 0.2, 0.5, 0, 0, 0, 0, 0])
    vec = gym.make_vec("sinew/Hopper-v0", num_envs=3, vectorization_mode="vector_entry_point", xml_file=str(path))
    obs, _ = vec.reset(seed=0, options={"keyframe": "crouch"})
    assert (obs == obs[0]).all() and obs[0, 0] == 1.1
