"""dm_control's suite as sinew envs beside dm_control itself: env-steps/s from state and from
84 × 84 pixels, and a uniform random policy's episode return.

sinew: the native vector env (``gym.make_vec(..., vectorization_mode="vector_entry_point")``),
64 worlds from state and 16 from pixels, all cores; dm_control: its own ``env.step`` loop, one
env, on the installed MuJoCo (on MuJoCo 3.17 where the installed dm-control, 1.0.50, cannot load
its tasks under MuJoCo 4; the table names the version); pixels by ``physics.render`` through
mesa's EGL. Each task is timed in a subprocess of its own, the two sides' windows alternating
(``--rounds`` state windows of each, then one pixel window of each): a shared machine's speed
drifts, and the state ratio is the median of the rounds' ratios. The ratio sinew's physics alone
reaches leaves out the env's Python: it divides each round's ratio by the share of sinew's window
that its worlds' ``Batch.step`` calls took. Returns: mean ± sd over 16 episodes of each
(fewer hide the tasks whose returns are bimodal: a quadruped that lands on its feet and stands
scores ~500, one that does not ~5), actions uniform in the action box (within ±1 where it is unbounded);
lqr's episodes never truncate and are left out of the returns.

    MUJOCO_GL=egl python benches/dmc.py --out results/dmc.md [--tasks dmc-walker-walk ...]
    python benches/dmc.py --stills results/stills/dmc.png    # one 84 × 84 observation per domain

The still is each domain's first task's pixel observation after ``reset(seed=0)`` and 20 random
steps, tiled.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

EPISODES = 16
MUJOCO_317 = os.path.join(os.path.expanduser("~"), ".cache", "sinew-tests", "mujoco-3.17.0")


class _Timed:
    """A batch whose `step` calls add up their wall time (the rest passes through)."""

    def __init__(self, batch):
        object.__setattr__(self, "_batch", batch)
        object.__setattr__(self, "spent", 0.0)

    def __getattr__(self, name):
        return getattr(self._batch, name)

    def __setattr__(self, name, value):
        setattr(self._batch, name, value)

    def step(self, *args):
        t = time.perf_counter()
        self._batch.step(*args)
        object.__setattr__(self, "spent", self.spent + time.perf_counter() - t)


def sinew_rate(name: str, pixels: bool, seconds: float = 1.5) -> float | tuple:
    """Env-steps/s of the native vector env; from state also the share of the time its worlds'
    `Batch.step` calls took (the physics, resets' included; the rest is the env's Python)."""
    import gymnasium as gym
    import sinew  # noqa: F401
    n = 16 if pixels else 64
    env = gym.make_vec(f"sinew/{name}-v0", num_envs=n, vectorization_mode="vector_entry_point", from_pixels=pixels)
    env.reset(seed=0)
    timed = env._core.batch = _Timed(env._core.batch)
    rng = np.random.default_rng(0)
    lo, hi = np.clip(env.single_action_space.low, -1, 1), np.clip(env.single_action_space.high, -1, 1)
    steps, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        for _ in range(10):
            env.step(rng.uniform(lo, hi, (n, len(lo))))
        steps += 10 * n
    wall = time.perf_counter() - t0
    return steps / wall if pixels else (steps / wall, timed.spent / wall)


def sinew_returns(name: str, episodes: int = EPISODES) -> list:
    import gymnasium as gym
    env = gym.make_vec(f"sinew/{name}-v0", num_envs=episodes, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    rng = np.random.default_rng(1)
    lo, hi = np.clip(env.single_action_space.low, -1, 1), np.clip(env.single_action_space.high, -1, 1)
    total, done = np.zeros(episodes), np.zeros(episodes, dtype=bool)
    while not done.all():
        _, r, term, trunc, _ = env.step(rng.uniform(lo, hi, (episodes, len(lo))))
        total += np.where(done, 0.0, r)
        done |= term | trunc
    return total.tolist()


def reference(names: list, rounds: int) -> dict:
    """Both sides' rates and dm_control's returns, measured in this script run in a subprocess
    (``--reference``), and the MuJoCo version dm_control ran on (``"mujoco"``)."""
    env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
    loads = [sys.executable, "-c", "from dm_control import suite; suite.load('acrobot', 'swingup')"]
    if subprocess.run(loads, env=env, capture_output=True).returncode != 0:
        # dm-control 1.0.50 loads its tasks under MuJoCo 3.17 only (1.0.52 under MuJoCo 4)
        if not os.path.exists(os.path.join(MUJOCO_317, "mujoco")):
            subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", MUJOCO_317,
                            "mujoco==3.17.0"], check=True)
        env["PYTHONPATH"] = MUJOCO_317
    out = subprocess.run([sys.executable, __file__, "--rounds", str(rounds), "--reference", *names], check=True, env=env, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure_dm_control(names: list, rounds: int, seconds: float = 1.5) -> None:
    from dm_control import suite
    rows = {}
    for name in names:
        domain, task = name[4:].split("-", 1)
        env = suite.load(domain, task, task_kwargs={"random": 0})
        spec = env.action_spec()
        lo, hi = np.clip(spec.minimum, -1, 1), np.clip(spec.maximum, -1, 1)
        rng = np.random.default_rng(0)

        def rate(pixels: bool) -> float:
            env.reset()
            camera = 2 if domain == "quadruped" else 0
            steps, t0 = 0, time.perf_counter()
            while time.perf_counter() - t0 < seconds:
                ts = env.step(rng.uniform(lo, hi))
                if pixels:
                    env.physics.render(84, 84, camera_id=camera)
                if ts.last():
                    env.reset()
                steps += 1
            return steps / (time.perf_counter() - t0)

        state = [(rate(False), *sinew_rate(name, False)) for _ in range(rounds)]
        pixels = (rate(True), sinew_rate(name, True))
        # returns from their own seeds, not from what the timed loops left
        env = suite.load(domain, task, task_kwargs={"random": 1})
        rng = np.random.default_rng(1)
        returns = []
        for _ in range(0 if domain == "lqr" else EPISODES):
            ts, total = env.reset(), 0.0
            while not ts.last():
                ts = env.step(rng.uniform(lo, hi))
                total += ts.reward
            returns.append(total)
        rows[name] = {"state": state, "pixels": pixels, "returns": returns}
    import mujoco
    print(json.dumps({"mujoco": mujoco.__version__, "tasks": rows}))


def stills(path: str) -> None:
    import gymnasium as gym
    import imageio.v3 as iio
    from sinew.dmc import TASKS
    first = {}
    for name in TASKS:
        first.setdefault(name.split("-")[1], name)
    frames = []
    for name in first.values():
        env = gym.make(f"sinew/{name}-v0", from_pixels=True)
        env.reset(seed=0)
        env.action_space.seed(0)
        for _ in range(20):
            obs, *_ = env.step(env.action_space.sample() if np.isfinite(env.action_space.high).all() else np.zeros(env.action_space.shape))
        frames.append(obs)
    columns = 9
    frames += [np.zeros_like(frames[0])] * (-len(frames) % columns)
    rows = [np.concatenate(frames[k:k + columns], axis=1) for k in range(0, len(frames), columns)]
    iio.imwrite(path, np.concatenate(rows, axis=0))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="results/dmc.md")
    p.add_argument("--tasks", nargs="*")
    p.add_argument("--reference", nargs="*")
    p.add_argument("--rounds", type=int, default=3, help="alternating state windows of each side per task")
    p.add_argument("--stills")
    a = p.parse_args()
    if a.stills:
        return stills(a.stills)
    if a.reference is not None:
        return measure_dm_control(a.reference, a.rounds)
    from sinew.dmc import TASKS
    names = a.tasks or list(TASKS)
    rows, version = [], None
    for name in names:
        measured = reference([name], a.rounds)
        version, r = measured["mujoco"], measured["tasks"][name]
        theirs_state, ours_state, _ = np.median(r["state"], axis=0)
        ratio = np.median([o / t for t, o, _ in r["state"]])
        bound = np.median([o / share / t for t, o, share in r["state"]])
        theirs_px, px = r["pixels"]
        returns = "| — | — |"
        if r["returns"]:
            ours, theirs = sinew_returns(name), r["returns"]
            returns = f"| {np.mean(ours):.1f} ± {np.std(ours):.1f} | {np.mean(theirs):.1f} ± {np.std(theirs):.1f} |"
        rows.append(f"| {name[4:]} | {ours_state:,.0f} | {theirs_state:,.0f} | {ratio:.1f} | {px:,.0f} | {theirs_px:,.0f} | "
                    f"{px / theirs_px:.1f} | {bound:.1f} " + returns)
        print(rows[-1], flush=True)
    lines = ["# dm_control's suite: sinew beside dm_control", "",
             "`MUJOCO_GL=egl python benches/dmc.py --out results/dmc.md` (`--tasks T...` rewrites those tasks' rows "
             "alone; 2 cores; sinew's native vector env, 64 worlds from state, 16 from 84 × 84 pixels; dm_control's own loop, one env, MuJoCo "
             f"{version}; each task in a process of its own, the sides' 1.5 s windows alternating: state steps/s are "
             f"medians of {a.rounds} rounds and × the median of the rounds' ratios, pixels one window each, by mesa's "
             f"EGL for dm_control; \"physics alone\": the state × with the env's Python left out, by the share of each sinew window its "
             f"worlds' `Batch.step` calls took, resets' included; random-policy returns over {EPISODES} episodes of each)", "",
             "| task | state steps/s sinew | dm_control | × | pixels steps/s sinew | dm_control | × | × from state, sinew's physics alone | random return sinew | dm_control |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    # the rows of the tasks not rerun are kept, in the order of TASKS
    kept = read_rows(a.out) if a.tasks and os.path.exists(a.out) else {}
    fresh = {row.split(" | ", 1)[0][2:]: row for row in rows}
    lines += [r for r in (fresh.get(t[4:], kept.get(t[4:])) for t in TASKS) if r]
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")


def read_rows(path: str) -> dict:
    """The per-task rows (keyed by the task's name) of a table this bench wrote."""
    rows = [line for line in open(path).read().splitlines() if line.startswith("| ") and not line.startswith("| task ")]
    return {row.split(" | ", 1)[0][2:]: row for row in rows}


if __name__ == "__main__":
    main()
