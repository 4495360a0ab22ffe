"""dm_control's own observations and rewards at given states, for tests/python/test_dmc.py.

Run as ``python dmc_reference.py IN.npz OUT.npz`` with a MuJoCo dm_control can load (3.17:
dm-control 1.0.50 reads model fields MuJoCo 4 no longer has). IN holds, per task key
``<domain>-<task>``, arrays ``<key>/qpos``, ``/qvel``, ``/ctrl``, ``/act`` (one row per state), ``<key>/geom/<name>``,
``<key>/site/<name>`` (where each state places a geom or site, a target), ``<key>/body_pos/<name>``
and ``<key>/body_quat/<name>`` (where each state places a body fixed to the world), ``<key>/hfield`` (each
state's height-field elevations, where worlds have their own) and
``<key>/sensor/<name>`` (sinew's readings, which the sensors that read contact forces take);
OUT gets
``<key>/obs`` (dm_control's observation flattened in its key order), ``<key>/reward`` and
``<key>/keys`` (each observation key repeated over its entries), and ``<key>/reset`` (initial
(qpos, qvel) of as many episodes as IN's ``<key>/episodes``, one generator seeded 0).
"""

import sys

import mujoco
import numpy as np
from dm_control import suite
from dm_control.mujoco import engine

# quadruped-escape uploads each new terrain to a rendering context when asked for one; the
# reference renders nothing (and has no OpenGL here)
engine.Physics.contexts = property(lambda self: None)


def main(src: str, dst: str) -> None:
    data = dict(np.load(src))
    out = {}
    for key in sorted({k.split("/")[0] for k in data}):
        domain, task = key.split("-", 1)
        env = suite.load(domain, task, task_kwargs={"random": 0})
        env.reset()  # a task's changes to the model (target sizes) are made at the reset
        phys, t = env.physics, env.task
        obs, rewards, names = [], [], []
        # sensors that read contact forces take sinew's readings (the simulators' contacts differ)
        contact_kinds = {int(k) for k in (mujoco.mjtSensor.mjSENS_TOUCH, mujoco.mjtSensor.mjSENS_ACCELEROMETER,
                                           mujoco.mjtSensor.mjSENS_FORCE, mujoco.mjtSensor.mjSENS_TORQUE)}
        given = [phys.model.sensor(i).name for i in range(phys.model.nsensor) if int(phys.model.sensor_type[i]) in contact_kinds]
        given = [n for n in given if f"{key}/sensor/{n}" in data]
        placed = [(k.split("/")[1], k.split("/")[2], v) for k, v in data.items() if k.startswith((f"{key}/geom/", f"{key}/site/"))]
        for i, (q, v, u, a) in enumerate(zip(data[f"{key}/qpos"], data[f"{key}/qvel"], data[f"{key}/ctrl"], data[f"{key}/act"])):
            for kind, name, pos in placed:
                getattr(phys.named.model, f"{kind}_pos")[name] = pos[i]
            for field in ("body_pos", "body_quat"):
                for entry, values in data.items():
                    if entry.startswith(f"{key}/{field}/"):
                        getattr(phys.named.model, field)[entry.split("/")[2]] = values[i]
            if f"{key}/hfield" in data:
                phys.model.hfield_data[:] = data[f"{key}/hfield"][i]
            with phys.reset_context():
                phys.data.qpos[:], phys.data.qvel[:], phys.data.ctrl[:], phys.data.act[:] = q, v, u, a
            for n in given:
                phys.named.data.sensordata[n] = data[f"{key}/sensor/{n}"][i]
            o = t.get_observation(phys)
            obs.append(np.concatenate([np.asarray(x, dtype=np.float64).ravel() for x in o.values()]))
            names = [k for k, x in o.items() for _ in range(np.asarray(x).size)]
            rewards.append(t.get_reward(phys))
        out[f"{key}/obs"], out[f"{key}/reward"], out[f"{key}/keys"] = np.array(obs), np.array(rewards), np.array(names)
        starts = []
        for _ in range(int(data.get(f"{key}/episodes", 0))):
            env.reset()
            starts.append(np.concatenate([phys.data.qpos, phys.data.qvel]))
        out[f"{key}/reset"] = np.array(starts)
    np.savez(dst, **out)


if __name__ == "__main__":
    main(*sys.argv[1:])
