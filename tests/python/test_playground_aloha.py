"""ALOHA's Playground tasks: the observations Playground computes (against MuJoCo at the same
state), the hand-over's potential-progress reward, and the peg insertion's repeated action."""

import gymnasium as gym
import mujoco
import numpy as np

import sinew  # noqa: F401  (registers the envs)
from sinew.playground import assets_dir

ALOHA = "mujoco_playground/_src/manipulation/aloha/xmls"


def mujoco_at(xml: str, core, i: int):
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{ALOHA}/{xml}")
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:], d.ctrl[:] = core.batch.qpos[i], core.batch.qvel[i], core.batch.ctrl[i]
    mujoco.mj_forward(mj, d)
    return mj, d


def test_handover_observes_what_mujoco_reads_and_pays_only_progress():
    env = gym.make_vec("sinew/playground-AlohaHandOver-v0", num_envs=16, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    task = core.task
    assert (task.target_pos[:, 0] >= 0.15).all() and (np.abs(task.target_pos - [0.2, 0.0, 0.25]) <= 0.15 + 1e-12).all()
    obs, reward, _, _, info = env.step(np.random.default_rng(0).uniform(-1, 1, (16, 14)))
    np.testing.assert_array_equal(reward, 0.0)          # an episode's first step pays nothing
    assert (core.batch.ctrl[:, 6] >= 0.01).all()        # the left gripper's raised lower bound
    mj, d = mujoco_at("mjx_hand_over.xml", core, 3)
    s = lambda n: d.site(n).xpos  # noqa: E731
    box = mj.body("box").id
    fingers = [mj.jnt_qposadr[mj.joint(j).id] for j in ("left/left_finger", "left/right_finger", "right/left_finger",
                                                          "right/right_finger")]
    expect = np.concatenate([d.qpos, d.qvel, d.qpos[fingers] - mj.geom("box").size[1], s("box_top"), s("box_bottom"),
                             s("left/gripper"), d.site("left/gripper").xmat[3:], s("right/gripper"), d.site("right/gripper").xmat[3:],
                             d.xmat[box][3:], d.xpos[box] - task.target_pos[3], [1 / 250]])
    np.testing.assert_allclose(obs[3], expect, atol=2e-5)
    potential = sum(info[k] for k in ("gripper_box", "box_handover", "handover_target", "no_table_collision")) / 13.3
    np.testing.assert_allclose(task.prev_potential, potential, rtol=1e-12)
    _, reward, _, _, info = env.step(np.zeros((16, 14)))
    now = sum(info[k] for k in ("gripper_box", "box_handover", "handover_target", "no_table_collision")) / 13.3
    assert (reward >= 0.02 * now * 0.0).all() and (reward <= np.maximum(now - potential, 0) + 0.02 * now + 1e-12).all()


def test_peg_insertion_holds_each_action_for_two_steps_and_observes_what_mujoco_reads():
    env = gym.make_vec("sinew/playground-AlohaSinglePegInsertion-v0", num_envs=8, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=0)
    core = env.unwrapped._core
    assert gym.make("sinew/playground-AlohaSinglePegInsertion-v0").unwrapped.dt == 0.005
    ctrl = core.batch.ctrl.copy()
    a = np.random.default_rng(1).uniform(-1, 1, (8, 14))
    obs, reward, _, _, info = env.step(a)
    lo, hi = core.model.actuator_ctrlrange.T
    np.testing.assert_allclose(core.batch.ctrl, np.clip(np.clip(ctrl + 0.005 * a, lo, hi) + 0.005 * a, lo, hi))
    np.testing.assert_allclose(core.batch.time, 0.005)
    assert (info["no_table_collision"] <= 2 * 0.3 + 1e-12).all()     # two steps' terms summed
    mj, d = mujoco_at("mjx_single_peg_insertion.xml", core, 2)
    socket, peg = mj.body("socket").id, mj.body("peg").id
    expect = np.concatenate([d.qpos, d.qvel, d.site("left/gripper").xpos, d.xpos[socket], d.site("right/gripper").xpos,
                             d.xpos[peg], d.site("socket_entrance").xpos, d.site("peg_end2").xpos, d.xmat[socket][6:],
                             d.xmat[peg][6:]])
    np.testing.assert_allclose(obs[2], expect, atol=2e-5)
    # the socket sits on the left (x < 0), the peg on the right, each moved by at most 0.1 m
    home = mj.keyframe("home").qpos
    for body in (socket, peg):
        adr = mj.jnt_qposadr[mj.body_jntadr[body]]
        moved = core.batch.qpos[:, adr:adr + 2] - home[adr:adr + 2]
        assert (np.abs(moved) <= 0.1 + 1e-3).all()
    assert (core.batch.qpos[:, mj.jnt_qposadr[mj.body_jntadr[socket]]] < 0).all()
