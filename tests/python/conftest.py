import os

# MuJoCo picks its GL platform when first imported: headless EGL for the renderer comparisons
# (test_render.py), whichever test imports it first (MUJOCO_GL=osmesa also works)
os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium  # noqa: E402
import pytest  # noqa: E402

ASSETS = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")

#: gymnasium's MuJoCo model files that sinew must load unchanged
GYM_MODELS = [
    "inverted_pendulum",
    "inverted_double_pendulum",
    "reacher",
    "swimmer",
    "hopper",
    "walker2d_v5",
    "half_cheetah",
    "ant",
    "humanoid",
    "humanoidstandup",
]


def gym_model_path(name: str) -> str:
    return os.path.join(ASSETS, name + ".xml")


@pytest.fixture(params=GYM_MODELS)
def gym_model(request):
    return request.param, gym_model_path(request.param)
