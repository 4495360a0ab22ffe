"""Meshes and height fields from Python: every mesh option (refpos, refquat, scale, mirrored, the
four inertia modes) weighs as in MuJoCo; height-field elevations are read and replaced from Python
(what dm_control's terrain tasks do each episode), checked, and kept through pickling; a model
whose meshes lie beside its file pickles and loads from anywhere."""

import importlib.util
import os
import pickle

import mujoco
import numpy as np
import pytest

import sinew
from twins import assert_inertias_equal

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")
FRUSTUM = ("0.1 0 -0.04  0.05 0.08660254 -0.04  -0.05 0.08660254 -0.04  -0.1 0 -0.04  -0.05 -0.08660254 -0.04  "
           "0.05 -0.08660254 -0.04 0.06 0 0.04  0.03 0.05196152 0.04  -0.03 0.05196152 0.04  -0.06 0 0.04  "
           "-0.03 -0.05196152 0.04  0.03 -0.05196152 0.04")
TET = 'vertex="0 0 0  1 0 0  0 1 0  0 0 1" face="0 2 1  0 1 3  0 3 2  1 2 3"'
MESHES = f"""<mujoco><asset>
<mesh name="placed" vertex="{FRUSTUM}" refpos="0.01 0.02 0.03" refquat="0.9 0.3 0.2 0.1" scale="1 2 0.5"/>
<mesh name="hull" vertex="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1  0.5 0.2 0.9" inertia="convex"/>
<mesh name="shell" {TET} inertia="shell"/>
<mesh name="mirrored" {TET} inertia="exact" scale="-1 1 1"/>
</asset><worldbody>
<body pos="0 0 1" euler="10 20 30"><freejoint/><geom type="mesh" mesh="placed" pos="0.1 0.2 0.3" euler="5 6 7"/>
  <geom type="mesh" mesh="hull" density="500"/></body>
<body pos="1 0 1"><freejoint/><geom type="mesh" mesh="shell"/></body>
<body pos="2 0 1"><freejoint/><geom type="mesh" mesh="mirrored" mass="2"/></body>
</worldbody></mujoco>"""


def test_every_mesh_option_weighs_as_in_mujoco(tmp_path):
    path = tmp_path / "meshes.xml"
    path.write_text(MESHES)
    m, mj = sinew.Model.from_mjcf(path), mujoco.MjModel.from_xml_path(str(path))
    np.testing.assert_allclose(m.body_mass, mj.body_mass, rtol=1e-12)
    np.testing.assert_allclose(m.body_ipos, mj.body_ipos, atol=1e-12)
    assert_inertias_equal(np.array(m.body_inertia_tensor), mj, 1e-9)


def terrain():
    return sinew.Model.from_mjcf_string("""<mujoco><option timestep="0.002"/><asset>
        <hfield name="ground" nrow="21" ncol="21" size="1 1 0.5 0.1"/></asset><worldbody>
        <geom type="hfield" hfield="ground"/>
        <body pos="0.3 -0.2 1"><freejoint/><geom type="sphere" size="0.05"/></body></worldbody></mujoco>""")


def test_height_field_elevations_are_read_and_replaced_from_python():
    m = terrain()
    assert m.hfield_names == ["ground"]
    flat = m.hfield_data("ground")
    assert flat.shape == (21, 21) and not flat.any()
    # a bowl whose lowest point (the centre, elevation 0.5: 0.25 m) holds the ball dropped in it
    x, y = np.meshgrid(np.linspace(-1, 1, 21), np.linspace(-1, 1, 21))
    bowl = 1.0 - 0.5 * np.exp(-(x ** 2 + y ** 2))
    bowled = m.with_hfield_data(0, bowl)
    np.testing.assert_array_equal(bowled.hfield_data(0), bowl)
    assert not m.hfield_data(0).any(), "the original model is unchanged"
    sims = [sinew.Sim(bowled), sinew.Sim(m)]
    for _ in range(5000):
        for s in sims:
            s.step()
    in_bowl, on_flat = sims
    assert abs(on_flat.qpos[2] - 0.05) < 1e-6, "on the flat field the ball rests at its radius"
    # it rolls to and fro about the centre (no rolling friction), never below the bowl's floor
    r = np.hypot(*in_bowl.qpos[:2])
    floor = 0.5 * (1.0 - 0.5 * np.exp(-r ** 2)) + 0.05
    assert r < 0.5 and floor - 0.01 < in_bowl.qpos[2] < floor + 0.02, in_bowl.qpos[:3]
    # pickling keeps the elevations
    again = pickle.loads(pickle.dumps(bowled))
    np.testing.assert_array_equal(again.hfield_data("ground"), bowl)


@pytest.mark.parametrize("bad,says", [
    (np.zeros((20, 21)), "shape"),
    (np.full((21, 21), np.nan), "finite"),
])
def test_bad_elevations_are_value_errors(bad, says):
    with pytest.raises(ValueError, match=says):
        terrain().with_hfield_data("ground", bad)
    with pytest.raises(ValueError, match="unknown height field"):
        terrain().hfield_data("nope")


@pytest.mark.filterwarnings("ignore::sinew.ModelWarning")
def test_a_meshed_model_pickles_and_loads_from_anywhere(tmp_path, monkeypatch):
    dog = sinew.Model.from_mjcf(os.path.join(SUITE, "dog.xml"))
    monkeypatch.chdir(tmp_path)
    again = pickle.loads(pickle.dumps(dog))
    np.testing.assert_array_equal(again.body_mass, dog.body_mass)


def random_poses(mj, sim, d, seed, spread, n=1000):
    """`n` random poses of a scene of one or two free bodies at (0, 0, 1): the first moved within
    ±0.2, the second within ±`spread` of it, both turned at random; each is forwarded in MuJoCo
    (`d`) and stepped once in sinew (`sim`, at rest) before it is yielded."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        q = mj.qpos0.copy()
        q[0:3] += rng.uniform(-0.2, 0.2, 3)
        for a in range(3, mj.nq, 7):
            quat = rng.normal(size=4)
            q[a:a + 4] = quat / np.linalg.norm(quat)
        if mj.nq > 7:
            q[7:10] = q[0:3] + rng.uniform(-spread, spread, 3)
        d.qpos[:] = q
        mujoco.mj_forward(mj, d)
        sim.qpos, sim.qvel = q, np.zeros(mj.nv)
        sim.step()
        yield q


ELLIPSOID_PARTNERS = {
    "plane": 'type="plane" size="2 2 0.1"',
    "sphere": 'type="sphere" size="0.1"',
    "capsule": 'type="capsule" size="0.07 0.15"',
    "box": 'type="box" size="0.1 0.15 0.08"',
    "ellipsoid": 'type="ellipsoid" size="0.2 0.09 0.11"',
    "mesh": 'type="mesh" mesh="frustum"',
}


@pytest.mark.parametrize("other", sorted(ELLIPSOID_PARTNERS))
def test_ellipsoid_contacts_are_mujocos(other):
    # an ellipsoid against every kind of geom at random poses: the same contact (one point),
    # distance and normal as MuJoCo's, to MuJoCo's own tolerance of its convex collisions (1e-6)
    partner = f'<geom {ELLIPSOID_PARTNERS[other]} pos="0 0 1"/>'
    if other != "plane":
        partner = f'<body pos="0 0 1"><freejoint/><geom {ELLIPSOID_PARTNERS[other]}/></body>'
    xml = f"""<mujoco><option gravity="0 0 0" timestep="1e-9"/><asset><mesh name="frustum" vertex="{FRUSTUM}" scale="2 2 2"/></asset>
    <worldbody><body pos="0 0 1"><freejoint/><geom type="ellipsoid" size="0.16 0.1 0.07"/></body>{partner}</worldbody></mujoco>"""
    m, mj = sinew.Model.from_mjcf_string(xml), mujoco.MjModel.from_xml_string(xml)
    sim, d = sinew.Sim(m), mujoco.MjData(mj)
    compared = 0
    for q in random_poses(mj, sim, d, seed=3, spread=0.25):
        ours = [c for c in sim.contacts if c["dist"] <= 0]
        if d.ncon and d.contact.dist[0] < -0.02:
            continue  # deep overlaps: MuJoCo's depth is not the least translation there
        assert len(ours) == d.ncon, (q, ours, d.contact)
        for c in ours:
            assert abs(c["dist"] - d.contact.dist[0]) < 1e-5, (q, c, d.contact.dist[0])
            assert abs(abs(np.dot(c["normal"], d.contact.frame[0][:3])) - 1) < 1e-5, (q, c, d.contact.frame[0])
            compared += 1
    assert compared > 20


CYLINDER_PARTNERS = {
    "plane": 'type="plane" size="2 2 0.1"',
    "sphere": 'type="sphere" size="0.1"',
    "capsule": 'type="capsule" size="0.07 0.15"',
    "box": 'type="box" size="0.1 0.15 0.08"',
    "cylinder": 'type="cylinder" size="0.12 0.06"',
}


def least_distance(mj, d):
    """The least distance between geoms 0 and 1 (cylinder, box, capsule), from a few starts of
    SLSQP over a point in each."""
    from scipy.optimize import minimize

    def inside(g):
        size, pos, rot = mj.geom_size[g], d.geom_xpos[g].copy(), d.geom_xmat[g].reshape(3, 3).copy()
        local = lambda x: rot.T @ (x - pos)
        if mj.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
            return [lambda x: size - np.abs(local(x))]
        if mj.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER:
            return [lambda x: size[1] - abs(local(x)[2]), lambda x: size[0] ** 2 - local(x)[:2] @ local(x)[:2]]
        # capsule: within its radius of its segment
        return [lambda x: size[0] ** 2 - np.sum((local(x) - [0, 0, np.clip(local(x)[2], -size[1], size[1])]) ** 2)]

    cons = [{"type": "ineq", "fun": lambda z, c=c: c(z[:3])} for c in inside(0)]
    cons += [{"type": "ineq", "fun": lambda z, c=c: c(z[3:])} for c in inside(1)]
    rng = np.random.default_rng(0)
    runs = [minimize(lambda z: np.sum((z[:3] - z[3:]) ** 2), np.concatenate([d.geom_xpos[0], d.geom_xpos[1]]) + rng.normal(0, 0.02, 6),
                     constraints=cons, method="SLSQP", options={"ftol": 1e-15, "maxiter": 500}) for _ in range(5)]
    return np.sqrt(min(r.fun for r in runs if r.success))


@pytest.mark.parametrize("other", sorted(CYLINDER_PARTNERS))
def test_cylinder_contacts_are_mujocos(other):
    # a cylinder (not the capsule of its size) against every primitive at random poses, every
    # geom with a 5 cm margin, where the shapes are apart or overlap by under 2 mm (deeper,
    # MuJoCo's depth of a cylinder and a box is not the least translation: a search over
    # directions finds sinew's, twice MuJoCo's): the least distance as MuJoCo's against a plane
    # and a sphere (closed forms on both sides), bracketing it against the rest
    partner = f'<geom {CYLINDER_PARTNERS[other]} pos="0 0 1"/>'
    if other != "plane":
        partner = f'<body pos="0 0 1"><freejoint/><geom {CYLINDER_PARTNERS[other]}/></body>'
    xml = f"""<mujoco><option gravity="0 0 0" timestep="1e-9"/><default><geom margin="0.05"/></default>
    <worldbody><body pos="0 0 1"><freejoint/><geom type="cylinder" size="0.1 0.15"/></body>{partner}</worldbody></mujoco>"""
    m, mj = sinew.Model.from_mjcf_string(xml), mujoco.MjModel.from_xml_string(xml)
    sim, d = sinew.Sim(m), mujoco.MjData(mj)
    compared = 0
    for q in random_poses(mj, sim, d, seed=4, spread=0.3):
        ours = min((c["dist"] for c in sim.contacts), default=None)
        theirs = d.contact.dist[:d.ncon].min() if d.ncon else None
        if theirs is None or theirs < -0.002 or theirs > 0.045:
            continue
        assert ours is not None, (q, theirs)
        if other in ("plane", "sphere"):
            assert abs(ours - theirs) < 1e-5, (q, ours, theirs)
        elif theirs - 1e-6 < ours + 1e-3 and ours < theirs + 1e-6:
            # sinew's distance is a separation along a direction, never more than the true one;
            # MuJoCo's, the distance of two points, never less: within 1 mm of each other
            pass
        else:
            # where they are not (MuJoCo 4.0.1 finds a cylinder 1.6 mm farther from a box than
            # it is), apart shapes' distance by a solver of its own
            assert ours > 0 and abs(ours - least_distance(mj, d)) < 1e-6, (q, ours, theirs)
        compared += 1
    assert compared > 50
