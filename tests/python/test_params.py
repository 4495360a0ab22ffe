"""Per-world model values (Batch.set_params) and the domain-randomization wrappers: values
applied and derived exactly, analytic effects, bad values refused whole, determinism, pickling."""

import pickle

import gymnasium as gym
import numpy as np
import pytest

import sinew
from conftest import gym_model_path

FIELDS = ["body_mass", "body_ipos", "body_inertia", "geom_friction", "dof_damping", "dof_armature", "dof_frictionloss",
          "jnt_stiffness", "actuator_gain", "actuator_bias", "actuator_gear", "actuator_ctrlrange", "gravity", "wrap_prm", "hfield_data"]

# a block on a slider pushed by a motor: q̈ = gear · ctrl / (mass + armature) while nothing else acts
SLIDER = """<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody><body name="block">
<joint name="x" type="slide" axis="1 0 0"/><geom type="box" size="0.1 0.1 0.1" mass="2"/></body></worldbody>
<actuator><motor joint="x" gear="3" ctrlrange="-1 1"/></actuator></mujoco>"""

# a box resting on the floor; tilting gravity by θ makes a slope of angle θ
BOX = """<mujoco><option timestep="0.005"/><worldbody><geom name="floor" type="plane" size="5 5 0.1"/>
<body name="box" pos="0 0 0.1"><freejoint/><geom name="b" type="box" size="0.1 0.1 0.1" mass="1" friction="0.5"/></body>
</worldbody></mujoco>"""


def hopper_batch(n=4, threads=1):
    b = sinew.Batch(sinew.Model.from_mjcf(gym_model_path("hopper")), n, seed=3, num_threads=threads)
    b.qvel[:] = np.random.default_rng(0).normal(0, 0.5, b.qvel.shape)
    return b


def roll(b, steps=60):
    rng = np.random.default_rng(1)
    out = []
    for _ in range(steps):
        b.ctrl[:] = rng.uniform(-1, 1, b.ctrl.shape)
        b.step(4)
        out.append(np.concatenate([b.qpos, b.qvel], axis=1).copy())
    return np.array(out)


def test_every_field_reads_as_the_model_and_takes_its_own_values_back_bit_for_bit():
    b = hopper_batch()
    m = b.model
    for f in FIELDS:
        assert np.array_equal(b.params(f), np.broadcast_to(m.param(f), (4,) + m.param(f).shape)), f
    plain = roll(hopper_batch())
    # world 2 gets every field set to the model's own values: it steps exactly as before
    for f in FIELDS:
        b.set_params(f, m.param(f), [2])
    assert np.array_equal(roll(b), plain)


def test_values_land_in_the_chosen_worlds_only_and_reset_params_takes_them_back():
    b = hopper_batch()
    mass = b.model.param("body_mass")
    b.set_params("body_mass", mass * 1.5, [1, 3])
    got = b.params("body_mass")
    assert np.array_equal(got[[0, 2]], np.tile(mass, (2, 1)))
    assert np.allclose(got[[1, 3]], mass * 1.5)
    # the inertia scales with the mass
    assert np.allclose(b.params("body_inertia")[1], b.model.param("body_inertia") * 1.5)
    b.set_params("gravity", [[0, 0, -1], [0, 0, -2]], worlds=np.array([False, True, True, False]))
    assert np.array_equal(b.params("gravity")[:, 2], [-9.81, -1, -2, -9.81])
    b.reset_params([1])
    assert np.array_equal(b.params("body_mass")[1], mass)
    b.reset_params()
    plain = roll(hopper_batch())
    assert np.array_equal(roll(b), plain)


def test_mass_armature_and_gear_give_the_analytic_acceleration():
    b = sinew.Batch(sinew.Model.from_mjcf_string(SLIDER), 3)
    b.set_params("body_mass", [[0, 1], [0, 2], [0, 4]])
    b.set_params("dof_armature", [[0.0], [0.5], [1.0]])
    b.set_params("actuator_gear", [[1.0], [3.0], [2.0]])
    b.ctrl[:] = 0.5
    b.step(1)
    expected = np.array([1 * 0.5 / 1, 3 * 0.5 / 2.5, 2 * 0.5 / 5]) * 0.01
    assert np.allclose(b.qvel[:, 0], expected, rtol=1e-12)


def test_gravity_and_friction_per_world_decide_exactly_who_slides():
    g, theta = 9.81, np.radians(20)  # tan 20° = 0.364
    b = sinew.Batch(sinew.Model.from_mjcf_string(BOX), 4)
    b.set_params("gravity", [g * np.sin(theta), 0, -g * np.cos(theta)])
    friction = b.model.param("geom_friction")
    mu = np.array([0.2, 0.3, 0.5, 0.8])
    f = np.tile(friction, (4, 1, 1))
    f[:, :, 0] = mu[:, None]
    b.set_params("geom_friction", f)
    for _ in range(200):
        b.step()
    x = b.qpos[:, 0]
    # below the friction angle the box holds exactly; above it slides at g (sin θ − μ cos θ)
    assert np.all(np.abs(x[2:]) < 1e-9), x
    t = 200 * 0.005
    slide = 0.5 * g * (np.sin(theta) - mu[:2] * np.cos(theta)) * t * t
    assert np.allclose(x[:2], slide, rtol=0.02), (x[:2], slide)


def test_a_pairs_friction_per_world_overrides_the_geoms_as_in_mujoco():
    """``pair_friction`` (npair × 5, MuJoCo's): an explicit pair's contacts read its first value,
    whatever the geoms' friction; the file's trailing values are MuJoCo's defaults."""
    g, theta = 9.81, np.radians(20)
    xml = BOX.replace("</mujoco>", '<contact><pair geom1="floor" geom2="b" friction="0.9 0.9"/></contact></mujoco>')
    m = sinew.Model.from_mjcf_string(xml)
    assert np.array_equal(m.param("pair_friction"), [[0.9, 0.9, 0.005, 0.0001, 0.0001]])
    b = sinew.Batch(m, 4)
    b.set_params("gravity", [g * np.sin(theta), 0, -g * np.cos(theta)])
    mu = np.array([0.2, 0.3, 0.5, 0.8])
    f = np.tile(m.param("pair_friction"), (4, 1, 1))
    f[:, 0, 0] = mu
    b.set_params("pair_friction", f)
    assert np.array_equal(b.params("pair_friction")[:, 0, 0], mu)
    for _ in range(200):
        b.step()
    x, t = b.qpos[:, 0], 200 * 0.005
    assert np.all(np.abs(x[2:]) < 1e-9), x
    assert np.allclose(x[:2], 0.5 * g * (np.sin(theta) - mu[:2] * np.cos(theta)) * t * t, rtol=0.02), x
    with pytest.raises(ValueError, match="world 1.*pair_friction.*is negative"):
        b.set_params("pair_friction", -f[1], [1])


@pytest.mark.parametrize("field, values, what", [
    ("body_mass", lambda m: np.where(np.arange(m.nbody) == 2, -1.0, m.param("body_mass")), "is negative"),
    ("body_inertia", lambda m: np.where(np.arange(3) == 0, 10.0, m.param("body_inertia")), "triangle inequality"),
    ("body_inertia", lambda m: np.where(np.arange(3) == 0, 0.0, m.param("body_inertia")), "not positive definite"),
    ("geom_friction", lambda m: -m.param("geom_friction"), "is negative"),
    ("actuator_ctrlrange", lambda m: m.param("actuator_ctrlrange")[:, ::-1], "lower end is above"),
    ("dof_damping", lambda m: np.full(m.nv, np.nan), "not finite"),
    ("gravity", lambda m: [0, 0, np.inf], "not finite"),
])
def test_a_bad_value_names_the_world_and_field_and_changes_no_world(field, values, what):
    b = hopper_batch()
    before = {f: b.params(f) for f in FIELDS}
    good = b.model.param(field)
    rows = np.stack([good, good, np.asarray(values(b.model), dtype=float), good])
    with pytest.raises(ValueError, match=f"world 2.*{field}.*{what}"):
        b.set_params(field, rows)
    for f in FIELDS:
        assert np.array_equal(b.params(f), before[f]), f


def test_wrong_shapes_and_unknown_fields_are_refused():
    b = hopper_batch()
    with pytest.raises(ValueError, match="unknown parameter 'mass'.*body_mass"):
        b.set_params("mass", 1.0)
    with pytest.raises(ValueError, match="do not broadcast"):
        b.set_params("body_mass", np.ones(3))
    with pytest.raises(ValueError, match="massless|no mass"):
        b.set_params("body_mass", np.zeros(b.model.nbody), [0])


def test_varied_worlds_are_bit_identical_for_any_thread_count_and_survive_pickling():
    def varied(threads):
        b = hopper_batch(n=6, threads=threads)
        scale = np.linspace(0.8, 1.2, 6)
        b.set_params("body_mass", np.outer(scale, b.model.param("body_mass")))
        b.set_params("geom_friction", b.model.param("geom_friction") * scale[:, None, None])
        return b

    one, two = varied(1), varied(2)
    assert np.array_equal(roll(one, 20), roll(two, 20))
    copy = pickle.loads(pickle.dumps(one))
    for f in FIELDS:
        assert np.array_equal(copy.params(f), one.params(f)), f
    assert np.array_equal(roll(copy, 20), roll(one, 20))


PARAMS = {"body_mass": ("scale", 0.7, 1.3), "geom_friction": ("scale", 0.5, 1.5), "gravity": ("add", [-1, -1, -1], [1, 1, 1])}


def test_the_vector_wrapper_equals_single_wrapped_envs_seeded_in_turn():
    n = 3
    vec = sinew.VectorRandomizeParams(
        gym.make_vec("sinew/Hopper-v0", num_envs=n, vectorization_mode="vector_entry_point"), PARAMS)
    singles = [sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), PARAMS) for _ in range(n)]
    obs, _ = vec.reset(seed=7)
    for i, e in enumerate(singles):
        o, _ = e.reset(seed=7 + i)
        assert np.array_equal(o, obs[i])
    core = vec.unwrapped._core
    for f in PARAMS:
        for i, e in enumerate(singles):
            assert np.array_equal(core.batch.params(f)[i], e.unwrapped._core.batch.params(f)[0]), f
    a = np.random.default_rng(0).uniform(-1, 1, (200, n, 3))
    done, restarts = np.zeros(n, dtype=bool), 0
    for t in range(200):
        o, r, term, trunc, _ = vec.step(a[t])
        for i, e in enumerate(singles):
            if done[i]:
                # the world restarts in this step (next-step autoreset) with new values
                o1, r1 = e.reset()[0], 0.0
                restarts += 1
            else:
                o1, r1 = e.step(a[t, i])[:2]
            assert np.array_equal(o1, o[i]) and r1 == r[i]
        done = term | trunc
    assert restarts > 0


def test_draws_start_from_the_model_value_every_time():
    env = sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), {"body_mass": ("scale", 0.9, 1.1)})
    default = env.unwrapped.model.param("body_mass")
    seen = []
    for s in range(5):
        env.reset(seed=s)
        mass = env.unwrapped._core.batch.params("body_mass")[0]
        ratio = mass[1:] / default[1:]
        assert np.all((ratio >= 0.9) & (ratio <= 1.1)), ratio
        seen.append(mass)
    assert len({m.tobytes() for m in seen}) == 5


def test_when_start_draws_once_and_an_interval_draws_every_k_steps():
    once = sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), {"body_mass": ("scale", 0.5, 1.5)}, when="start")
    once.reset(seed=0)
    first = once.unwrapped._core.batch.params("body_mass").copy()
    once.reset()
    assert np.array_equal(once.unwrapped._core.batch.params("body_mass"), first)
    every = sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), {"dof_damping": ("set", 0.0, 2.0)}, when=3)
    every.reset(seed=0)
    assert np.array_equal(every.unwrapped._core.batch.params("dof_damping")[0], every.unwrapped.model.param("dof_damping"))
    values = []
    for _ in range(6):
        every.step(np.zeros(3))
        values.append(every.unwrapped._core.batch.params("dof_damping")[0].copy())
    assert np.array_equal(values[0], values[1]) and not np.array_equal(values[1], values[2])
    assert np.array_equal(values[2], values[4]) and not np.array_equal(values[4], values[5])
    with pytest.raises(ValueError, match="op must be one of"):
        sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), {"body_mass": ("times", 1, 2)})
    with pytest.raises(ValueError, match="when must be"):
        sinew.RandomizeParams(gym.make("sinew/Hopper-v0"), {"body_mass": ("scale", 1, 2)}, when=0)


def test_envs_pickle_with_their_worlds_own_values():
    env = gym.make_vec("sinew/Hopper-v0", num_envs=2, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    b = env.unwrapped._core.batch
    b.set_params("body_mass", b.model.param("body_mass") * 1.3, [1])
    copy = pickle.loads(pickle.dumps(env))
    assert np.array_equal(copy.unwrapped._core.batch.params("body_mass"), b.params("body_mass"))
    a = np.full((2, 3), 0.3)
    assert np.array_equal(copy.step(a)[0], env.step(a)[0])


TERRAIN = """<mujoco><option timestep="0.005"/><asset><hfield name="ground" nrow="3" ncol="3" size="2 2 0.3 0.1"/></asset>
<worldbody><light pos="0 0 3"/><geom type="hfield" hfield="ground" rgba=".4 .6 .4 1"/>
<body name="ball" pos="0 0 0.6"><freejoint/><geom type="sphere" size="0.1" mass="1"/></body></worldbody></mujoco>"""


def test_height_fields_per_world_carry_and_show_each_worlds_terrain():
    b = sinew.Batch(sinew.Model.from_mjcf_string(TERRAIN), 3)
    assert b.params("hfield_data").shape == (3, 9)
    raised = np.full(9, 0.5)
    b.set_params("hfield_data", raised, [1])
    # a ball 0.2 m up overlaps only the raised terrain (0.15 m) of world 1
    b.qpos[:, 2] = 0.2
    b.forward_kinematics()
    assert b.penetrations().tolist() == [0, 1, 0]
    for _ in range(400):
        b.step()
    # the ball rests on its own world's surface: z = elevation · 0.3 + radius
    assert np.allclose(b.qpos[:, 2], [0.1, 0.25, 0.1], atol=1e-6)
    frames = b.render(64, 64, camera={"lookat": [0, 0, 0], "distance": 3, "elevation": -20})
    assert not np.array_equal(frames[0], frames[1]) and np.array_equal(frames[0], frames[2])
    copy = pickle.loads(pickle.dumps(b))
    assert np.array_equal(copy.params("hfield_data"), b.params("hfield_data"))
    assert np.array_equal(copy.render(64, 64, camera={"lookat": [0, 0, 0], "distance": 3, "elevation": -20}), frames)
    b.reset_params([1])
    b.qpos[1] = b.qpos[0]
    b.forward_kinematics()
    again = b.render(64, 64, camera={"lookat": [0, 0, 0], "distance": 3, "elevation": -20})
    assert np.array_equal(again[0], again[1])


def test_only_bodies_fixed_to_the_world_are_placed_per_world():
    xml = """<mujoco><worldbody><body name="target" pos="1 0 0"><geom size=".1" contype="0" conaffinity="0"/></body>
<body name="ball" pos="0 0 1"><freejoint/><geom size=".1"/></body></worldbody></mujoco>"""
    b = sinew.Batch(sinew.Model.from_mjcf_string(xml), 2)
    pos = b.params("body_pos")
    pos[1, 1] = [0, 2, 0.5]
    b.set_params("body_pos", pos)
    quat = b.params("body_quat")
    quat[1, 1] = [0, 0, 0, 2]  # normalized when set
    b.set_params("body_quat", quat)
    b.forward_kinematics()
    assert np.allclose(b.xpos[:, 1], [[1, 0, 0], [0, 2, 0.5]])
    assert np.allclose(b.xmat[1, 1].reshape(3, 3), np.diag([-1, -1, 1]))
    # a copy holds the same placements bit for bit
    copy = pickle.loads(pickle.dumps(b))
    for f in ("body_pos", "body_quat"):
        assert np.array_equal(copy.params(f), b.params(f))
    # each world's frame shows the body where that world placed it
    view = {"lookat": [0.5, 0.5, 0.5], "distance": 4, "elevation": -30}
    frames = b.render(64, 64, camera=view)
    plain = sinew.Batch(b.model, 1).render(64, 64, camera=view)
    assert np.array_equal(frames[0], plain[0]) and not np.array_equal(frames[1], plain[0])
    moved = b.params("body_pos")
    moved[0, 2] = [0, 0, 3]
    with pytest.raises(ValueError, match="world 0.*body_pos\\[2\\].*'ball' is not fixed to the world"):
        b.set_params("body_pos", moved)
    zero = b.params("body_quat")
    zero[:, 1] = 0
    with pytest.raises(ValueError, match="body_quat\\[1\\] is zero"):
        b.set_params("body_quat", zero)


# three equalities of three kinds in one file: MuJoCo numbers them in file order
EQUALITIES = """<mujoco><option timestep="0.005"/><worldbody>
<body name="a" pos="0 0 1"><joint name="ja" type="slide" axis="0 0 1"/><geom size="0.1" mass="1"/></body>
<body name="b" pos="1 0 1"><joint name="jb" type="slide" axis="0 0 1"/><geom size="0.1" mass="1"/></body>
<body name="c" pos="2 0 1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
<body name="d" pos="3 0 1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
</worldbody><equality><joint joint1="ja" joint2="jb"/><weld body1="c" active="false"/><connect body1="d" anchor="0 0 0.1"/></equality>
</mujoco>"""


def test_eq_active_is_mujocos_and_switches_each_worlds_equalities_at_run_time():
    import mujoco
    m = sinew.Model.from_mjcf_string(EQUALITIES)
    np.testing.assert_array_equal(m.param("eq_active"), mujoco.MjModel.from_xml_string(EQUALITIES).eq_active0)
    b = sinew.Batch(m, 3, num_threads=1)
    b.set_params("eq_active", [1, 1, 1], worlds=[1])   # world 1: the weld holds c too
    b.set_params("eq_active", [0, 0, 0], worlds=[2])   # world 2: nothing holds
    np.testing.assert_array_equal(b.params("eq_active"), [[1, 0, 1], [1, 1, 1], [0, 0, 0]])
    b.qvel[:, 0] = 1.0   # ja thrown up: coupled, jb goes with it
    b.step(100)
    ja, jb, c_z, d_z = b.qpos[:, 0], b.qpos[:, 1], b.qpos[:, 4], b.qpos[:, 11]
    np.testing.assert_allclose(ja[:2], jb[:2], atol=1e-6)
    assert ja[2] - jb[2] > 0.45                              # off: each on its own
    assert abs(c_z[1] - 1.0) < 1e-6 and c_z[0] < 0.6 and c_z[2] < 0.6   # the weld holds c in world 1 only
    assert abs(d_z[0] - 1.0) < 1e-3 and d_z[2] < 0.6        # the connect holds d where it acts
    with pytest.raises(ValueError, match="eq_active"):
        b.set_params("eq_active", [1, 0.5, 1])
    # a world given the model's own flags steps as one without
    fresh = sinew.Batch(m, 1, num_threads=1)
    fresh.qvel[:, 0] = 1.0
    fresh.step(100)
    np.testing.assert_array_equal(fresh.qpos[0], b.qpos[0])
