"""The base commit of an A/B (`ab_step.py`, `ab_instructions.py`): a worktree of it, checked out
once and kept under ~/.cache/sinew-ab/<sha>/tree, beside what each A/B builds from it."""

import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CACHE = Path.home() / ".cache" / "sinew-ab"


def base_tree(commit: str) -> Path:
    """The worktree of `commit` (checked out on first use)."""
    sha = subprocess.run(["git", "rev-parse", commit], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
    tree = CACHE / sha / "tree"
    if not tree.is_dir():
        subprocess.run(["git", "worktree", "add", "--force", "--detach", str(tree), sha], cwd=ROOT, check=True)
    return tree
