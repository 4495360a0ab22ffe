"""Per-environment hyperparameters (rl-baselines3-zoo's for the MuJoCo v4 tasks where it has them,
shortened nets and budgets otherwise). Keys are task names; the same values serve sinew's env
and its MuJoCo twin so that a comparison differs only in the simulator."""

PPO = {
    "InvertedPendulum": dict(n_steps=1024, batch_size=64, gae_lambda=0.95, gamma=0.99, n_epochs=10, learning_rate=3e-4),
    "Hopper": dict(n_steps=512, batch_size=32, gamma=0.999, learning_rate=9.80828e-05, ent_coef=0.00229519,
                   clip_range=0.2, n_epochs=5, gae_lambda=0.99, max_grad_norm=0.7, vf_coef=0.835671),
    "default": dict(),
}

SAC = {
    "Hopper": dict(learning_starts=10000, learning_rate=3e-4, batch_size=256, buffer_size=1_000_000),
    "default": dict(learning_starts=10000),
}

BUDGET = {"InvertedPendulum": 20_000, "Hopper": 200_000, "default": 100_000}


def task_of(env_id: str) -> str:
    """'sinew/Hopper-v0' or 'Hopper-v5' → 'Hopper'."""
    return env_id.split("/")[-1].rsplit("-", 1)[0]


def get(algo: str, env_id: str) -> dict:
    table = {"ppo": PPO, "sac": SAC}[algo]
    return dict(table.get(task_of(env_id), table["default"]))
