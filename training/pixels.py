"""DrQ-v2 from pixels on a dm_control suite task, on sinew's env or on dm_control itself, with the
same agent, budget and seed: a learning curve (return per episode against frames) and where the
wall time went (environment against learner).

    python training/pixels.py --task walker-walk --sim sinew
    MUJOCO_GL=egl PYTHONPATH=~/.cache/sinew-tests/mujoco-3.17.0 \\
        python training/pixels.py --task walker-walk --sim dm_control   # dm-control 1.0.50 needs MuJoCo 3.17
    python training/pixels.py --table results/training_pixels.md        # the table of runs/pixels/*.json

The agent is DrQ-v2 (Yarats et al. 2022: DDPG with n-step returns, clipped exploration noise on a
linear schedule, random-shift augmentation, the encoder trained by the critic), sized for a CPU:
64 × 64 frames (Dreamer's size), three stride-2-2-1 convolutions, 256-unit heads, batch 64, one
update every second agent step after 2,000 random steps. Both sides see 3 stacked RGB frames of camera 0
with action repeat 2. Writes runs/pixels/<sim>_<task>_<seed>.json.
"""

import argparse
import collections
import json
import os
import time

import numpy as np


def make_sinew(task: str, seed: int, size: int, repeat: int, stack: int):
    import gymnasium as gym

    import sinew  # noqa: F401

    env = gym.make(f"sinew/dmc-{task}-v0", from_pixels=True, height=size, width=size, action_repeat=repeat, frame_stack=stack)
    first = [True]

    def reset():
        obs, _ = env.reset(seed=seed if first[0] else None)
        first[0] = False
        return obs

    def step(action):
        obs, reward, term, trunc, _ = env.step(action)
        return obs, float(reward), bool(term or trunc)

    return reset, step, env.action_space.shape[0]


def make_dm_control(task: str, seed: int, size: int, repeat: int, stack: int):
    from dm_control import suite

    domain, name = task.split("-", 1)
    env = suite.load(domain, name, task_kwargs={"random": seed})
    frames = collections.deque(maxlen=stack)

    def pixels():
        return env.physics.render(size, size, camera_id=0)

    def reset():
        env.reset()
        frame = pixels()
        for _ in range(stack):
            frames.append(frame)
        return np.concatenate(frames, axis=-1)

    def step(action):
        reward, last = 0.0, False
        for _ in range(repeat):
            ts = env.step(action)
            reward += ts.reward or 0.0
            if ts.last():
                last = True
                break
        frames.append(pixels())
        return np.concatenate(frames, axis=-1), reward, last

    return reset, step, env.action_spec().shape[0]


def agent(obs_shape, action_dim, args):
    import torch
    import torch.nn as nn
    import torch.nn.functional as F

    class Encoder(nn.Module):
        def __init__(self):
            super().__init__()
            c = obs_shape[0]
            self.net = nn.Sequential(nn.Conv2d(c, 32, 3, stride=2), nn.ReLU(), nn.Conv2d(32, 32, 3, stride=2), nn.ReLU(),
                                     nn.Conv2d(32, 32, 3, stride=1), nn.ReLU(), nn.Flatten())
            with torch.no_grad():
                self.dim = self.net(torch.zeros(1, *obs_shape)).shape[1]

        def forward(self, obs):
            return self.net(obs / 255.0 - 0.5)

    def head(n_in, n_out):
        return nn.Sequential(nn.Linear(n_in, args.hidden), nn.ReLU(), nn.Linear(args.hidden, args.hidden), nn.ReLU(), nn.Linear(args.hidden, n_out))

    def trunk(dim):
        return nn.Sequential(nn.Linear(dim, 50), nn.LayerNorm(50), nn.Tanh())

    class Actor(nn.Module):
        def __init__(self, dim):
            super().__init__()
            self.trunk, self.policy = trunk(dim), head(50, action_dim)

        def forward(self, h, std):
            mu = torch.tanh(self.policy(self.trunk(h)))
            return mu, std

    class Critic(nn.Module):
        def __init__(self, dim):
            super().__init__()
            self.trunk, self.q1, self.q2 = trunk(dim), head(50 + action_dim, 1), head(50 + action_dim, 1)

        def forward(self, h, a):
            x = torch.cat([self.trunk(h), a], dim=-1)
            return self.q1(x), self.q2(x)

    def shift(x, pad=4):
        """Random-shift augmentation (DrQ-v2): pad by replication, crop back at a random offset."""
        n, _, hgt, wid = x.shape
        x = F.pad(x, (pad,) * 4, mode="replicate")
        eps = 1.0 / (hgt + 2 * pad)
        ar = torch.linspace(-1.0 + eps, 1.0 - eps, hgt + 2 * pad)[:hgt]
        ar = ar.unsqueeze(0).repeat(hgt, 1).unsqueeze(2)
        base = torch.cat([ar, ar.transpose(1, 0)], dim=2).unsqueeze(0).repeat(n, 1, 1, 1)
        offset = torch.randint(0, 2 * pad + 1, size=(n, 1, 1, 2)).float() * 2.0 / (hgt + 2 * pad)
        return F.grid_sample(x, base + offset, padding_mode="zeros", align_corners=False)

    def sample(mu, std, clip=None):
        noise = torch.randn_like(mu) * std
        if clip is not None:
            noise = noise.clamp(-clip, clip)
        return (mu + noise).clamp(-1.0, 1.0)

    enc = Encoder()
    actor, critic, target = Actor(enc.dim), Critic(enc.dim), Critic(enc.dim)
    target.load_state_dict(critic.state_dict())
    opt_enc, opt_actor, opt_critic = (torch.optim.Adam(p.parameters(), lr=args.lr) for p in (enc, actor, critic))

    def act(obs, std, explore):
        with torch.no_grad():
            mu, _ = actor(enc(torch.as_tensor(obs[None]).float()), std)
            return (sample(mu, std) if explore else mu)[0].numpy()

    def update(obs, action, reward, discount, next_obs, std):
        obs, next_obs = shift(torch.as_tensor(obs).float()), shift(torch.as_tensor(next_obs).float())
        action, reward, discount = (torch.as_tensor(x).float() for x in (action, reward, discount))
        h = enc(obs)
        with torch.no_grad():
            h_next = enc(next_obs)
            mu, _ = actor(h_next, std)
            q1, q2 = target(h_next, sample(mu, std, clip=0.3))
            y = reward[:, None] + discount[:, None] * torch.min(q1, q2)
        q1, q2 = critic(h, action)
        loss = F.mse_loss(q1, y) + F.mse_loss(q2, y)
        opt_enc.zero_grad(set_to_none=True)
        opt_critic.zero_grad(set_to_none=True)
        loss.backward()
        opt_critic.step()
        opt_enc.step()
        mu, _ = actor(h.detach(), std)
        q1, q2 = critic(h.detach(), sample(mu, std, clip=0.3))
        actor_loss = -torch.min(q1, q2).mean()
        opt_actor.zero_grad(set_to_none=True)
        actor_loss.backward()
        opt_actor.step()
        with torch.no_grad():
            for p, pt in zip(critic.parameters(), target.parameters()):
                pt.lerp_(p, args.tau)

    return act, update


class Replay:
    """Transitions of whole episodes; n-step returns are summed at sampling within an episode."""

    def __init__(self, capacity, obs_shape, action_dim, n, gamma):
        self.obs = np.zeros((capacity, *obs_shape), dtype=np.uint8)
        self.next_obs = np.zeros((capacity, *obs_shape), dtype=np.uint8)
        self.action = np.zeros((capacity, action_dim), dtype=np.float32)
        self.reward = np.zeros(capacity, dtype=np.float32)
        self.episode = np.zeros(capacity, dtype=np.int64)
        self.size, self.n, self.gamma = 0, n, gamma

    def add(self, obs, action, reward, next_obs, episode):
        i = self.size
        self.obs[i], self.action[i], self.reward[i], self.next_obs[i], self.episode[i] = obs, action, reward, next_obs, episode
        self.size += 1

    def sample(self, rng, batch):
        # an n-step window lies within one episode (dm_control's tasks end only by the time limit,
        # so every window bootstraps)
        i = rng.integers(0, self.size - self.n + 1, size=batch)
        same = self.episode[i + self.n - 1] == self.episode[i]
        i = np.where(same, i, i - (self.n - 1))
        i = np.clip(i, 0, None)
        reward = sum(self.gamma ** k * self.reward[i + k] for k in range(self.n))
        discount = np.full(batch, self.gamma ** self.n, dtype=np.float32)
        return self.obs[i], self.action[i], reward, discount, self.next_obs[i + self.n - 1]


def train(args):
    import torch
    import torch._dynamo  # noqa: F401  (optimizers load it lazily; loaded after mesa's EGL it segfaults)

    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    make = make_sinew if args.sim == "sinew" else make_dm_control
    reset, step, action_dim = make(args.task, args.seed, args.size, args.repeat, args.stack)
    env_time = env_cpu = 0.0

    def timed(f, *a):
        nonlocal env_time, env_cpu
        t, c = time.perf_counter(), time.process_time()
        out = f(*a)
        env_time, env_cpu = env_time + time.perf_counter() - t, env_cpu + time.process_time() - c
        return out

    to_chw = lambda o: np.ascontiguousarray(np.transpose(o, (2, 0, 1)))
    obs = to_chw(timed(reset))
    act, update = agent(obs.shape, action_dim, args)
    replay = Replay(args.steps, obs.shape, action_dim, args.nstep, args.gamma)
    std_at = lambda t: max(0.1, 1.0 - 0.9 * t * args.repeat / args.std_frames)
    curve, episode, ret, t0, cpu0 = [], 0, 0.0, time.perf_counter(), time.process_time()
    for t in range(args.steps):
        std = std_at(t)
        action = rng.uniform(-1, 1, action_dim).astype(np.float32) if t < args.seed_steps else act(obs, std, True)
        next_obs, reward, last = timed(step, action)
        next_obs = to_chw(next_obs)
        replay.add(obs, action, reward, next_obs, episode)
        ret += reward
        obs = next_obs
        if last:
            curve.append({"frames": (t + 1) * args.repeat, "return": ret, "wall_s": time.perf_counter() - t0, "env_s": env_time})
            print(f"{args.sim} {args.task} frames {(t + 1) * args.repeat:6d} return {ret:7.1f} wall {time.perf_counter() - t0:6.0f} s "
                  f"(env {env_time:5.0f} s)", flush=True)
            save(args, curve, t0, cpu0, env_time, env_cpu, t + 1)
            obs, ret, episode = to_chw(timed(reset)), 0.0, episode + 1
        if t >= args.seed_steps and t % args.update_every == 0:
            update(*replay.sample(rng, args.batch), std)
    save(args, curve, t0, cpu0, env_time, env_cpu, args.steps)


def save(args, curve, t0, cpu0, env_time, env_cpu, steps):
    """Writes the run so far (after every episode, so a run stopped early keeps its curve)."""
    out = {"sim": args.sim, "task": args.task, "seed": args.seed, "frames": steps * args.repeat, "curve": curve,
           "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - cpu0, "env_s": env_time, "env_cpu_s": env_cpu,
           "settings": {k: v for k, v in vars(args).items() if k not in ("table", "out")}}
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, f"{args.sim}_{args.task}_{args.seed}.json"), "w") as f:
        json.dump(out, f, indent=1)


def table(args):
    """The runs in --out, each task's at the budget both simulators reached: its table (and, with
    matplotlib, the learning curves beside it as a .png)."""
    import glob

    runs = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(args.out, "*.json")))]
    lines = [f"<!-- python training/pixels.py --table {args.table} -->",
             "| task | simulator | seed | frames | return, first 5 episodes | return, last 5 episodes | best episode | "
             "wall time (s) | of which environment (s) | CPU time (s) | of which environment (s) |",
             "|---|---|---|---|---|---|---|---:|---:|---:|---:|"]
    tasks = sorted({r["task"] for r in runs})
    for task in tasks:
        mine = sorted((r for r in runs if r["task"] == task), key=lambda r: (r["sim"] != "sinew", r["seed"]))
        budget = min(r["curve"][-1]["frames"] for r in mine)
        for r in mine:
            curve = [c for c in r["curve"] if c["frames"] <= budget]
            rets = [c["return"] for c in curve]
            # CPU times are the whole run's: shown when the run ended at the budget
            whole = r["frames"] == budget and "cpu_s" in r
            cpu = f"{r['cpu_s']:,.0f} | {r['env_cpu_s']:,.0f}" if whole else "— | —"
            lines.append(f"| {task} | {r['sim']} | {r['seed']} | {budget:,} | {np.mean(rets[:5]):.1f} | {np.mean(rets[-5:]):.1f} | "
                         f"{max(rets):.1f} | {curve[-1]['wall_s']:,.0f} | {curve[-1]['env_s']:,.0f} | {cpu} |")
    text = "\n".join(lines) + "\n"
    with open(args.table, "w") as f:
        f.write(text)
    print(text)
    try:
        import matplotlib
    except ImportError:
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(tasks), figsize=(5 * len(tasks), 3.6), squeeze=False)
    for ax, task in zip(axes[0], tasks):
        for r in (r for r in runs if r["task"] == task):
            ax.plot([c["frames"] for c in r["curve"]], [c["return"] for c in r["curve"]], label=f"{r['sim']} (seed {r['seed']})")
        ax.set(title=f"{task}, DrQ-v2 from 64 × 64 pixels", xlabel="frames", ylabel="episode return")
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.splitext(args.table)[0] + ".png", dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--task", default="walker-walk", help="domain-task, as in sinew/dmc-<domain>-<task>-v0")
    ap.add_argument("--sim", choices=["sinew", "dm_control"], default="sinew")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--steps", type=int, default=20000, help="agent steps (frames / action repeat)")
    ap.add_argument("--seed-steps", type=int, default=2000, help="uniformly random steps before learning")
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--stack", type=int, default=3)
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--update-every", type=int, default=2, help="agent steps per update")
    ap.add_argument("--hidden", type=int, default=256)
    ap.add_argument("--lr", type=float, default=1e-4)
    ap.add_argument("--tau", type=float, default=0.01)
    ap.add_argument("--gamma", type=float, default=0.99)
    ap.add_argument("--nstep", type=int, default=3)
    ap.add_argument("--std-frames", type=float, default=20000, help="frames over which exploration noise falls 1 → 0.1")
    ap.add_argument("--threads", type=int, default=1, help="torch threads")
    ap.add_argument("--out", default="runs/pixels")
    ap.add_argument("--table", default=None, help="write the table of the runs in --out here instead of training")
    args = ap.parse_args()
    table(args) if args.table else train(args)


if __name__ == "__main__":
    main()
