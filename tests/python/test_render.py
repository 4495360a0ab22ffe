"""Rendering through the gymnasium layer: the twin's keywords and outputs, the tools that use
them (SB3's make_vec_env, RecordVideo, HumanRendering, videos), bad input, and depth against
MuJoCo's own ray casts from the twin's camera (no GL needed; benches/render_gallery.py compares
with MuJoCo's OpenGL renderer where mesa is installed)."""

import os
import warnings

import gymnasium as gym
import numpy as np
import pytest

import sinew
from conftest import gym_model_path

NAMES = ["InvertedPendulum", "InvertedDoublePendulum", "Reacher", "Hopper", "Walker2d", "HalfCheetah", "Ant", "Humanoid"]


@pytest.mark.parametrize("name", NAMES)
def test_every_env_renders_what_the_twin_returns(name):
    env = gym.make(f"sinew/{name}-v0", render_mode="rgbd_tuple", width=64, height=48)
    env.reset(seed=0)
    rgb, depth = env.render()
    assert rgb.shape == (48, 64, 3) and rgb.dtype == np.uint8
    assert depth.shape == (48, 64) and depth.dtype == np.float32
    assert 0 < depth.min() and depth.max() <= 1
    assert rgb.std() > 5, "the frame shows something"
    twin_meta = gym.make(f"{name}-v5").unwrapped.metadata
    assert env.unwrapped.metadata == twin_meta
    rgb2 = gym.make(f"sinew/{name}-v0", render_mode="rgb_array", width=64, height=48)
    rgb2.reset(seed=0)
    assert np.array_equal(rgb2.render(), rgb), "the same frame in both modes"


def test_no_render_mode_warns_and_returns_none():
    env = gym.make("sinew/Hopper-v0").unwrapped
    env.reset(seed=0)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        assert env.render() is None
    assert any("render mode" in str(x.message) for x in w)


@pytest.mark.parametrize("kwargs, words", [
    ({"render_mode": "rgb"}, "rgb_array"),
    ({"render_mode": "rgb_array", "width": 0}, "width"),
    ({"render_mode": "rgb_array", "height": 10**6}, "height"),
    ({"render_mode": "rgb_array", "camera_name": "nope"}, "track"),
    ({"render_mode": "rgb_array", "camera_id": 7}, "camera_id"),
    ({"render_mode": "rgb_array", "camera_id": 0, "camera_name": "track"}, "not both"),
])
def test_bad_render_arguments_raise_value_errors_naming_the_choices(kwargs, words):
    with pytest.raises(ValueError, match=words):
        gym.make("sinew/Hopper-v0", **kwargs)


def test_model_cameras_by_name_and_id_give_the_same_frame():
    a = gym.make("sinew/Hopper-v0", render_mode="rgb_array", camera_name="track", width=40, height=40)
    b = gym.make("sinew/Hopper-v0", render_mode="rgb_array", camera_id=0, width=40, height=40)
    a.reset(seed=1), b.reset(seed=1)
    assert np.array_equal(a.render(), b.render())


def test_stock_sb3_make_vec_env_and_its_images():
    from stable_baselines3.common.env_util import make_vec_env

    venv = make_vec_env("sinew/Hopper-v0", n_envs=2, env_kwargs={"width": 32, "height": 32})
    venv.reset()
    assert venv.render().shape == (64, 32, 3)  # SB3 tiles the two frames


def test_sinew_sb3_adapter_and_native_vector_env_draw_each_world():
    from sinew.sb3 import make_vec_env

    venv = make_vec_env("sinew/Ant-v0", n_envs=3, render_mode="rgb_array", width=24, height=16)
    venv.reset()
    imgs = venv.get_images()
    assert len(imgs) == 3 and imgs[0].shape == (16, 24, 3)
    vec = gym.make_vec("sinew/Ant-v0", num_envs=3, vectorization_mode="vector_entry_point", render_mode="rgb_array",
                       width=24, height=16)
    vec.reset(seed=0)
    frames = vec.render()
    assert isinstance(frames, tuple) and len(frames) == 3
    # world i of the vector env is the single env seeded seed + i
    single = gym.make("sinew/Ant-v0", render_mode="rgb_array", width=24, height=16)
    single.reset(seed=2)
    assert np.array_equal(frames[2], single.render())


def test_record_video_writes_a_file(tmp_path):
    from gymnasium.wrappers import RecordVideo

    env = RecordVideo(gym.make("sinew/Hopper-v0", render_mode="rgb_array", width=64, height=64), str(tmp_path),
                      episode_trigger=lambda e: True, disable_logger=True)
    env.reset(seed=0)
    for _ in range(10):
        env.step(env.action_space.sample())
    env.close()
    files = [f for f in os.listdir(tmp_path) if f.endswith(".mp4")]
    assert files and os.path.getsize(tmp_path / files[0]) > 0


HUMAN = """
import gymnasium as gym, pygame, sinew
from gymnasium.wrappers import HumanRendering
env = gym.make("sinew/Hopper-v0", render_mode="human", width=32, height=32)
env.reset(seed=0)
env.step(env.action_space.sample())  # draws, as the twin's step does in human mode
assert pygame.display.get_surface().get_size() == (32, 32)
env.close()
env = HumanRendering(gym.make("sinew/Hopper-v0", render_mode="rgb_array", width=32, height=32))
env.reset(seed=0)
env.step(env.action_space.sample())
env.close()
print("ok")
"""


def test_human_mode_draws_a_window_through_pygame():
    # in its own process: SDL's dummy display (no screen here), and pygame's GL stays out of the
    # process that runs MuJoCo's renderer
    import subprocess
    import sys

    r = subprocess.run([sys.executable, "-c", HUMAN], capture_output=True, text=True, env={**os.environ, "SDL_VIDEODRIVER": "dummy"})
    assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stderr


def test_batch_renders_a_subset_as_the_whole_does():
    m = sinew.Model.from_mjcf(gym_model_path("ant"))
    b = sinew.Batch(m, 6)
    b.qpos[:, 0] = np.arange(6) * 0.3
    whole = b.render(30, 20, worlds=None)
    assert whole.shape == (6, 20, 30, 3)
    some = b.render(30, 20, worlds=[1, 4])
    assert np.array_equal(some, whole[[1, 4]])
    mask = np.zeros(6, dtype=bool)
    mask[[0, 5]] = True
    assert np.array_equal(b.render(30, 20, worlds=mask), whole[[0, 5]])
    with pytest.raises(ValueError, match="out of range"):
        b.render(30, 20, worlds=[6])
    with pytest.raises(ValueError, match="width"):
        b.render(0, 20)
    with pytest.raises(ValueError, match="no camera named"):
        b.render(30, 20, camera="nope")
    b.qpos[2, 0] = np.nan
    with pytest.raises(ValueError, match="world 2"):
        b.render(30, 20)


def test_a_diverged_world_renders_its_reset_state():
    env = gym.make("sinew/Hopper-v0", render_mode="rgb_array", width=32, height=32).unwrapped
    env.reset(seed=0)
    fresh = sinew.Batch(env.model, 1).render(32, 32, env.viewer.camera(env.data_qpos))[0]
    env._core.batch.qpos[0, 1] = 1e300  # the next step finds the world diverged and resets it
    _, _, terminated, _, info = env.step(env.action_space.sample() * 0)
    assert terminated and info["sim_diverged"]
    assert np.array_equal(env.render(), fresh)


def test_python_m_sinew_records_a_video(tmp_path):
    import subprocess
    import sys

    out = tmp_path / "run.mp4"
    r = subprocess.run([sys.executable, "-m", "sinew", gym_model_path("hopper"), "--seconds", "0.2", "--video", str(out),
                        "--width", "64", "--height", "64"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 0 and "wrote 6 frames" in r.stdout
    r = subprocess.run([sys.executable, "-m", "sinew", str(tmp_path / "missing.xml")], capture_output=True, text=True)
    assert r.returncode != 0 and r.stderr.strip().count("\n") == 0 and "missing.xml" in r.stderr


def mujoco_view(twin):
    """The twin's default camera as MuJoCo computes it (``mjv_updateScene``, no GL needed): the
    free camera gymnasium's viewer sets up at its first frame (median geom centre, the model's
    extent, azimuth 90, elevation -45), then the env's ``default_camera_config``."""
    import mujoco

    m, d = twin.model, twin.data
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = np.median(d.geom_xpos, axis=0)
    cam.distance = m.stat.extent
    for k, v in (twin.mujoco_renderer.default_cam_config or {}).items():
        if isinstance(v, np.ndarray):
            getattr(cam, k)[:] = v
        else:
            setattr(cam, k, v)
    scn = mujoco.MjvScene(m, 1000)
    mujoco.mjv_updateScene(m, d, mujoco.MjvOption(), None, cam, mujoco.mjtCatBit.mjCAT_ALL, scn)
    left, right = scn.camera[0], scn.camera[1]
    pos = 0.5 * (np.array(left.pos) + np.array(right.pos))  # the stereo pair's centre
    return pos, np.array(left.forward), np.array(left.up), left.frustum_top / left.frustum_near


@pytest.mark.parametrize("name", NAMES)
def test_depth_matches_mujocos_ray_casts_from_the_twins_camera(name):
    """Same state, the twin's default camera: every 4th pixel's depth against MuJoCo's own ray
    cast (``mj_ray``) through that pixel, within 2% on at least 95% of the pixels where either
    sees geometry."""
    import mujoco

    side = 160
    twin = gym.make(f"{name}-v5").unwrapped
    twin.reset(seed=0)
    env = gym.make(f"sinew/{name}-v0", render_mode="depth_array", width=side, height=side).unwrapped
    env.reset(seed=0)
    env.set_state(twin.data.qpos, twin.data.qvel)
    ours = env.render().astype(np.float64)
    n, f = env.model.clip
    pos, forward, up, tan_half = mujoco_view(twin)
    right = np.cross(forward, up)
    close = seen = 0
    geomid = np.zeros(1, dtype=np.int32)
    for y in range(0, side, 4):
        for x in range(0, side, 4):
            d = forward + (2 * (x + 0.5) / side - 1) * tan_half * right + (1 - 2 * (y + 0.5) / side) * tan_half * up
            u = d / np.linalg.norm(d)
            dist = mujoco.mj_ray(twin.model, twin.data, pos, u, None, 1, -1, geomid)
            theirs = dist * u.dot(forward) if dist >= 0 else np.inf
            theirs = theirs if n <= theirs <= f else np.inf
            mine = n * f / (f - ours[y, x] * (f - n)) if ours[y, x] < 1 else np.inf
            if np.isfinite(mine) or np.isfinite(theirs):
                seen += 1
                close += bool(abs(mine - theirs) <= 0.02 * min(mine, theirs))
    assert seen > 100, "the camera sees the model"
    assert close / seen >= 0.95, f"{name}: {close}/{seen} pixels within 2%"
