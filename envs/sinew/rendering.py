"""Rendering for sinew's environments, with the keywords and semantics of gymnasium's MuJoCo envs.

Frames are drawn by sinew's own renderer in Rust (``Batch.render``): rays cast against the
analytic geoms on every core, no OpenGL and no system library. The camera follows gymnasium's
``MujocoRenderer``: with neither ``camera_id`` nor ``camera_name`` it is MuJoCo's free camera,
initialised at the first frame to look at the median geom centre from the model's extent
(azimuth 90°, elevation −45°) and then set from ``default_camera_config``; as in MuJoCo, a
``trackbodyid`` there follows that body only with ``"type": "tracking"``.

Depth (``"depth_array"``, ``"rgbd_tuple"``) is MuJoCo's z-buffer value d in [0, 1], as the twin
returns it: a point at distance z along the view axis has d = f (z − n) / ((f − n) z) with
(n, f) = ``model.clip`` (the model's ``<map znear zfar>`` times its extent); 1 where nothing is
drawn. Metric depth is z = n f / (f − d (f − n)).
"""

from __future__ import annotations

import os
import sys
from typing import Any

import gymnasium
import numpy as np

from sinew._core import MAX_RENDER_SIDE as MAX_SIDE

RENDER_MODES = ["human", "rgb_array", "depth_array", "rgbd_tuple"]


def check_render_args(render_mode, width, height) -> None:
    """ValueError for an unknown render mode or a frame size that is not 1..MAX_SIDE pixels."""
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise ValueError(f"unknown render_mode {render_mode!r}; choose one of {RENDER_MODES} or None")
    for name, v in (("width", width), ("height", height)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= MAX_SIDE:
            raise ValueError(f"{name} must be an integer between 1 and {MAX_SIDE}, got {v!r}")


class Viewer:
    """The camera and render mode of one env (or of every world of a vector env)."""

    def __init__(self, model, render_mode: str | None = None, width: int = 480, height: int = 480,
                 camera_id: int | None = None, camera_name: str | None = None,
                 default_camera_config: dict[str, Any] | None = None, visual_options: dict | None = None):
        check_render_args(render_mode, width, height)
        self.model, self.render_mode = model, render_mode
        self.width, self.height = int(width), int(height)
        if camera_id is not None and camera_name is not None:
            raise ValueError("give camera_id or camera_name, not both")
        names = model.camera_names
        if camera_name is not None:
            if camera_name not in names:
                raise ValueError(f"no camera named {camera_name!r}; the model's cameras: {[n for n in names if n]}")
            camera_id = names.index(camera_name)
        if camera_id is not None and not (isinstance(camera_id, (int, np.integer)) and -1 <= camera_id < len(names)):
            raise ValueError(f"camera_id must be -1 (free camera) or one of 0..{len(names) - 1}, got {camera_id!r}")
        self.camera_id = -1 if camera_id is None else int(camera_id)
        self.default_camera_config = dict(default_camera_config or {})
        # MuJoCo's visualisation flags (contact points, joints, ...): sinew draws no overlays
        self.visual_options = dict(visual_options or {})
        # each world's free camera, set up at its first frame
        self._free: dict[int, dict] = {}
        self._window = None
        self._warned_no_display = False

    def camera(self, qpos: np.ndarray, world: int = 0):
        """The ``camera`` argument of ``Batch.render`` for world ``world`` at ``qpos`` (its free
        camera is set up at its first frame, as the twin's viewer is when it is created)."""
        if self.camera_id >= 0:
            return self.camera_id
        if world not in self._free:
            cam = {"lookat": np.median(self.model.geom_xpos(qpos), axis=0).tolist(), "distance": self.model.extent,
                   "azimuth": 90.0, "elevation": -45.0}
            for k, v in self.default_camera_config.items():
                cam[k] = v.tolist() if isinstance(v, np.ndarray) else v
            self._free[world] = cam
        return self._free[world]

    def render(self, batch, worlds: list[int]):
        """The frames of ``worlds`` in this viewer's mode: a list, one per world (None without a
        mode: gymnasium's warning)."""
        mode = self.render_mode
        if mode is None:
            gymnasium.logger.warn("You are calling render method without specifying any render mode. "
                                  "You can specify the render_mode at initialization, "
                                  'e.g. gymnasium.make("sinew/Hopper-v0", render_mode="rgb_array")')
            return None
        cam = [self.camera(batch.qpos[i], i) for i in worlds]
        depth = mode in ("depth_array", "rgbd_tuple")
        rgb = mode != "depth_array"
        out = batch.render(self.width, self.height, cam, list(worlds), rgb=rgb, depth=depth)
        if mode == "rgbd_tuple":
            return [(c, d) for c, d in zip(*out)]
        if mode == "human":
            self.show(out[0])
            return None
        return list(out)

    def show(self, frame: np.ndarray) -> None:
        """Shows an RGB frame in a pygame window; without a display (Linux with neither DISPLAY,
        WAYLAND_DISPLAY nor an SDL_VIDEODRIVER set) it warns once and shows nothing, as opening a
        window would fail."""
        display = ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")
        if sys.platform.startswith("linux") and not any(os.environ.get(k) for k in display):
            if not self._warned_no_display:
                gymnasium.logger.warn('render_mode="human": no display (DISPLAY, WAYLAND_DISPLAY and SDL_VIDEODRIVER are unset), '
                                      'nothing is shown; use render_mode="rgb_array" for frames')
                self._warned_no_display = True
            return
        try:
            import pygame
        except ImportError as e:
            raise gymnasium.error.DependencyNotInstalled(
                'render_mode="human" needs pygame: pip install "sinew[human]" (or pygame)') from e
        if self._window is None:
            try:
                pygame.display.init()
                self._window = pygame.display.set_mode((self.width, self.height))
            except pygame.error as e:
                raise RuntimeError(f'render_mode="human" cannot open a window ({e}); without a display use '
                                   'render_mode="rgb_array"') from e
            pygame.display.set_caption("sinew")
        pygame.event.pump()
        surf = pygame.surfarray.make_surface(np.ascontiguousarray(frame.transpose(1, 0, 2)))
        self._window.blit(surf, (0, 0))
        pygame.display.flip()

    def close(self) -> None:
        if self._window is not None:
            import pygame

            pygame.display.quit()
            self._window = None
