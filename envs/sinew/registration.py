"""Registers sinew's environments with gymnasium under the namespace ``sinew`` on import."""

import gymnasium

from sinew.dmc import TASKS as DMC_TASKS
from sinew.env import class_name
from sinew.playground import TASKS as PLAYGROUND_TASKS
from sinew.tasks import TASKS

#: The task of each env entry point (``sinew.env:HopperEnv`` → ``Hopper``), whatever id it is
#: registered under.
ENTRY_TASKS: dict[str, str] = {f"sinew.env:{class_name(name)}Env": name for name in [*TASKS, *DMC_TASKS, *PLAYGROUND_TASKS]}


def register_envs() -> None:
    """gymnasium's MuJoCo tasks as ``sinew/<Name>-v0``, dm_control's as ``sinew/dmc-<domain>-<task>-v0``,
    Playground's as ``sinew/playground-<Task>-v0``."""
    for name in [*TASKS, *DMC_TASKS, *PLAYGROUND_TASKS]:
        env_id = f"sinew/{name}-v0"
        if env_id in gymnasium.registry:
            continue
        # a dm_control task's length depends on its action_repeat: its env counts it
        steps = TASKS[name].max_episode_steps if name in TASKS else None
        if name in PLAYGROUND_TASKS:
            steps = PLAYGROUND_TASKS[name].episode_length
        gymnasium.register(
            id=env_id,
            entry_point=f"sinew.env:{class_name(name)}Env",
            vector_entry_point=f"sinew.env:{class_name(name)}VectorEnv",
            max_episode_steps=steps,
        )
