import os

import pytest

from sinew.tasks import ASSETS  # gymnasium's model files: one definition

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
