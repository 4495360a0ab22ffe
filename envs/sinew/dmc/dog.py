"""dm_control's dog: a 38-joint dog with mesh-weighted bones stands, walks, trots or runs, or
fetches a ball to a target."""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from sinew.dmc.physics import in_frame, tolerance
from sinew.dmc.task import Task, remove

MIN_UPRIGHT = np.cos(np.deg2rad(30))


class Stand(Task):
    """``dog-stand``: at qpos0 turned by an azimuth U(0, 2π), horizontal and yaw velocities
    N(0, 2²), activations uniform in the controls' ranges; reward for torso and pelvis above 90%
    of their standing heights, skull, torso and pelvis upright, and the feet carrying the weight."""

    xml = "dog.xml"
    time_limit = 15
    control_timestep = .015
    speed = 0.0
    sensors = ("torso_linvel", "accelerometer", "velocimeter", "gyro", "foot_L", "foot_R", "hand_L", "hand_R",
               "palm_L", "palm_R", "sole_L", "sole_R")
    floor = 15.0
    ball = False

    def model_xml(self):
        """dog.xml as dm_control's ``make_model`` edits it: the floor's size and, but for fetch,
        no ball, target, ball cameras or walls."""
        def edit(root):
            root.find(".//geom[@name='floor']").set("size", f"{self.floor} {self.floor} .1")
            if not self.ball:
                remove(root, "body", "ball")
                remove(root, "geom", "target")
                remove(root, "camera", "ball")
                remove(root, "camera", "head")
                for wall in ("px", "nx", "py", "ny"):
                    remove(root, "geom", f"wall_{wall}")
        return self.edited_model(edit)

    def initialize_episode(self, phys, rngs):
        names = phys.names
        root = names.jnt_qposadr[names.index("joint", "root")]
        # the standing heights and weight, from qpos0
        self.stand_height = self.heights(phys)[0] * 0.9
        torso = names.subtree(names.index("body", "torso"))
        self.weight = -phys.batch.model.gravity[2] * names.body_mass[torso].sum()
        qpos, qvel, act = phys.position().copy(), phys.velocity().copy(), phys.activation().copy()
        lo, hi = phys.batch.model.actuator_ctrlrange.T
        for q, v, a, r in zip(qpos, qvel, act, rngs):
            azimuth = r.uniform(0, 2 * np.pi)
            q[root + 3:root + 7] = np.cos(azimuth / 2), 0, 0, np.sin(azimuth / 2)
            for k in (0, 1, 5):
                v[k] = 2 * r.standard_normal()
            for i in range(len(a)):
                a[i] = r.uniform(lo[i], hi[i])
        phys.set_state(qpos, qvel, act)

    @staticmethod
    def heights(phys):
        return np.stack([phys.xpos("torso")[:, 2], phys.xpos("pelvis")[:, 2]], axis=1)

    @staticmethod
    def z_projection(phys):
        """The bottom rows of the skull's, torso's and pelvis's rotations (n, 3, 3)."""
        return np.stack([phys.xmat(b)[:, 2, :] for b in ("skull", "torso", "pelvis")], axis=1)

    @staticmethod
    def torso_com_velocity(phys):
        return in_frame(phys.sensor("torso_linvel"), phys.xmat("torso"))

    def observation(self, phys):
        names = phys.names
        hinges = [j for j, kind in enumerate(names.joint_types) if kind == "hinge"]
        return OrderedDict(
            joint_angles=phys.position()[:, [names.jnt_qposadr[j] for j in hinges]],
            joint_velocites=phys.velocity()[:, [names.jnt_dofadr[j] for j in hinges]],
            torso_pelvis_height=self.heights(phys),
            z_projection=self.z_projection(phys).reshape(-1, 9),
            torso_com_velocity=self.torso_com_velocity(phys),
            inertial_sensors=np.concatenate([phys.sensor(s) for s in ("accelerometer", "velocimeter", "gyro")], axis=1),
            foot_forces=np.concatenate([phys.sensor(s) for s in ("foot_L", "foot_R", "hand_L", "hand_R")], axis=1),
            touch_sensors=self.touch(phys),
            actuator_state=phys.activation().copy(),
        )

    @staticmethod
    def touch(phys):
        return np.concatenate([phys.sensor(s) for s in ("palm_L", "palm_R", "sole_L", "sole_R")], axis=1)

    def factors(self, phys):
        """The reward's factors, one column each."""
        h, sh = self.heights(phys), self.stand_height
        torso = tolerance(h[:, 0], bounds=(sh[0], float("inf")), margin=sh[0])
        pelvis = tolerance(h[:, 1], bounds=(sh[1], float("inf")), margin=sh[1])
        upright = tolerance(self.z_projection(phys)[:, :, 2], bounds=(MIN_UPRIGHT, float("inf")), sigmoid="linear",
                            margin=MIN_UPRIGHT + 1, value_at_margin=0)
        touch = tolerance(self.touch(phys).sum(axis=1), bounds=(self.weight, float("inf")), margin=self.weight,
                          sigmoid="linear", value_at_margin=0.9)
        columns = [torso[:, None], pelvis[:, None], upright, touch[:, None]]
        if self.speed > 0:
            forward = tolerance(self.torso_com_velocity(phys)[:, 0], bounds=(self.speed, 2 * self.speed),
                                margin=max(1.0, self.speed), value_at_margin=0, sigmoid="linear")
            columns.append(((4 * forward + 1) / 5)[:, None])
        return np.concatenate(columns, axis=1)

    def reward(self, phys):
        return self.factors(phys).prod(axis=1)


class Walk(Stand):
    """``dog-walk``: forward at 1–2 m/s."""

    speed = 1.0


class Trot(Stand):
    """``dog-trot``: 3–6 m/s."""

    speed = 3.0
    floor = 45.0


class Run(Stand):
    """``dog-run``: 9–18 m/s."""

    speed = 9.0
    floor = 135.0


class Fetch(Stand):
    """``dog-fetch``: as stand, and the ball thrown towards the dog from 0.75 of the floor's
    half-size at an azimuth U(0, 2π), up to 3 m high and 5 m/s fast; reward for biting the ball,
    then for bringing it to the target."""

    floor = 10.0
    ball = True

    def initialize_episode(self, phys, rngs):
        super().initialize_episode(phys, rngs)
        names = phys.names
        ball_q, ball_v = names.jnt_qposadr[names.index("joint", "ball_root")], names.jnt_dofadr[names.index("joint", "ball_root")]
        radius, g = 0.75 * phys.geom_size("floor")[0], -phys.batch.model.gravity[2]
        qpos, qvel = phys.position().copy(), phys.velocity().copy()
        for q, v, r in zip(qpos, qvel, rngs):
            azimuth = r.uniform(0, 2 * np.pi)
            q[ball_q:ball_q + 3] = radius * np.sin(azimuth), radius * np.cos(azimuth), 0.05
            vertical = np.sqrt(2 * g * r.uniform(0, 3))
            speed = r.uniform(0, 5)
            dx = -np.sin(azimuth) + 0.05 * r.standard_normal()
            dy = -np.cos(azimuth) + 0.05 * r.standard_normal()
            v[ball_v:ball_v + 3] = speed * dx, speed * dy, vertical
        phys.set_state(qpos, qvel)

    def observation(self, phys):
        obs = super().observation(phys)
        head, ball, frame = phys.site_xpos("head"), phys.geom_xpos("ball"), phys.site_xmat("head")
        velocity = phys.geom_velocity("ball") - phys.site_velocity("head")
        obs["ball_state"] = np.concatenate([in_frame(ball - head, frame), in_frame(velocity, frame)], axis=1)
        obs["target_position"] = in_frame(phys.geom_xpos("target") - head, frame)
        return obs

    def factors(self, phys):
        ball = phys.geom_xpos("ball")
        mouth = 0.5 * (np.linalg.norm(ball - phys.site_xpos("upper_bite"), axis=1) + np.linalg.norm(ball - phys.site_xpos("lower_bite"), axis=1))
        reach = (6 * tolerance(mouth, bounds=(0, phys.site_size("upper_bite")[0]), sigmoid="reciprocal", margin=2) + 1) / 7
        target = phys.geom_size("target")[0]
        distance = np.linalg.norm(ball - phys.geom_xpos("target"), axis=1)
        near = tolerance(distance, bounds=(0, target), sigmoid="reciprocal", margin=phys.geom_size("floor")[0])
        reach = np.where(distance < 2 * target, 1.0, reach)
        return np.concatenate([super().factors(phys), reach[:, None], ((near + 1) / 2)[:, None]], axis=1)


TASKS = {"stand": Stand, "walk": Walk, "trot": Trot, "run": Run, "fetch": Fetch}
