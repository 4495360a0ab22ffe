"""A/B of the physics step's cost by instruction count, which a shared or throttled machine does
not move (wall-clock A/Bs here swing by ±15–50%): `examples/profile_step` (this tree's copy, at
both commits) steps each model under seeded random controls with its own integrator, under
`valgrind --tool=callgrind`, for several seeds (a changed trajectory alone moves one run's count
by a few percent); the table gives new / base summed over the seeds. Needs valgrind.

    python benches/ab_instructions.py BASE_COMMIT [--seeds 4] [--models hopper ant ...] [--out FILE]
"""

import argparse
import re
import shutil
import subprocess
from pathlib import Path

import gymnasium

from ab_base import ROOT, base_tree
from emit import invocation

ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
#: steps per run: about 10 s each under callgrind
STEPS = {"hopper": 10_000, "walker2d": 10_000, "half_cheetah": 10_000, "ant": 8_000, "humanoid": 5_000}


def build(tree: Path) -> Path:
    subprocess.run(["cargo", "build", "--profile", "profiling", "--example", "profile_step"], cwd=tree, check=True,
                   capture_output=True)
    return tree / "target" / "profiling" / "examples" / "profile_step"


def with_example(tree: Path) -> Path:
    """`tree` with this tree's `examples/profile_step.rs` (the same workload at both commits)."""
    shutil.copy(ROOT / "examples" / "profile_step.rs", tree / "examples" / "profile_step.rs")
    return tree


def instructions(binary: Path, model: str, seed: int) -> int:
    out = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", str(binary),
                          str(ASSETS / f"{model}.xml"), "own", str(STEPS[model]), str(seed)],
                         capture_output=True, text=True, check=True)
    return int(re.search(r"Collected\s*:\s*(\d+)", out.stderr).group(1))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--models", nargs="+", default=["hopper", "half_cheetah", "ant", "humanoid"])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    if shutil.which("valgrind") is None:
        raise SystemExit("valgrind is needed (apt-get install valgrind)")
    new, base = build(ROOT), build(with_example(base_tree(args.base)))
    lines = ["| model | steps × seeds | new / base instructions | new (10⁶) | base (10⁶) |", "|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for model in args.models:
        seeds = range(1, args.seeds + 1)
        a = sum(instructions(new, model, s) for s in seeds)
        b = sum(instructions(base, model, s) for s in seeds)
        lines.append(f"| {model} | {STEPS[model]} × {args.seeds} | {a / b:.3f} | {a / 1e6:,.0f} | {b / 1e6:,.0f} |")
        print(lines[-1], flush=True)
    if args.out:
        Path(args.out).write_text("\n".join([invocation(), *lines]) + "\n")


if __name__ == "__main__":
    main()
