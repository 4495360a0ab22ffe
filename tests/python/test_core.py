"""The Python surface of the core: Model and Sim contracts, state round-trips, bad input."""

import warnings

import numpy as np
import pytest

import sinew
from conftest import gym_model_path

PENDULUM = """<mujoco><option timestep="0.01"/><worldbody><body name="pole">
<joint name="hinge" type="hinge" axis="0 1 0" damping="0.1"/><geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05"/>
</body></worldbody><actuator><motor name="m" joint="hinge" gear="2" ctrlrange="-1 1"/></actuator></mujoco>"""


def test_model_properties():
    m = sinew.Model.from_mjcf_string(PENDULUM)
    assert (m.nq, m.nv, m.nu, m.nbody) == (1, 1, 1, 2)
    assert m.timestep == 0.01
    assert m.body_names == ["world", "pole"]
    assert m.joint_names == ["hinge"]
    assert m.actuator_names == ["m"]
    assert m.qpos0.dtype == np.float64 and m.qpos0.shape == (1,)
    assert m.body_mass[1] > 0


def test_model_loads_every_gym_file(gym_model):
    name, path = gym_model
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        m = sinew.Model.from_mjcf(path)
    assert m.nq > 0
    # every physics of these files is modelled (swimmer's fluid forces too)
    assert not m.warnings
    assert not any(issubclass(x.category, sinew.ModelWarning) for x in w)


def test_arrays_are_assignable_in_place_and_shape_checked():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(PENDULUM))
    sim.qpos[:] = 0.3
    assert sim.qpos[0] == 0.3
    sim.qvel = [1.5]
    assert sim.qvel[0] == 1.5
    sim.ctrl = np.array([0.5])
    for bad in ([1.0, 2.0], np.zeros((1, 1))):
        with pytest.raises(ValueError, match="shape"):
            sim.qpos = bad
    with pytest.raises(ValueError, match="finite"):
        sim.ctrl = [np.nan]


def test_forward_does_not_advance_and_step_does():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(PENDULUM))
    sim.qpos[:] = 0.5
    sim.forward()
    assert sim.time == 0.0 and sim.qpos[0] == 0.5
    assert sim.qacc[0] < 0  # gravity pulls the pendulum back
    sim.step(10)
    assert sim.time == pytest.approx(0.1)
    assert sim.qpos[0] < 0.5


def test_state_round_trips_bit_exactly():
    m = sinew.Model.from_mjcf(gym_model_path("humanoid"))
    sim = sinew.Sim(m)
    rng = np.random.default_rng(0)
    sim.qvel[:] = rng.normal(size=m.nv)
    sim.ctrl[:] = rng.uniform(-0.4, 0.4, size=m.nu)
    sim.step(7)
    state, full = sim.get_state(), sim.get_state(full=True)
    sim.step(20)
    after = sim.get_state()
    sim.set_state(state)
    assert np.array_equal(sim.get_state(), state)
    sim.set_state(full)
    assert np.array_equal(sim.get_state(full=True), full)
    sim.step(20)
    assert np.array_equal(sim.get_state(), after)


def ant_on_its_floor(steps, seed=1):
    """An Ant with pyramid friction under random controls, after `steps` steps: persisting
    contacts, tangents and warm starts in its history."""
    m = sinew.Model.from_mjcf(gym_model_path("ant")).with_options(friction="pyramid")
    sim = sinew.Sim(m)
    drive(sim, steps, seed)
    return m, sim


def drive(sim, steps, seed):
    rng = np.random.default_rng(seed)
    for _ in range(steps // 5):
        sim.ctrl[:] = rng.uniform(-1, 1, size=sim.model.nu)
        sim.step(5)


def test_full_state_steps_exactly_as_the_sim_it_came_from():
    m, sim = ant_on_its_floor(200)
    full = sim.get_state(full=True)
    short = 1 + m.nq + m.nv + m.nu
    tangents = int(full[short + 2 * m.nu + 3])
    assert tangents > 0, "the ant stands on its feet: its contacts keep friction tangents"
    assert np.array_equal(full[:short], sim.get_state())
    drive(sim, 300, seed=2)
    copy = sinew.Sim(m)
    copy.set_state(full)
    assert np.array_equal(copy.get_state(full=True), full)
    drive(copy, 300, seed=2)
    np.testing.assert_array_equal(copy.get_state(full=True), sim.get_state(full=True))


def test_a_short_state_steps_as_a_new_sim_given_it():
    m, sim = ant_on_its_floor(200)
    state = sim.get_state()
    sim.set_state(state)
    new = sinew.Sim(m)
    new.set_state(state)
    assert np.array_equal(sim.get_state(full=True), new.get_state(full=True))
    drive(sim, 300, seed=2)
    drive(new, 300, seed=2)
    np.testing.assert_array_equal(sim.get_state(full=True), new.get_state(full=True))


def test_a_bad_history_is_a_value_error_naming_it():
    m, sim = ant_on_its_floor(100)
    full = sim.get_state(full=True)
    h = 1 + m.nq + m.nv + 3 * m.nu  # where the history starts
    assert int(full[h + 3]) > 0
    first = h + 4  # the first tangent: geom1, geom2, feature, t
    cases = {
        "regrow rate": (h, 2.0),
        "random state": (h + 1, 0.5),
        "tangent count": (h + 3, -1.0),
        "geom1": (first, float(m.ngeom)),
        "unit vector": (first + 3, 3.0),
        "constrained last step": (len(full) - 2, 0.5),
        "sliding dof count": (len(full) - 1, 0.5),
    }
    for what, (i, value) in cases.items():
        bad = full.copy()
        bad[i] = value
        with pytest.raises(ValueError, match=what):
            sim.set_state(bad)
    with pytest.raises(ValueError, match="more than its counts"):
        sim.set_state(np.append(full, 0.0))
    with pytest.raises(ValueError, match="ends at element|inside a tangent"):
        sim.set_state(full[: first + 4])
    assert np.array_equal(sim.get_state(full=True), full)


def test_reset_restores_reference():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(PENDULUM))
    sim.qvel[:] = 3
    sim.step(5)
    sim.reset()
    assert sim.time == 0 and sim.qpos[0] == 0 and sim.qvel[0] == 0


def test_set_state_rejects_bad_input_and_leaves_state_alone():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(PENDULUM))
    sim.qpos[:] = 0.2
    before = sim.get_state()
    with pytest.raises(ValueError, match="shape"):
        sim.set_state(before[:-1])
    bad = before.copy()
    bad[1] = np.inf
    with pytest.raises(ValueError, match="finite"):
        sim.set_state(bad)
    assert np.array_equal(sim.get_state(), before)


def test_nan_in_state_or_ctrl_is_a_value_error_not_a_panic():
    sim = sinew.Sim(sinew.Model.from_mjcf_string(PENDULUM))
    sim.ctrl[:] = np.nan
    with pytest.raises(ValueError, match=r"ctrl\[0\]"):
        sim.step()
    sim.ctrl[:] = 0
    sim.qvel[:] = np.inf
    with pytest.raises(ValueError, match=r"qvel\[0\]"):
        sim.forward()


def test_divergence_raises_and_restores():
    # a free body pushed to astronomic speed leaves the 1e10 bound within a step
    m = sinew.Model.from_mjcf_string(
        "<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>"
    )
    sim = sinew.Sim(m)
    sim.qvel[:3] = 1e9
    sim.qpos[0] = 9.99e9
    before = sim.get_state()
    with pytest.raises(sinew.SimulationError, match=r"qpos\[0\]"):
        sim.step(100)
    assert np.array_equal(sim.get_state(), before)


def test_ctrl_is_clamped_to_ctrlrange():
    m = sinew.Model.from_mjcf_string(PENDULUM)
    a, b = sinew.Sim(m), sinew.Sim(m)
    a.ctrl[:] = 1.0
    b.ctrl[:] = 50.0
    a.forward()
    b.forward()
    assert a.qacc[0] == b.qacc[0]


def test_with_options_validates():
    m = sinew.Model.from_mjcf_string(PENDULUM)
    assert m.with_options(integrator="RK4").integrator == "RK4"
    assert m.with_options(integrator="leapfrog").integrator == "leapfrog"
    assert m.integrator == "Euler"
    with pytest.raises(ValueError):
        m.with_options(timestep=-1.0)
    with pytest.raises(ValueError):
        m.with_options(integrator="Verlet")


@pytest.mark.parametrize("dt", [0.002, 0.01])
def test_leapfrog_is_exact_in_free_fall_where_euler_lags_by_g_h_t_over_2(dt):
    """A thrown ball under gravity: leapfrog (drift–kick–drift) is exact under constant
    acceleration; semi-implicit Euler's height is off by g·h·t/2, first order in h."""
    xml = f'''<mujoco><option timestep="{dt}"/><worldbody><body pos="0 0 10"><freejoint/>
    <geom type="sphere" size="0.1"/></body></worldbody></mujoco>'''
    t = 1.0
    exact = 10.0 + 3.0 * t - 0.5 * 9.81 * t**2
    for integrator, expected in [("leapfrog", exact), ("Euler", exact - 0.5 * 9.81 * dt * t)]:
        sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(integrator=integrator))
        sim.qvel[2] = 3.0
        sim.step(round(t / dt))
        assert abs(sim.qpos[2] - expected) < 1e-9, integrator


def test_malformed_mjcf_raises_model_error_with_location():
    with pytest.raises(sinew.ModelError) as e:
        sinew.Model.from_mjcf_string("<mujoco>\n<worldbody>\n<body>\n<joint range='1 x'/></body></worldbody></mujoco>")
    assert (e.value.element, e.value.attribute, e.value.line) == ("joint", "range", 4)
    assert "line 4" in str(e.value)
    with pytest.raises(sinew.ModelError) as e:
        sinew.Model.from_mjcf_string("<mujoco><worldbody>")
    assert e.value.line == 1
    assert isinstance(e.value, ValueError)
    with pytest.raises(OSError):
        sinew.Model.from_mjcf("/nonexistent/model.xml")


def test_unsupported_mjcf_raises_model_error():
    with pytest.raises(sinew.ModelError, match="mesh"):
        sinew.Model.from_mjcf_string("<mujoco><worldbody><body><geom type='mesh'/></body></worldbody></mujoco>")


def test_pd_actuation_servos_to_the_target_within_the_motor_limit():
    xml = """<mujoco><option gravity="0 0 0" timestep="0.002"/><worldbody><body>
    <joint name="j" axis="0 0 1"/><geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/></body></worldbody>
    <actuator><motor joint="j" gear="10" ctrlrange="-1 1"/></actuator></mujoco>"""
    m = sinew.Model.from_mjcf_string(xml).with_options(pd_gains=(5.0, 0.5))
    assert m.pd_gains == (5.0, 0.5)
    sim = sinew.Sim(m)
    sim.ctrl[:] = 0.5  # target angle, rad
    sim.forward()
    # 5 · 0.5 = 2.5 saturates at ctrlrange 1: torque = gear · 1
    inertia = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    inertia.ctrl[:] = 1.0
    inertia.forward()
    assert sim.qacc[0] == pytest.approx(inertia.qacc[0])
    sim.step(5000)
    assert sim.qpos[0] == pytest.approx(0.5, abs=1e-6)
    with pytest.raises(ValueError):
        m.with_options(pd_gains=(-1.0, 0.0))


def test_model_sim_and_batch_pickle_and_copy_with_their_full_state():
    import copy
    import pickle

    from conftest import gym_model_path

    m = sinew.Model.from_mjcf(gym_model_path("ant")).with_options(friction="one_tangent", pd_gains=(4.0, 0.2))
    m2 = pickle.loads(pickle.dumps(m))
    assert repr(m2) == repr(m) and m2.timestep == m.timestep
    sim = sinew.Sim(m)
    sim.ctrl[:] = 0.3
    sim.step(150)
    twin = pickle.loads(pickle.dumps(sim))
    deep = copy.deepcopy(sim)
    for s in (sim, twin, deep):
        s.step(100)
    assert np.array_equal(sim.qpos, twin.qpos) and np.array_equal(sim.qpos, deep.qpos) and sim.time == twin.time
    from sinew.tasks import Ant

    b = sinew.Batch(m, 3, num_threads=2)
    b.set_task("Ant", **Ant(m).params())
    b.ctrl[:] = np.linspace(-0.5, 0.5, 3 * m.nu).reshape(3, m.nu)
    b.step(40)
    c = pickle.loads(pickle.dumps(b))
    assert c.num_threads == 2 and np.array_equal(c.obs, b.obs)
    b.step(60)
    c.step(60)
    assert np.array_equal(b.qpos, c.qpos) and np.array_equal(b.reward, c.reward)


def test_envs_pickle_and_deep_copy_with_their_state():
    import copy
    import pickle

    import gymnasium as gym

    env = gym.make("sinew/Hopper-v0").unwrapped
    env.reset(seed=4)
    rng = np.random.default_rng(1)
    for _ in range(30):
        env.step(rng.uniform(-1, 1, 3))
    for dup in (lambda e: copy.deepcopy(e), lambda e: pickle.loads(pickle.dumps(e))):
        dup = dup(env)
        for _ in range(300):
            a = rng.uniform(-1, 1, 3)
            r1, r2 = env.step(a), dup.step(a)
            assert np.array_equal(r1[0], r2[0]) and r1[1:4] == r2[1:4]
            if r1[2]:
                assert np.array_equal(env.reset()[0], dup.reset()[0]), "the generators continue alike"
    venv = gym.make_vec("sinew/Hopper-v0", num_envs=3, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    venv.step(rng.uniform(-1, 1, (3, 3)))
    vdup = pickle.loads(pickle.dumps(venv))
    for _ in range(200):
        a = rng.uniform(-1, 1, (3, 3))
        r1, r2 = venv.step(a), vdup.step(a)
        for x, y in zip(r1[:4], r2[:4]):
            assert np.array_equal(x, y)


def _step_copy(sim_and_n):
    sim, n = sim_and_n
    sim.step(n)
    return sim


def test_sims_and_envs_ship_to_other_processes():
    import multiprocessing

    import gymnasium as gym
    from gymnasium.vector import AsyncVectorEnv, SyncVectorEnv

    from conftest import gym_model_path

    sim = sinew.Sim(sinew.Model.from_mjcf(gym_model_path("ant")))
    sim.step(20)
    with multiprocessing.get_context("fork").Pool(1) as pool:
        remote = pool.map(_step_copy, [(sim, 50)])[0]
    sim.step(50)
    assert np.array_equal(remote.qpos, sim.qpos) and remote.get_state(full=True).tolist() == sim.get_state(full=True).tolist()
    fns = [lambda: gym.make("sinew/Hopper-v0")] * 2
    a, s = AsyncVectorEnv(fns), SyncVectorEnv(fns)
    oa, _ = a.reset(seed=0)
    os_, _ = s.reset(seed=0)
    assert np.array_equal(oa, os_)
    rng = np.random.default_rng(0)
    for _ in range(30):
        act = rng.uniform(-1, 1, (2, 3))
        ra, rs = a.step(act), s.step(act)
        for x, y in zip(ra[:4], rs[:4]):
            assert np.array_equal(x, y)
    a.close()
