"""Writing frames to a video file (``.mp4`` through imageio's ffmpeg, ``.gif`` through Pillow)."""

from __future__ import annotations

from typing import Iterable

import gymnasium
import numpy as np


def write_video(path: str, frames: Iterable[np.ndarray], fps: float) -> int:
    """Writes RGB frames (H, W, 3) uint8 to ``path`` at ``fps``; returns how many were written."""
    try:
        import imageio.v2 as imageio
    except ImportError as e:
        raise gymnasium.error.DependencyNotInstalled('writing videos needs imageio: pip install "sinew[video]"') from e
    n = 0
    try:
        # macro_block_size=1: any frame size, not only multiples of 16
        kw = {"macro_block_size": 1} if path.endswith(".mp4") else {}
        with imageio.get_writer(path, fps=fps, **kw) as w:
            for f in frames:
                w.append_data(np.asarray(f))
                n += 1
    except (ImportError, ValueError) as e:
        if "ffmpeg" in str(e).lower() or isinstance(e, ImportError):
            raise gymnasium.error.DependencyNotInstalled(
                f'writing {path} needs ffmpeg for imageio: pip install "sinew[video]" ({e})') from e
        raise
    return n
