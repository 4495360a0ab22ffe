"""``python -m sinew [model.xml]``: load a model, simulate it, print what happened and how fast;
with ``--video out.mp4``, record it.

With no model it runs gymnasium's humanoid.xml for 10 simulated seconds under random controls
(``--controls zero`` holds them at zero).
"""

import argparse
import math
import os
import sys
import time

import numpy as np

import sinew
from sinew._core import MAX_RENDER_SIDE
from sinew.tasks import ASSETS


def main() -> None:
    ap = argparse.ArgumentParser(prog="python -m sinew", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", nargs="?", default=None, help="MJCF file (default: gymnasium's humanoid.xml)")
    ap.add_argument("--seconds", type=float, default=10.0, help="simulated time (default 10)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the random controls")
    ap.add_argument("--controls", choices=["random", "zero"], default="random")
    ap.add_argument("--video", metavar="FILE", help="record the run to FILE (.mp4 or .gif) at 30 frames/s")
    ap.add_argument("--width", type=int, default=480)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--camera", default=None, help="camera name or id (default: the free camera)")
    args = ap.parse_args()
    if not (math.isfinite(args.seconds) and args.seconds > 0):
        ap.error(f"--seconds must be a positive number, got {args.seconds}")
    for side in ("width", "height"):
        if not 1 <= getattr(args, side) <= MAX_RENDER_SIDE:
            ap.error(f"--{side} must be 1..{MAX_RENDER_SIDE} pixels, got {getattr(args, side)}")
    if args.video and not args.video.lower().endswith((".mp4", ".gif")):
        ap.error(f"--video writes .mp4 or .gif files, got {args.video!r}")
    if args.camera is not None and not args.video:
        ap.error("--camera chooses the view of --video FILE: give both")
    path = args.model or os.path.join(ASSETS, "humanoid.xml")
    try:
        model = sinew.Model.from_mjcf(path)
    except (OSError, sinew.ModelError) as e:
        sys.exit(f"python -m sinew: {e}")
    camera = None if args.camera is None else int(args.camera) if args.camera.lstrip("-").isdigit() else args.camera
    cams = model.camera_names
    if isinstance(camera, str) and camera not in cams or isinstance(camera, int) and not -1 <= camera < len(cams):
        ap.error(f"--camera: {path} has no camera {args.camera!r}; its cameras: "
                 f"{', '.join(repr(c) for c in cams if c) or 'none'} (or ids -1..{len(cams) - 1}, -1 the free camera)")
    print(f"loaded {path}\n  {model}")
    sim = sinew.Sim(model)
    rng = np.random.default_rng(args.seed)
    lo, hi = model.actuator_ctrlrange.T if model.nu else (np.zeros(0), np.zeros(0))
    steps_per_ctrl = max(1, int(round(0.02 / model.timestep)))
    n_ctrl = max(1, int(round(args.seconds / model.timestep)) // steps_per_ctrl)
    frames, frame_dt, next_frame = [], 1.0 / 30.0, 0.0
    start = sim.xpos.copy()
    wall = 0.0
    for _ in range(n_ctrl):
        if args.video and sim.time >= next_frame:
            frames.append(sim.render(args.width, args.height, camera))
            next_frame += frame_dt
        if model.nu and args.controls == "random":
            sim.ctrl[:] = rng.uniform(lo, hi)
        t0 = time.perf_counter()
        sim.step(steps_per_ctrl)
        wall += time.perf_counter() - t0
    steps = n_ctrl * steps_per_ctrl
    end = sim.xpos
    moved = np.linalg.norm(end - start, axis=1)
    far = int(np.argmax(moved))
    print(f"simulated {sim.time:.2f} s ({steps} steps, {model.integrator}, dt={model.timestep})")
    print(f"  body '{model.body_names[far]}' moved farthest: {moved[far]:.3f} m, now at {np.round(end[far], 3)}")
    print(f"  max |qvel| = {np.abs(sim.qvel).max():.3f}, all finite: {bool(np.isfinite(sim.get_state()).all())}")
    print(f"  wall time {wall:.3f} s stepping: {steps / max(wall, 1e-9):,.0f} steps/s, "
          f"{sim.time / max(wall, 1e-9):,.0f}x real time (one thread)")
    if args.video:
        from sinew.video import write_video

        n = write_video(args.video, frames, fps=30)
        print(f"  wrote {n} frames of {args.width}×{args.height} to {args.video}")


if __name__ == "__main__":
    main()
