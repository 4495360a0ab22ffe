"""Registers sinew's environments with gymnasium under the namespace ``sinew`` on import."""

import gymnasium

from sinew.tasks import TASKS

#: The task of each env entry point (``sinew.env:HopperEnv`` → ``Hopper``), whatever id it is
#: registered under.
ENTRY_TASKS: dict[str, str] = {f"sinew.env:{name}Env": name for name in TASKS}


def register_envs() -> None:
    for name, cls in TASKS.items():
        env_id = f"sinew/{name}-v0"
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point=f"sinew.env:{name}Env",
            vector_entry_point=f"sinew.env:{name}VectorEnv",
            max_episode_steps=cls.max_episode_steps,
        )
