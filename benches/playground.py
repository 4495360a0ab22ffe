"""sinew's Playground tasks beside EnvPool's port of Playground (``MuJoCoPlayground/<Task>-v1``):
the same initial-state and command distributions, rewards and episode ends under fixed policies
(in distribution: the two step different physics, so states cannot be matched step by step), and
env-steps/s on the same machine and threads.

    python benches/playground.py --out results/playground.md
    python benches/playground.py --stills results/stills      # one still per robot, sinew's renderer

Needs ``pip install envpool`` (its Playground port and model files).
"""

from __future__ import annotations

import argparse
import os
import time

import gymnasium as gym
import numpy as np

import sinew  # noqa: F401

#: Each task and the reward terms its table shows.
TASKS = {
    "Go1JoystickFlatTerrain": ["tracking_lin_vel", "tracking_ang_vel", "orientation", "pose", "torques", "action_rate", "energy",
                               "feet_clearance", "feet_slip", "feet_air_time", "termination"],
    "Go1JoystickRoughTerrain": ["tracking_lin_vel", "tracking_ang_vel", "orientation", "pose", "torques", "action_rate", "energy",
                                "feet_clearance", "feet_slip", "feet_air_time", "termination"],
    "Go1Getup": ["orientation", "torso_height", "posture", "stand_still", "action_rate", "torques", "dof_pos_limits", "dof_acc",
                 "dof_vel"],
    "Go1Handstand": ["height", "orientation", "contact", "dof_pos_limits", "pose"],
    "Go1Footstand": ["height", "orientation", "contact", "dof_pos_limits", "pose"],
    "SpotFlatTerrainJoystick": ["tracking_lin_vel", "tracking_ang_vel", "orientation", "posture", "torques", "action_rate",
                                "energy", "feet_clearance", "feet_slip", "feet_air_time", "termination"],
    "SpotJoystickGaitTracking": ["feet_phase", "tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "lin_vel_z", "hip_splay"],
    "SpotGetup": ["orientation", "torso_height", "posture", "stand_still"],
    "BarkourJoystick": ["tracking_lin_vel", "tracking_ang_vel", "lin_vel_z", "ang_vel_xy", "orientation", "torques", "action_rate",
                        "stand_still", "termination", "feet_air_time"],
    "G1JoystickFlatTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "feet_air_time", "feet_slip",
                              "feet_phase", "stand_still", "termination", "contact_force", "pose"],
    "G1JoystickRoughTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "feet_air_time", "feet_slip",
                               "feet_phase", "stand_still", "termination", "contact_force", "pose"],
    "T1JoystickFlatTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "feet_air_time", "feet_slip",
                              "feet_phase", "alive", "pose", "feet_distance", "collision"],
    "T1JoystickRoughTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "feet_air_time", "feet_slip",
                               "feet_phase", "alive", "pose", "feet_distance", "collision"],
    "BerkeleyHumanoidJoystickFlatTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "torques",
                                            "action_rate", "feet_air_time", "feet_slip", "feet_phase", "termination", "pose"],
    "BerkeleyHumanoidJoystickRoughTerrain": ["tracking_lin_vel", "tracking_ang_vel", "ang_vel_xy", "orientation", "torques",
                                             "action_rate", "feet_air_time", "feet_slip", "feet_phase", "termination", "pose"],
    "H1InplaceGaitTracking": ["feet_phase", "pose", "ang_vel", "lin_vel"],
    "H1JoystickGaitTracking": ["feet_phase", "tracking_lin_vel", "tracking_ang_vel", "pose", "action_rate"],
    "PandaPickCube": ["gripper_box", "box_target", "no_floor_collision", "robot_target_qpos"],
    "PandaPickCubeOrientation": ["gripper_box", "box_target", "no_floor_collision", "robot_target_qpos"],
    "PandaOpenCabinet": ["gripper_box", "box_target", "no_barrier_collision", "robot_target_qpos"],
    "PandaPickCubeCartesian": ["gripper_box", "box_target", "no_floor_collision", "no_box_collision"],
    "PandaRobotiqPushCube": ["box_target", "box_orientation", "gripper_box", "joint_vel", "total_command", "action_rate"],
    "LeapCubeRotateZAxis": ["angvel", "termination"],
    "LeapCubeReorient": ["orientation", "position", "termination", "hand_pose", "action_rate", "energy"],
    "AeroCubeRotateZAxis": ["angvel", "termination", "action_rate"],
    "AlohaHandOver": ["gripper_box", "box_handover", "handover_target", "no_table_collision"],
    "AlohaSinglePegInsertion": ["left_reward", "right_reward", "no_table_collision", "socket_entrance_reward", "peg_end2_reward",
                                "peg_insertion_reward"],
    "ApolloJoystickFlatTerrain": ["tracking", "ang_vel_xy", "orientation", "feet_phase", "pose", "collision"],
    "Op3Joystick": ["tracking_lin_vel", "tracking_ang_vel", "orientation", "torques", "action_rate", "zero_cmd", "termination",
                    "feet_slip", "energy"],
}
#: Privileged-state entries compared at reset, per robot: (name, columns).
RESET = {"Go1": [("body linear velocity", slice(57, 60)), ("gravity in IMU frame", slice(54, 57)), ("gyro", slice(48, 51)),
                 ("joint angles − default", slice(63, 75))],
         # Spot's gait task observes one array, its noisy state (Playground gives it no privileged one)
         "SpotJoystickGaitTracking": [("gyro (noisy)", slice(0, 3)), ("up vector (noisy)", slice(3, 6)),
                                      ("joint angles (noisy)", slice(6, 18))],
         "Spot": [("body linear velocity", slice(90, 93)), ("up vector", slice(87, 90)), ("gyro", slice(81, 84)),
                  ("joint angles − default", slice(96, 108))],
         # Barkour's state: its newest readings first, noisy (its reset is the keyframe at rest)
         "Barkour": [("up vector (noisy)", slice(1, 4)), ("joint angles − default (noisy)", slice(7, 19))],
         "G1": [("pelvis linear velocity", slice(112, 115)), ("gravity in pelvis IMU frame", slice(109, 112)),
                ("gyro", slice(103, 106)), ("joint angles − default", slice(118, 147))],
         "T1": [("body linear velocity", slice(94, 97)), ("gravity in IMU frame", slice(91, 94)), ("gyro", slice(85, 88)),
                ("joint angles − default", slice(100, 123))],
         "BerkeleyHumanoid": [("body linear velocity", slice(61, 64)), ("gravity in IMU frame", slice(58, 61)),
                              ("gyro", slice(52, 55)), ("joint angles − default", slice(67, 79))],
         "Apollo": [("body linear velocity", slice(118, 121)), ("gravity in IMU frame", slice(115, 118)), ("gyro", slice(112, 115)),
                    ("joint angles − default", slice(121, 153))],
         "H1": [("gyro (noisy)", slice(0, 3)), ("up vector (noisy)", slice(3, 6)), ("joint angles − default (noisy)", slice(6, 25))],
         "PandaRobotiq": [], "Panda": [], "Leap": [], "Aero": [], "Aloha": [],
         # OP3's state: its newest readings first, noisy (its reset is the keyframe at rest)
         "Op3": [("gyro (noisy)", slice(0, 3)), ("up vector (noisy)", slice(3, 6)), ("joint angles − default (noisy)", slice(9, 29))]}
#: Worlds per run: EnvPool's port holds about 50 MB per world (its contact buffers) for Go1, more
#: for the humanoids, about 0.55 GB for Apollo and 0.45 GB for OP3.
WORLDS = {"Go1": 256, "SpotJoystickGaitTracking": 256, "Spot": 256, "Barkour": 256, "H1": 128, "G1": 128, "T1": 128,
          "BerkeleyHumanoid": 128, "Apollo": 16, "Op3": 16, "PandaRobotiq": 64, "Panda": 128,
          "Leap": 64, "Aero": 64, "Aloha": 64}


class Sinew:
    def __init__(self, task, n, threads, seed):
        self.env = gym.make_vec(f"sinew/playground-{task}-v0", num_envs=n, vectorization_mode="vector_entry_point",
                                num_threads=threads)
        obs, info = self.env.reset(seed=seed)
        self.priv, self.command, self.terms = info["privileged_state"], info.get("command"), TASKS[task]
        self.nu = self.env.single_action_space.shape[0]

    def step(self, a):
        obs, r, term, trunc, info = self.env.step(a)
        return r, term, trunc, {k: info[k] for k in self.terms}


class EnvPool:
    def __init__(self, task, n, threads, seed):
        import envpool
        self.env = envpool.make_gymnasium(f"MuJoCoPlayground/{task}-v1", num_envs=n, num_threads=threads, seed=seed)
        obs, info = self.env.reset()
        # OP3's, H1's, Barkour's, Panda's and two of Spot's tasks observe one array, their state (Playground gives
        # them no privileged state)
        self.priv = obs["privileged_state"] if isinstance(obs, dict) else obs
        self.command, self.terms = info.get("command"), TASKS[task]
        self.nu = self.env.action_space.shape[-1]

    def step(self, a):
        obs, r, term, trunc, info = self.env.step(a)
        return r, term, trunc, {k: info["reward_" + k] for k in self.terms}


def robot(task: str) -> str:
    return next(r for r in RESET if task.startswith(r))


def rollout(env, task, policy, n, steps=250, seed=0):
    """Mean reward per step, each term's mean (scaled, per second) over the worlds whose episode
    has not terminated yet, and the share that terminated within `steps`, under `policy` ("zero": the default pose held; "random":
    uniform actions in [-1, 1] redrawn each step), from `env` as made (2 threads, `seed`)."""
    rng = np.random.default_rng(seed)
    fell = np.zeros(n, dtype=bool)
    rewards, terms = [], {k: [] for k in TASKS[task]}
    for _ in range(steps):
        a = np.zeros((n, env.nu)) if policy == "zero" else rng.uniform(-1, 1, (n, env.nu))
        r, term, trunc, t = env.step(a)
        live = ~fell
        if live.any():
            rewards.append(r[live].mean())
            for k in t:
                terms[k].append(t[k][live].mean())
        fell |= term
    return float(np.mean(rewards)), {k: float(np.mean(v)) for k, v in terms.items()}, float(fell.mean())


def throughput(env, n, steps=200):
    """Env-steps/s of `env` (`n` worlds) under seeded uniform actions, after one step."""
    a = np.random.default_rng(0).uniform(-1, 1, (steps, n, env.nu))
    env.step(a[0])
    t0 = time.perf_counter()
    for k in range(steps):
        env.step(a[k])
    return n * steps / (time.perf_counter() - t0)


def stills(directory: str) -> None:
    """Each robot after ``reset(seed=0)`` and 20 steps holding its default pose, 480 × 480."""
    import imageio
    for name, task in (("Go1", "Go1JoystickFlatTerrain"), ("Spot", "SpotFlatTerrainJoystick"), ("Barkour", "BarkourJoystick"),
                       ("H1", "H1InplaceGaitTracking"),
                       ("G1", "G1JoystickFlatTerrain"), ("T1", "T1JoystickFlatTerrain"),
                       ("BerkeleyHumanoid", "BerkeleyHumanoidJoystickFlatTerrain"), ("Apollo", "ApolloJoystickFlatTerrain"),
                       ("Op3", "Op3Joystick"), ("Panda", "PandaPickCube"),
                       ("Leap", "LeapCubeRotateZAxis"), ("Aero", "AeroCubeRotateZAxis"), ("Aloha", "AlohaHandOver")):
        env = gym.make(f"sinew/playground-{task}-v0", render_mode="rgb_array", domain_randomization=False)
        env.reset(seed=0)
        for _ in range(20):
            env.step(np.zeros(env.action_space.shape))
        imageio.imwrite(f"{directory}/playground-{name}.png", env.render())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=None)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--stills", metavar="DIR", help="write a still of each robot there instead")
    ap.add_argument("--tasks", nargs="+", default=list(TASKS), choices=list(TASKS), help="only these tasks (a check)")
    args = ap.parse_args()
    if args.stills:
        stills(args.stills)
        return
    head = ["# Playground tasks: sinew beside EnvPool's port", "",
            "`python benches/playground.py --out results/playground.md` (EnvPool "
            f"{__import__('envpool').__version__}, 2-core machine; `--tasks T...` rewrites those tasks' sections "
            "alone). Checked in distribution: the two simulators' physics differ (exact contact against MuJoCo's "
            "soft contact), so the same actions do not reach the same states.", ""]
    sections = {}
    for task in args.tasks:
        lines = []
        names, n = TASKS[task], WORLDS[robot(task)]
        lines += [f"## {task}", ""]
        # each policy's rollout starts from envs made afresh (seed 0); the zero policy's are the
        # reset distribution's too (an EnvPool env of a humanoid task holds gigabytes: made
        # as few times as the table needs)
        fresh = {policy: {"sinew": Sinew(task, n, 2, 0), "EnvPool": None} for policy in ("zero", "random")}
        fresh["zero"]["EnvPool"] = EnvPool(task, n, 2, 0)
        if "Joystick" in task:
            lines += [f"Reset distribution (privileged state, clean readings; {n} worlds): mean ± std per group.", "",
                      "| quantity | sinew | EnvPool |", "|---|---|---|"]
            s, e = fresh["zero"]["sinew"], fresh["zero"]["EnvPool"]
            for name, cols in RESET[robot(task)]:
                lines.append(f"| {name} | {s.priv[:, cols].mean():+.3f} ± {s.priv[:, cols].std():.3f} | "
                             f"{e.priv[:, cols].mean():+.3f} ± {e.priv[:, cols].std():.3f} |")
            lines.append(f"| command (vx, vy, ωz) std | {np.array2string(s.command.std(0), precision=2)} | "
                         f"{np.array2string(e.command.std(0), precision=2)} |")
            del s, e
            lines.append("")
        lines += [f"Fixed policies, {n} worlds × 250 steps (5 s): mean reward per step, the share of worlds whose episode "
                  "terminated (a fall, or a handstand's leg touching down), and each reward term's mean (scaled, per second).", "",
                  "| policy | sim | reward/step | ended | " + " | ".join(names) + " |", "|---|---|---:|---:|" + "---:|" * len(names)]
        for policy in ("zero", "random"):
            for name, sim in (("sinew", Sinew), ("EnvPool", EnvPool)):
                env = fresh[policy].pop(name) or sim(task, n, 2, 0)
                r, t, fell = rollout(env, task, policy, n)
                del env
                lines.append(f"| {policy} | {name} | {r:.4f} | {fell:.2f} | " + " | ".join(f"{t[k]:+.3f}" for k in names) + " |")
        lines += ["", "Env-steps/s, random actions, median of alternating rounds:", "",
                  "| worlds | threads | sinew | EnvPool | × |", "|---:|---:|---:|---:|---:|"]
        for threads in (1, 2):
            ours, theirs = [], []
            s, e = Sinew(task, n, threads, 0), EnvPool(task, n, threads, 0)
            for _ in range(args.rounds):
                ours.append(throughput(s, n))
                theirs.append(throughput(e, n))
            del s, e
            a, b = np.median(ours), np.median(theirs)
            lines.append(f"| {n} | {threads} | {a:,.0f} | {b:,.0f} | {a / b:.2f} |")
        lines.append("")
        sections[task] = "\n".join(lines)
        print(sections[task], flush=True)
    if args.out:
        # the sections of the tasks not rerun are kept, in the order of TASKS
        kept = read_sections(args.out) if os.path.exists(args.out) else {}
        body = [sections.get(t, kept.get(t)) for t in TASKS]
        with open(args.out, "w") as f:
            f.write("\n".join(head + [b for b in body if b]))


def read_sections(path: str) -> dict:
    """The per-task sections (``## Task`` to the next) of a table this bench wrote."""
    text = open(path).read()
    parts = text.split("\n## ")[1:]
    return {p.split("\n", 1)[0]: "## " + p.rstrip("\n") + "\n" for p in parts}


if __name__ == "__main__":
    main()
