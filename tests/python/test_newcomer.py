"""The slips a new user makes past the first steps, each answered by name: misspelt keywords,
absurd options, wrong shapes, missing files; and what they reach for next (a model's full state,
the values domain randomization drew, videos at the simulation's pace)."""

import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest

import sinew
from sinew.tasks import ASSETS


@pytest.mark.parametrize("make", [
    lambda: gym.make("sinew/dmc-cartpole-balance-v0", from_pixel=True),
    lambda: gym.make_vec("sinew/dmc-walker-walk-v0", num_envs=2, vectorization_mode="vector_entry_point", from_pixel=True),
    lambda: __import__("sinew.sb3").sb3.make_vec_env("sinew/dmc-walker-walk-v0", n_envs=2, from_pixel=True),
])
def test_a_misspelt_keyword_on_a_dm_control_env_is_named(make):
    with pytest.raises(TypeError, match="unexpected keyword argument 'from_pixel'.*from_pixels"):
        make()


def test_a_dm_control_task_keeps_its_own_keyword():
    a, b = gym.make("sinew/dmc-lqr-lqr_2_1-v0", model_seed=3), gym.make("sinew/dmc-lqr-lqr_2_1-v0", model_seed=4)
    assert not np.array_equal(a.unwrapped._core.model.param("jnt_stiffness"), b.unwrapped._core.model.param("jnt_stiffness"))
    with pytest.raises(TypeError, match="'model_sed'.*model_seed"):
        gym.make("sinew/dmc-lqr-lqr_2_1-v0", model_sed=3)


@pytest.mark.parametrize("limit", [-1, 0, float("nan"), "10"])
def test_a_dm_control_time_limit_must_be_positive(limit):
    with pytest.raises(ValueError, match="time_limit must be a positive"):
        gym.make("sinew/dmc-cartpole-balance-v0", time_limit=limit)


def test_the_sb3_env_plays_videos_at_the_simulations_pace():
    import sinew.sb3

    env = sinew.sb3.make_vec_env("sinew/Humanoid-v0", n_envs=1)
    single = gym.make("sinew/Humanoid-v0")
    assert env.get_attr("metadata")[0]["render_fps"] == single.metadata["render_fps"] == 67


@pytest.mark.parametrize("args, said", [
    (["--width", "0"], "--width must be 1.."),
    (["--height", "100000"], "--height must be 1.."),
    (["--seconds", "-1"], "--seconds must be a positive"),
    (["--seconds", "nan"], "--seconds must be a positive"),
    (["--video", "x.txt"], ".mp4 or .gif"),
    (["--camera", "nope"], "--camera chooses the view of --video"),
    (["--camera", "nope", "--video", "x.mp4"], "has no camera 'nope'.*'track'"),
    (["--camera", "7", "--video", "x.mp4"], "has no camera '7'"),
])
def test_the_command_line_names_a_bad_option_without_a_traceback(args, said, tmp_path):
    out = subprocess.run([sys.executable, "-m", "sinew", *args], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert out.returncode == 2, out.stdout
    assert "Traceback" not in out.stderr
    assert __import__("re").search(said, out.stderr), out.stderr
    assert not list(tmp_path.iterdir())


def test_a_bad_gravity_names_the_element_that_is_bad():
    b = sinew.Batch(sinew.Model.from_mjcf(f"{ASSETS}/hopper.xml"), 2)
    with pytest.raises(ValueError, match=r"gravity\[2\] = NaN"):
        b.set_params("gravity", [0, 0, np.nan])
    with pytest.raises(ValueError, match=r"geom_friction\[1, 2\] = inf"):
        f = b.params("geom_friction")[0].copy()
        f[1, 2] = np.inf
        b.set_params("geom_friction", f)
    with pytest.raises(ValueError, match=r"body_mass\[3\] = -1"):
        b.set_params("body_mass", np.where(np.arange(b.model.nbody) == 3, -1.0, 1.0))


def test_many_model_warnings_arrive_as_one_line_with_the_details_on_the_model(tmp_path):
    # a hopper whose 25 textures name image files, which sinew's renderer does not draw
    textures = "".join(f'<texture name="t{i}" type="2d" file="t{i}.png"/>' for i in range(25))
    xml = open(f"{ASSETS}/hopper.xml").read().replace("<asset>", "<asset>" + textures)
    (tmp_path / "hopper.xml").write_text(xml)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        env = gym.make("sinew/Hopper-v0", xml_file=str(tmp_path / "hopper.xml"))
    ours = [x for x in w if issubclass(x.category, sinew.ModelWarning)]
    assert len(ours) == 1
    model = env.unwrapped._core.model
    assert len(model.warnings) == 25
    assert "25 model features" in str(ours[0].message) and "Model.warnings" in str(ours[0].message)
    assert "25 times, first <texture> 't0'" in str(ours[0].message)


def test_a_missing_model_file_is_a_file_not_found_error(tmp_path):
    for load in (sinew.Model.from_mjcf, sinew.Model.from_urdf):
        with pytest.raises(FileNotFoundError) as e:
            load(str(tmp_path / "nope.xml"))
        assert "nope.xml" in str(e.value) and e.value.errno == 2
    with pytest.raises(FileNotFoundError):
        gym.make("sinew/Hopper-v0", xml_file=str(tmp_path / "nope.xml"))


def test_a_single_env_takes_its_action_shape_only():
    env = gym.make("sinew/Hopper-v0")
    env.reset(seed=0)
    for bad in (np.zeros((1, 3)), np.zeros(4), np.zeros(())):
        with pytest.raises(ValueError, match=r"expected \(3,\)"):
            env.step(bad)
    env.step(np.zeros(3))


def test_the_envs_data_reads_and_sets_activations():
    env = gym.make("sinew/dmc-quadruped-walk-v0")
    env.reset(seed=0)
    data = env.unwrapped.data
    assert data.act.shape == (env.unwrapped._core.model.na,) == (12,)
    for _ in range(3):
        env.step(env.action_space.sample())
    assert np.abs(data.act).max() > 0
    saved = (data.qpos.copy(), data.qvel.copy(), data.act.copy())
    after = env.step(np.zeros(env.action_space.shape))[0]
    data.qpos[:], data.qvel[:], data.act[:] = saved
    env.unwrapped.data.forward()
    assert np.array_equal(env.step(np.zeros(env.action_space.shape))[0], after)


def test_the_values_a_world_drew_are_read_from_the_wrapper():
    params = {"body_mass": ("scale", 0.5, 1.5), "gravity": ("add", -1.0, 1.0)}
    vec = sinew.VectorRandomizeParams(gym.make_vec("sinew/Hopper-v0", num_envs=3, vectorization_mode="vector_entry_point"), params)
    vec.reset(seed=0)
    drawn = vec.params()
    assert set(drawn) == set(params) and drawn["body_mass"].shape == (3, vec.unwrapped._core.model.nbody)
    assert np.array_equal(vec.params("body_mass"), vec.unwrapped._core.batch.params("body_mass"))
    assert len({row.tobytes() for row in drawn["body_mass"]}) == 3
    single = sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), params)
    single.reset(seed=0)
    assert np.array_equal(single.params("body_mass"), drawn["body_mass"][0])
    assert single.params("dof_damping").shape == (single.unwrapped._core.model.nv,)


def test_a_far_checker_floor_blends_instead_of_aliasing():
    """Checks smaller than a pixel are averaged over it: a 160 × 160 frame of the Ant's checker
    floor is within a few grey levels of the same view drawn 8× finer and averaged down, where
    point-sampled checks (moiré) are 25 levels off in the far half."""
    b = sinew.Batch(sinew.Model.from_mjcf(f"{ASSETS}/ant.xml"), 1)
    small = b.render(160, 160, worlds=[0])[0].astype(float)
    fine = b.render(1280, 1280, worlds=[0])[0].astype(float).reshape(160, 8, 160, 8, 3).mean(axis=(1, 3))
    err = np.abs(small - fine).mean(axis=2)
    assert err[:60].mean() < 5 and err.mean() < 3, (err[:60].mean(), err.mean())
