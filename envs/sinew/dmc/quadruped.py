"""dm_control's quadruped: a four-legged ant-like robot with filtered position actuators walks
or runs forward, escapes a bumpy bowl of terrain, or fetches a ball to a target."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import in_frame, tolerance
from sinew.dmc.task import Task, remove

TOES = ["toe_front_left", "toe_front_right", "toe_back_right", "toe_back_left"]
WALLS = ["wall_px", "wall_py", "wall_nx", "wall_ny"]
RANGEFINDERS = [f"rf_{i}{j}" for i in range(4) for j in range(5)]


def find_non_contacting_height(phys, orientation, xy=None):
    """dm_control's ``_find_non_contacting_height``: each world's root at (x, y, z) with the
    given orientation, z rising from 0 in steps of 0.01 until nothing overlaps."""
    names = phys.names
    root = names.jnt_qposadr[names.index("joint", "root")]
    qpos = phys.position().copy()
    n = len(qpos)
    xy = np.zeros((n, 2)) if xy is None else xy
    z = np.zeros(n)
    pending = np.arange(n)
    while len(pending):
        qpos[pending, root:root + 2] = xy[pending]
        qpos[pending, root + 2] = z[pending]
        qpos[pending, root + 3:root + 7] = orientation[pending]
        phys.set_state(qpos)
        pending = pending[phys.penetrations()[pending] > 0]
        z[pending] += 0.01


class Walk(Task):
    """``quadruped-walk``: a random orientation (normalised N(0, 1)⁴) at the lowest height free of
    contact; reward for forward speed of at least 0.5 m/s, while upright."""

    xml = "quadruped.xml"
    time_limit = 20
    control_timestep = .02
    pixels_camera = 2
    speed = 0.5
    sensors = ("velocimeter", "imu_accel", "imu_gyro", *(f"{kind}_{toe}" for kind in ("force", "torque") for toe in TOES))
    walls_and_ball = False
    terrain = False

    def floor_size(self):
        """The floor's half-width: 20 s of the speed."""
        return 20 * self.speed

    def model_xml(self):
        """quadruped.xml as dm_control's ``make_model`` edits it: the terrain and rangefinders
        only for escape, the walls and ball only for fetch, else a floor ``floor_size`` wide."""
        def edit(root):
            if not self.walls_and_ball:
                root.find(".//geom[@name='floor']").set("size", f"{self.floor_size()} {self.floor_size()} .5")
                for wall in WALLS:
                    remove(root, "geom", wall)
                remove(root, "body", "ball")
                remove(root, "site", "target")
            if not self.terrain:
                remove(root, "geom", "terrain")
                remove(root, "rangefinder")
        return self.edited_model(edit)

    def initialize_episode(self, phys, rngs):
        orientation = np.stack([r.standard_normal(4) for r in rngs])
        find_non_contacting_height(phys, orientation / np.linalg.norm(orientation, axis=1, keepdims=True))

    @staticmethod
    def upright(phys):
        return phys.xmat("torso")[:, 2, 2]

    def observation(self, phys):
        names = phys.names
        hinges = [j for j, kind in enumerate(names.joint_types) if kind == "hinge"]
        q, v = phys.position(), phys.velocity()
        ego = [q[:, [names.jnt_qposadr[j] for j in hinges]], v[:, [names.jnt_dofadr[j] for j in hinges]], phys.activation()]
        forces = [phys.sensor(f"{kind}_{toe}") for kind in ("force", "torque") for toe in TOES]
        return OrderedDict(egocentric_state=np.concatenate(ego, axis=1), torso_velocity=phys.sensor("velocimeter").copy(),
                           torso_upright=self.upright(phys), imu=np.concatenate([phys.sensor("imu_accel"), phys.sensor("imu_gyro")], axis=1),
                           force_torque=np.arcsinh(np.concatenate(forces, axis=1)))

    def reward(self, phys):
        upright = tolerance(self.upright(phys), bounds=(1, float("inf")), sigmoid="linear", margin=2, value_at_margin=0)
        move = tolerance(phys.sensor("velocimeter")[:, 0], bounds=(self.speed, float("inf")), margin=self.speed,
                         value_at_margin=0.5, sigmoid="linear")
        return upright * move


class Run(Walk):
    """``quadruped-run``: at least 5 m/s."""

    speed = 5.0


class Escape(Walk):
    """``quadruped-escape``: each episode a new terrain per world (a sinusoidal bowl times smooth
    random bumps, dm_control's), a random orientation at the lowest height free of contact;
    reward for the distance from the origin out to the terrain's edge, while upright within 20°.
    Observes the origin in the torso's frame and 20 rangefinders (tanh of the distance, 1 where
    a ray meets nothing)."""

    terrain = True
    sensors = Walk.sensors + tuple(RANGEFINDERS)
    bump_scale, smoothness = 2.0, 0.15

    def floor_size(self):
        return 40

    def initialize_episode(self, phys, rngs):
        from scipy import ndimage  # dm_control's own smoothing of the bumps

        model = phys.names.model
        res = model.hfield_data(0).shape[0]
        row, col = np.ogrid[-1:1:res * 1j, -1:1:res * 1j]
        bowl = 0.5 - np.cos(2 * np.pi * np.clip(np.sqrt(col ** 2 + row ** 2), 0.04, 1)) / 2
        bump_res = int(2 * model.hfield_size[0, 0] / self.bump_scale)
        terrains = [bowl * ndimage.zoom(r.uniform(self.smoothness, 1, (bump_res, bump_res)), res / bump_res) for r in rngs]
        # in single precision, as MuJoCo keeps height fields
        phys.set_params("hfield_data", np.stack([t.ravel() for t in terrains]).astype(np.float32))
        orientation = np.stack([r.standard_normal(4) for r in rngs])
        find_non_contacting_height(phys, orientation / np.linalg.norm(orientation, axis=1, keepdims=True))

    def observation(self, phys):
        obs = super().observation(phys)
        obs["origin"] = in_frame(-phys.xpos("torso"), phys.xmat("torso"))
        rf = np.concatenate([phys.sensor(n) for n in RANGEFINDERS], axis=1)
        obs["rangefinder"] = np.where(rf == -1.0, 1.0, np.tanh(rf))
        return obs

    def reward(self, phys):
        edge = phys.names.model.hfield_size[0, 0]
        escape = tolerance(np.linalg.norm(phys.site_xpos("workspace"), axis=1), bounds=(edge, float("inf")), margin=edge,
                           value_at_margin=0, sigmoid="linear")
        deviation = np.cos(np.deg2rad(20))
        upright = tolerance(self.upright(phys), bounds=(deviation, float("inf")), sigmoid="linear", margin=1 + deviation,
                            value_at_margin=0)
        return upright * escape


class Fetch(Walk):
    """``quadruped-fetch``: in a walled arena, turned by an azimuth U(0, 2π) at a random spot, the
    ball dropped from 2 m at a random spot with N(0, 5²) horizontal velocity; reward for reaching
    the ball, then for bringing it to the target."""

    walls_and_ball = True

    def initialize_episode(self, phys, rngs):
        n, names = len(rngs), phys.names
        radius = 0.9 * phys.geom_size("floor")[0]
        azimuth = np.array([r.uniform(0, 2 * np.pi) for r in rngs])
        xy = np.stack([r.uniform(-radius, radius, size=2) for r in rngs])
        orientation = np.stack([np.cos(azimuth / 2), np.zeros(n), np.zeros(n), np.sin(azimuth / 2)], axis=1)
        find_non_contacting_height(phys, orientation, xy)
        ball_q, ball_v = names.jnt_qposadr[names.index("joint", "ball_root")], names.jnt_dofadr[names.index("joint", "ball_root")]
        qpos, qvel = phys.position().copy(), phys.velocity().copy()
        for q, v, r in zip(qpos, qvel, rngs):
            q[ball_q:ball_q + 2] = r.uniform(-radius, radius, size=2)
            q[ball_q + 2] = 2
            v[ball_v:ball_v + 2] = 5 * r.standard_normal(2)
        phys.set_state(qpos, qvel)

    def observation(self, phys):
        obs = super().observation(phys)
        names = phys.names
        ball, root = (names.jnt_dofadr[names.index("joint", j)] for j in ("ball_root", "root"))
        v = phys.velocity()
        rows = [phys.xpos("ball") - phys.xpos("torso"), v[:, ball:ball + 3] - v[:, root:root + 3], v[:, ball + 3:ball + 6]]
        frame = phys.xmat("torso")
        obs["ball_state"] = np.concatenate([in_frame(r, frame) for r in rows], axis=1)
        obs["target_position"] = in_frame(phys.site_xpos("target") - phys.xpos("torso"), frame)
        return obs

    def reward(self, phys):
        arena = phys.geom_size("floor")[0] * np.sqrt(2)
        ball = phys.xpos("ball")
        reach = tolerance(np.linalg.norm((phys.site_xpos("workspace") - ball)[:, :2], axis=1),
                          bounds=(0, phys.site_size("workspace")[0] + phys.geom_size("ball")[0]), sigmoid="linear",
                          margin=arena, value_at_margin=0)
        fetch = tolerance(np.linalg.norm((phys.site_xpos("target") - ball)[:, :2], axis=1),
                          bounds=(0, phys.site_size("target")[0]), sigmoid="linear", margin=arena, value_at_margin=0)
        upright = tolerance(self.upright(phys), bounds=(1, float("inf")), sigmoid="linear", margin=2, value_at_margin=0)
        return upright * reach * (0.5 + 0.5 * fetch)


TASKS = {"walk": Walk, "run": Run, "escape": Escape, "fetch": Fetch}
