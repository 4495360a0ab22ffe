"""The LEAP hand's Playground task: its privileged state against MuJoCo at the same state, the
reset and randomization Playground draws, and a cube that rests in the still hand."""

import gymnasium as gym
import mujoco
import numpy as np

import sinew  # noqa: F401  (registers the envs)
from sinew.playground import assets_dir
from sinew.playground.leap import JOINTS, TIPS

XML = "mujoco_playground/_src/manipulation/leap_hand/xmls/scene_mjx_cube.xml"


def test_leap_observes_what_mujoco_reads_at_the_same_state():
    env = gym.make("sinew/playground-LeapCubeRotateZAxis-v0", domain_randomization=False)
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{XML}")
    d = mujoco.MjData(mj)
    q_ids = [mj.jnt_qposadr[mj.joint(j).id] for j in JOINTS]
    obs, info = env.reset(seed=0)
    obs, _, _, _, info = env.step(np.random.default_rng(0).uniform(-1, 1, 16).astype(np.float32))
    u = env.unwrapped
    d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
    mujoco.mj_forward(mj, d)
    p = info["privileged_state"].astype(np.float64)
    cube = mj.body("cube").id
    expect = {"joints": (32, d.qpos[q_ids]), "velocities": (48, d.qvel[q_ids]), "servo forces": (64, d.actuator_force),
              "fingertips": (80, np.concatenate([d.sensor(f"{t}_position").data for t in TIPS])),
              "palm − cube": (92, d.sensor("palm_position").data - d.xpos[cube]), "cube quat": (95, d.xquat[cube]),
              "cube angvel": (99, d.sensor("cube_angvel").data), "cube linvel": (102, d.sensor("cube_linvel").data)}
    for name, (at, value) in expect.items():
        np.testing.assert_allclose(p[at:at + len(value)], value, rtol=1e-5, atol=1e-5, err_msg=name)
    assert (np.abs(obs[:16] - d.qpos[q_ids]) <= 0.05 + 1e-6).all()
    np.testing.assert_allclose(obs[16:32], p[16:32])


def test_leap_resets_and_randomizes_as_playground():
    env = gym.make_vec("sinew/playground-LeapCubeRotateZAxis-v0", num_envs=64, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    core = env.unwrapped._core
    m, b, task = core.model, core.batch, core.task
    cube = b.qpos[:, task.cube_q:task.cube_q + 7]
    assert (np.abs(cube[:, :3] - [0.1, 0.0, 0.05]) <= 0.01 + 1e-12).all()
    np.testing.assert_allclose(np.linalg.norm(cube[:, 3:], axis=1), 1.0, rtol=1e-12)
    assert np.abs(cube[:, 3:].mean(axis=0)).max() < 0.2, "orientations drawn all about"
    np.testing.assert_allclose(b.ctrl, b.qpos[:, task.q_ids])
    gain, bias = b.params("actuator_gain")[:, :, 0], b.params("actuator_bias")[:, :, 1]
    np.testing.assert_array_equal(bias, -gain)
    np.testing.assert_array_equal(task.gain, gain)
    ratio = gain / m.param("actuator_gain")[:, 0]
    assert (ratio >= 0.8).all() and (ratio <= 1.2).all() and ratio.std() > 0.05
    mass, inertia = b.params("body_mass"), b.params("body_inertia")
    scale = mass[:, task.cube] / m.param("body_mass")[task.cube]
    np.testing.assert_allclose(inertia[:, task.cube], np.outer(scale, m.param("body_inertia")[task.cube]), rtol=1e-12)
    palm = m.body_names.index("palm")
    np.testing.assert_allclose(inertia[:, palm], np.tile(m.param("body_inertia")[palm], (64, 1)), rtol=1e-12)
    tips = b.params("geom_friction")[:, task.tip_geoms, 0]
    assert (tips >= 0.5).all() and (tips <= 1.0).all() and (tips == tips[:, :1]).all()


def test_a_still_hand_holds_the_cube():
    """Holding the home pose, the cube stays in the hand for 5 s in every world."""
    env = gym.make_vec("sinew/playground-LeapCubeRotateZAxis-v0", num_envs=16, vectorization_mode="vector_entry_point")
    env.reset(seed=1)
    for _ in range(100):
        _, _, term, _, _ = env.step(np.zeros((16, 16)))
        assert not term.any()
    assert np.isfinite(env.unwrapped._core.batch.qpos).all()


def test_reorient_observes_the_cube_against_its_goal_and_pays_a_success():
    """LeapCubeReorient: the privileged state's cube readings against MuJoCo's (its rotation
    relative to the goal: the last six entries of mat(cube ⊗ goal⁻¹)); a cube within 0.1 rad of its
    goal is a success: +100 and the goal spins off at 1–5 rad/s per axis."""
    env = gym.make("sinew/playground-LeapCubeReorient-v0", domain_randomization=False)
    obs, info = env.reset(seed=0)
    u = env.unwrapped
    task = u._core.task
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/{XML}")
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
    mujoco.mj_forward(mj, d)
    cube = mj.body("cube").id
    goal_inv = np.zeros(4)
    mujoco.mju_negQuat(goal_inv, task.goal_quat[0])
    rel = np.zeros(4)
    mujoco.mju_mulQuat(rel, d.xquat[cube], goal_inv)
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, rel)
    p = info["privileged_state"].astype(np.float64)
    np.testing.assert_allclose(p[57 + 44:57 + 47], d.sensor("palm_position").data - d.xpos[cube], atol=1e-6)
    np.testing.assert_allclose(p[57 + 47:57 + 53], mat[3:], atol=1e-6)
    np.testing.assert_allclose(obs[16:32], obs[:16] - u._core.batch.ctrl[0], atol=1e-6)   # servo errors at reset
    # the goal set to the orientation the cube rests at after 1 s: a success
    for _ in range(20):
        env.step(np.zeros(16, np.float32))
    assert task.success_count[0] == 0
    task.goal_quat[0] = u.data_qpos[task.cube_q + 3:task.cube_q + 7]
    _, reward, _, _, info = env.step(np.zeros(16, np.float32))
    assert task.success_count[0] == 1 and reward > 99.0
    assert ((task.goal_quat_dquat[0] >= 1.0) & (task.goal_quat_dquat[0] <= 5.0)).all()
    np.testing.assert_allclose(np.linalg.norm(task.goal_quat[0]), 1.0, rtol=1e-12)


def test_aero_observes_its_tendons_and_servo_forces_as_mujoco():
    """AeroCubeRotateZAxis: the servos' forces on tendons and the thumb's joint (from the tendon and
    joint length sensors) equal MuJoCo's ``actuator_force``; the state's tendon lengths lie within
    5 mm of MuJoCo's."""
    env = gym.make("sinew/playground-AeroCubeRotateZAxis-v0", domain_randomization=False)
    env.reset(seed=0)
    obs, _, _, _, info = env.step(np.random.default_rng(0).uniform(-1, 1, 7).astype(np.float32))
    u = env.unwrapped
    mj = mujoco.MjModel.from_xml_path(f"{assets_dir()}/mujoco_playground/_src/manipulation/aero_hand/xmls/scene_mjx_cube.xml")
    d = mujoco.MjData(mj)
    d.qpos[:], d.qvel[:], d.ctrl[:] = u.data_qpos, u.data_qvel, u._core.batch.ctrl[0]
    mujoco.mj_forward(mj, d)
    p = info["privileged_state"].astype(np.float64)
    assert np.abs(d.actuator_force).max() > 1e-3
    np.testing.assert_allclose(p[46:53], d.actuator_force, rtol=1e-4, atol=1e-4)
    lengths = [d.sensor(s).data[0] for s in ("len_if", "len_mf", "len_rf", "len_pf", "len_th1", "len_th2")]
    assert (np.abs(obs[:6] - lengths) <= 0.005 + 1e-6).all()


def test_the_still_aero_hand_lets_the_cube_come_to_rest():
    """The Aero hand at its keyframe, controls held: the cube drops into the palm and rests there
    from 0.5 s on, as in MuJoCo. (A thin palm box's edge across the cube's face once touched at
    one point, about which the cube rocked in yaw at 1–4 rad/s for seconds.)"""
    path = f"{assets_dir()}/mujoco_playground/_src/manipulation/aero_hand/xmls/scene_mjx_cube.xml"
    mj = mujoco.MjModel.from_xml_path(path)
    sim = sinew.Sim(sinew.Model.from_mjcf(path))
    sim.qpos[:], sim.ctrl[:] = mj.key_qpos[0], mj.key_ctrl[0]
    sim.forward()
    spin = []
    for _ in range(200):   # 2 s at 0.01 s
        sim.step(1)
        spin.append(np.abs(sim.qvel[-3:]).max())
    assert max(spin[50:]) < 0.01, f"cube still turning at {max(spin[50:]):.3f} rad/s"
