"""Train a walking policy on a Playground locomotion task with a lean PPO (rsl_rl's recipe:
Gaussian MLP actor on the noisy ``state``, critic on the privileged state, GAE, clipped
surrogate, KL-adaptive learning rate, normalised observations), within a wall-time budget, on
sinew's native vector env or, for comparison, EnvPool's port of the same task.

    python training/playground.py Go1JoystickFlatTerrain --minutes 15
    python training/playground.py --evaluate runs/playground/Go1JoystickFlatTerrain/sinew_0
    python training/playground.py Go1JoystickFlatTerrain --minutes 15 --sim envpool --num-envs 256   # EnvPool's port
    python training/playground.py --report results/playground_training.md RUN_DIR...  # curves, table

Writes RUN_DIR (runs/playground/<task>/<sim>_<seed>): policy.pt, curve.csv (wall seconds, env
steps, the last rollout's tracking error and mean reward per step) and config.json. ``--evaluate``
runs 16 episodes of 20 s with the policy's mean action (commands resampled as the task does) and
prints ``tracking_error_m_s`` (time average of |commanded − actual base velocity in the plane|,
the body frame's x and y) and ``fall_rate`` (episodes ended by a fall).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import time

import numpy as np
import torch
from torch import nn

#: Each robot's layout in Playground's observations: the command in the state, the clean
#: body-frame linear velocity (Go1's trunk, G1's pelvis) in the privileged state.
LAYOUT = {"Go1": (slice(45, 48), slice(57, 60)), "G1": (slice(9, 12), slice(112, 115)), "T1": (slice(9, 12), slice(94, 97)),
          "BerkeleyHumanoid": (slice(9, 12), slice(61, 64)), "Apollo": (slice(9, 12), slice(118, 121)),
          "SpotFlatTerrainJoystick": (slice(78, 81), slice(90, 93))}


class Normalizer(nn.Module):
    """Running mean and variance of observations (brax's ``normalize_observations``)."""

    def __init__(self, dim: int):
        super().__init__()
        self.register_buffer("mean", torch.zeros(dim))
        self.register_buffer("var", torch.ones(dim))
        self.register_buffer("count", torch.tensor(1e-4))

    def update(self, x: torch.Tensor) -> None:
        m, v, n = x.mean(0), x.var(0, unbiased=False), x.shape[0]
        total = self.count + n
        delta = m - self.mean
        self.mean += delta * n / total
        self.var = (self.var * self.count + v * n + delta ** 2 * self.count * n / total) / total
        self.count = total

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return torch.clamp((x - self.mean) / torch.sqrt(self.var + 1e-8), -10.0, 10.0)


def mlp(n_in: int, sizes, n_out: int) -> nn.Sequential:
    layers, d = [], n_in
    for h in sizes:
        layers += [nn.Linear(d, h), nn.ELU()]
        d = h
    return nn.Sequential(*layers, nn.Linear(d, n_out))


class ActorCritic(nn.Module):
    """Gaussian MLP actor and MLP critic (Playground's Go1 and G1 networks: (512, 256, 128))."""

    def __init__(self, n_obs: int, n_priv: int, n_act: int, hidden=(512, 256, 128), init_std: float = 0.25):
        super().__init__()
        self.obs_norm, self.priv_norm = Normalizer(n_obs), Normalizer(n_priv)
        self.actor, self.critic = mlp(n_obs, hidden, n_act), mlp(n_priv, hidden, 1)
        # Playground clips each step's reward at 0: a first policy as wild as rsl_rl's (std 1)
        # earns 0 almost everywhere and learns nothing; at std 0.25 most steps score
        self.log_std = nn.Parameter(torch.full((n_act,), np.log(init_std)))

    def dist(self, obs: torch.Tensor) -> torch.distributions.Normal:
        return torch.distributions.Normal(self.actor(self.obs_norm(obs)), self.log_std.exp())

    def value(self, priv: torch.Tensor) -> torch.Tensor:
        return self.critic(self.priv_norm(priv)).squeeze(-1)


class SinewVec:
    """sinew's native vector env: the state observation, the privileged state from info."""

    def __init__(self, task: str, n: int, seed: int, threads: int):
        import gymnasium as gym
        import sinew  # noqa: F401

        self.env = gym.make_vec(f"sinew/playground-{task}-v0", num_envs=n, vectorization_mode="vector_entry_point",
                                num_threads=threads)
        obs, info = self.env.reset(seed=seed)
        self.obs, self.priv = obs, info["privileged_state"]
        self.n_act = self.env.single_action_space.shape[0]

    def step(self, a: np.ndarray):
        obs, r, term, trunc, info = self.env.step(a)
        self.obs, self.priv = obs, info["privileged_state"]
        return r, term, trunc


class EnvPoolVec:
    """EnvPool's port (``MuJoCoPlayground/<task>-v1``), same observation keys (it holds about
    50 MB per world: 256 worlds take 12.6 GB)."""

    def __init__(self, task: str, n: int, seed: int, threads: int):
        import envpool

        self.env = envpool.make_gymnasium(f"MuJoCoPlayground/{task}-v1", num_envs=n, num_threads=threads, seed=seed)
        obs, _ = self.env.reset()
        self.obs, self.priv = obs["state"], obs["privileged_state"]
        self.n_act = self.env.action_space.shape[-1]

    def step(self, a: np.ndarray):
        obs, r, term, trunc, _ = self.env.step(a)
        self.obs, self.priv = obs["state"], obs["privileged_state"]
        return r, term, trunc


def make_vec(sim: str, task: str, n: int, seed: int, threads: int):
    return (SinewVec if sim == "sinew" else EnvPoolVec)(task, n, seed, threads)


def layout(task: str) -> tuple[slice, slice]:
    """Where ``task``'s command and clean body velocity lie; ValueError for a task without them."""
    for robot, where in LAYOUT.items():
        if task.startswith(robot) and "Joystick" in task:
            return where
    raise ValueError(f"{task}: this script trains the joystick tasks that observe their body velocity "
                     f"({', '.join(LAYOUT)}'s)")


def tracking_error(task: str, obs: np.ndarray, priv: np.ndarray) -> np.ndarray:
    """|commanded − actual planar body-frame velocity| per world (m/s)."""
    command, linvel = layout(task)
    return np.linalg.norm(obs[:, command][:, :2] - priv[:, linvel][:, :2], axis=1)


def train(args) -> str:
    layout(args.task)
    torch.manual_seed(args.seed)
    torch.set_num_threads(args.threads)
    env = make_vec(args.sim, args.task, args.num_envs, args.seed, args.threads)
    n, n_obs, n_priv, n_act = args.num_envs, env.obs.shape[1], env.priv.shape[1], env.n_act
    ac = ActorCritic(n_obs, n_priv, n_act, tuple(args.hidden), args.init_std)
    opt = torch.optim.Adam(ac.parameters(), lr=args.lr)
    run = os.path.join(args.out, args.task, f"{args.sim}_{args.seed}")
    os.makedirs(run, exist_ok=True)
    T = args.unroll
    buf = {k: torch.zeros(T, n, d) for k, d in (("obs", n_obs), ("priv", n_priv), ("act", n_act))}
    for k in ("logp", "rew", "done", "val", "trunc", "valid"):
        buf[k] = torch.zeros(T, n)
    start, steps, it, lr, rows, env_s = time.time(), 0, 0, args.lr, [], 0.0
    # the vector envs reset a world on the step after its episode ended (gymnasium's next-step
    # autoreset), ignoring that step's action: such steps are left out of the loss
    resetting = np.zeros(n, dtype=bool)
    while time.time() - start < args.minutes * 60:
        err = []
        with torch.no_grad():
            for t in range(T):
                obs, priv = torch.as_tensor(env.obs, dtype=torch.float32), torch.as_tensor(env.priv, dtype=torch.float32)
                ac.obs_norm.update(obs)
                ac.priv_norm.update(priv)
                d = ac.dist(obs)
                a = d.sample()
                buf["obs"][t], buf["priv"][t], buf["act"][t] = obs, priv, a
                buf["logp"][t], buf["val"][t] = d.log_prob(a).sum(-1), ac.value(priv)
                t_env = time.time()
                r, term, trunc = env.step(np.clip(a.numpy(), -1.0, 1.0).astype(np.float64))
                env_s += time.time() - t_env
                err.append(tracking_error(args.task, env.obs, env.priv)[~resetting].mean())
                buf["rew"][t] = torch.as_tensor(r, dtype=torch.float32)
                buf["done"][t] = torch.as_tensor(term | trunc | resetting, dtype=torch.float32)
                buf["trunc"][t] = torch.as_tensor(trunc & ~term, dtype=torch.float32)
                buf["valid"][t] = torch.as_tensor(~resetting, dtype=torch.float32)
                resetting = term | trunc
            # a time-limit end bootstraps from the value of the state it reached (rsl_rl)
            buf["rew"] += args.gamma * buf["trunc"] * buf["val"]
            last = ac.value(torch.as_tensor(env.priv, dtype=torch.float32))
            adv, gae = torch.zeros(T, n), torch.zeros(n)
            for t in reversed(range(T)):
                nxt = last if t == T - 1 else buf["val"][t + 1]
                delta = buf["rew"][t] + args.gamma * nxt * (1 - buf["done"][t]) - buf["val"][t]
                gae = delta + args.gamma * args.lam * (1 - buf["done"][t]) * gae
                adv[t] = gae
            ret = adv + buf["val"]
        steps += T * n
        flat = {k: v.reshape(T * n, *v.shape[2:]) for k, v in buf.items()}
        keep = flat["valid"] > 0
        flat = {k: v[keep] for k, v in flat.items()}
        adv_f, ret_f = adv.reshape(-1)[keep], ret.reshape(-1)[keep]
        mb = len(adv_f) // args.minibatches
        for _ in range(args.epochs):
            perm = torch.randperm(len(adv_f))
            for k in range(args.minibatches):
                idx = perm[k * mb:(k + 1) * mb]
                d = ac.dist(flat["obs"][idx])
                logp = d.log_prob(flat["act"][idx]).sum(-1)
                a_n = (adv_f[idx] - adv_f[idx].mean()) / (adv_f[idx].std() + 1e-8)
                ratio = torch.exp(logp - flat["logp"][idx])
                pg = -torch.min(ratio * a_n, torch.clamp(ratio, 1 - args.clip, 1 + args.clip) * a_n).mean()
                v_loss = (ac.value(flat["priv"][idx]) - ret_f[idx]).pow(2).mean()
                loss = pg + args.vf_coef * v_loss - args.entropy * d.entropy().sum(-1).mean()
                opt.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(ac.parameters(), 1.0)
                opt.step()
                with torch.no_grad():
                    kl = (flat["logp"][idx] - logp).mean().item()
                # rsl_rl's adaptive schedule: keep the KL near its target
                lr = max(1e-5, lr / 1.5) if kl > 2 * args.kl else min(1e-2, lr * 1.5) if kl < args.kl / 2 else lr
                for g in opt.param_groups:
                    g["lr"] = lr
        it += 1
        rows.append((round(time.time() - start, 1), steps, float(np.mean(err)), float(buf["rew"].mean())))
        if it % 10 == 0:
            print(f"{rows[-1][0]:7.1f} s  {steps:9d} steps  tracking error {rows[-1][2]:.3f} m/s  reward/step {rows[-1][3]:.4f}  "
                  f"stepping {env_s / (time.time() - start):.0%} of the time", flush=True)
    torch.save(ac.state_dict(), os.path.join(run, "policy.pt"))
    with open(os.path.join(run, "curve.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["wall_s", "env_steps", "tracking_error_m_s", "reward_per_step"])
        w.writerows(rows)
    with open(os.path.join(run, "config.json"), "w") as f:
        json.dump({**vars(args), "n_obs": n_obs, "n_priv": n_priv, "n_act": n_act, "iterations": it, "env_steps": steps}, f, indent=1)
    print(f"saved {run} after {it} iterations, {steps} env steps, {time.time() - start:.0f} s")
    return run


def evaluate(run: str, episodes: int = 16, threads: int = 2) -> tuple[float, float]:
    cfg = json.load(open(os.path.join(run, "config.json")))
    torch.set_num_threads(threads)
    ac = ActorCritic(cfg["n_obs"], cfg["n_priv"], cfg.get("n_act", 12), tuple(cfg.get("hidden", (512, 256, 128))))
    ac.load_state_dict(torch.load(os.path.join(run, "policy.pt")))
    env = make_vec(cfg["sim"], cfg["task"], episodes, 10_000 + cfg["seed"], threads)
    alive, err_sum, err_n, falls = np.ones(episodes, dtype=bool), 0.0, 0, 0
    for _ in range(1000):   # 20 s at ctrl_dt 0.02
        with torch.no_grad():
            a = ac.actor(ac.obs_norm(torch.as_tensor(env.obs, dtype=torch.float32))).numpy()
        _, term, _ = env.step(np.clip(a, -1.0, 1.0).astype(np.float64))
        e = tracking_error(cfg["task"], env.obs, env.priv)
        # a world that fell is reset by the env: its episode is over
        err_sum += e[alive & ~term].sum()
        err_n += int((alive & ~term).sum())
        falls += int((alive & term).sum())
        alive &= ~term
    tracking, fall_rate = err_sum / max(err_n, 1), falls / episodes
    print(f"tracking_error_m_s: {tracking:.3f}")
    print(f"fall_rate: {fall_rate:.3f}")
    return tracking, fall_rate


def report(out: str, runs: list[str]) -> None:
    """The runs' learning curves (tracking error against wall time) as a plot beside `out`, and a
    table of each run's budget, steps and evaluation (``--evaluate``'s numbers, recomputed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    rows = []
    for run in runs:
        cfg = json.load(open(os.path.join(run, "config.json")))
        with open(os.path.join(run, "curve.csv")) as f:
            curve = [tuple(map(float, r)) for r in list(csv.reader(f))[1:]]
        t, err = [c[0] / 60 for c in curve], [c[2] for c in curve]
        learner = "{}, std {}, {} minibatches".format("-".join(map(str, cfg.get("hidden", (512, 256, 128)))),
                                                      cfg.get("init_std", 0.25), cfg["minibatches"])
        ax.plot(t, err, label=f"{cfg['sim']}, {cfg['num_envs']} worlds, {learner}")
        tracking, falls = evaluate(run)
        rows.append(f"| {cfg['task']} | {cfg['sim']} | {cfg['num_envs']} | {learner} | {cfg['seed']} | {cfg['minutes']:g} | "
                    f"{cfg['env_steps']:,} | {err[-1]:.3f} | {tracking:.3f} | {falls:.2f} |")
    ax.set_xlabel("wall time (min), training included")
    ax.set_ylabel("tracking error (m/s), training rollouts")
    ax.axhline(0.25, color="gray", linestyle=":", label="target 0.25 m/s")
    ax.legend()
    png = os.path.splitext(out)[0] + ".png"
    fig.savefig(png, dpi=100, bbox_inches="tight")
    text = "\n".join([
        "# Time to a walking policy on this 2-core machine", "",
        f"`python training/playground.py --report {out} {' '.join(runs)}` after each run's "
        "`python training/playground.py TASK --minutes M [--sim envpool] [--num-envs N] [--hidden H...] [--init-std S] "
        "[--minibatches K]` (the same learner, 2 threads shared by the simulator and torch). Evaluation: 16 episodes of "
        "20 s, the policy's mean action.", "",
        "| task | sim | worlds | networks, first std, minibatches | seed | minutes | env steps | last rollouts' tracking error (m/s) | "
        "evaluated tracking_error_m_s | fall_rate |",
        "|---|---|---:|---|---:|---:|---:|---:|---:|---:|", *rows, "", f"![]({os.path.basename(png)})", ""])
    with open(out, "w") as f:
        f.write(text)
    print(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("task", nargs="?", default="Go1JoystickFlatTerrain")
    ap.add_argument("--evaluate", metavar="RUN_DIR")
    ap.add_argument("--report", nargs="+", metavar=("OUT", "RUN_DIR"), help="write curves and a table of runs to OUT")
    ap.add_argument("--minutes", type=float, default=15.0)
    ap.add_argument("--sim", choices=["sinew", "envpool"], default="sinew")
    ap.add_argument("--num-envs", type=int, default=512)
    ap.add_argument("--unroll", type=int, default=24)
    ap.add_argument("--epochs", type=int, default=4)
    ap.add_argument("--minibatches", type=int, default=4)
    ap.add_argument("--gamma", type=float, default=0.97)
    ap.add_argument("--lam", type=float, default=0.95)
    ap.add_argument("--clip", type=float, default=0.2)
    ap.add_argument("--entropy", type=float, default=0.01)
    ap.add_argument("--vf-coef", type=float, default=1.0)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--kl", type=float, default=0.01)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--hidden", type=int, nargs="+", default=[512, 256, 128], help="hidden layers of the actor and the critic")
    ap.add_argument("--init-std", type=float, default=0.25, help="the policy's first standard deviation")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="runs/playground")
    args = ap.parse_args()
    if args.evaluate:
        evaluate(args.evaluate, threads=args.threads)
        return
    if args.report:
        report(args.report[0], args.report[1:])
        return
    if args.minutes <= 0 or args.num_envs < args.minibatches:
        ap.error("--minutes must be positive and --num-envs at least --minibatches")
    train(args)


if __name__ == "__main__":
    main()
