"""The MJCF that the robot packages of 2026 (Menagerie, Playground, mjlab, robosuite,
gymnasium-robotics, Meta-World, MyoSuite) write, read as MuJoCo reads it: servo ranges inherited
from joints, damping ratios, joint actuator-force limits, mocap bodies, `<mujocoinclude>`, bounded
masses, repeated pairs, unnamed textures, inertia groups, muscles written as `<general>`, and the
XML only MuJoCo's parser accepts. Each checked against the mujoco package where it computes it."""

import os
import warnings

import mujoco
import numpy as np
import pytest

import sinew

ARM = """
<mujoco>
  <compiler angle="radian" {compiler}/>
  <default>
    <default class="servo">
      <joint damping="0.3" armature="0.02" {joint}/>
      <position kp="50" {position}/>
    </default>
  </default>
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" class="servo" axis="0 1 0" range="-1.5 0.5"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <body name="lower" pos="0.4 0 0">
        <joint name="elbow" class="servo" axis="0 1 0" range="-2 2"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="a_shoulder" joint="shoulder" class="servo" gear="2"/>
    <position name="a_elbow" joint="elbow" class="servo"/>
  </actuator>
</mujoco>
"""


def both(xml):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        return mujoco.MjModel.from_xml_string(xml), sinew.Model.from_mjcf_string(xml)


def qacc_both(mj, sm, qpos, qvel, ctrl):
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d.qpos[:], d.qvel[:], d.ctrl[:] = qpos, qvel, ctrl
    sim.qpos[:], sim.qvel[:], sim.ctrl[:] = qpos, qvel, ctrl
    mujoco.mj_forward(mj, d)
    sim.forward()
    return d, sim


def test_inheritrange_gives_the_joints_range_scaled_about_its_middle():
    mj, sm = both(ARM.format(compiler="", joint="", position='inheritrange="0.8"'))
    np.testing.assert_allclose(sm.actuator_ctrlrange, mj.actuator_ctrlrange, rtol=0, atol=1e-15)
    np.testing.assert_allclose(sm.actuator_ctrlrange[0], [-0.5 - 0.8, -0.5 + 0.8])
    assert list(sm.actuator_ctrllimited) == [True, True]
    with pytest.raises(sinew.ModelError, match="cannot both be given"):
        sinew.Model.from_mjcf_string(ARM.format(compiler="", joint="", position='inheritrange="1" ctrlrange="-1 1"'))


def test_dampratio_gives_mujocos_damping_from_the_reflected_inertia():
    mj, sm = both(ARM.format(compiler="", joint="", position='dampratio="1.5"'))
    np.testing.assert_allclose(sm.param("actuator_bias"), mj.actuator_biasprm[:, :3], rtol=1e-12)
    assert (mj.actuator_biasprm[:, 2] < 0).all()
    rng = np.random.default_rng(0)
    for _ in range(5):
        d, sim = qacc_both(mj, sm, rng.normal(size=2) * 0.5, rng.normal(size=2), rng.uniform(-1, 1, 2))
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-9, atol=1e-9)
    with pytest.raises(sinew.ModelError, match="kv and dampratio"):
        sinew.Model.from_mjcf_string(ARM.format(compiler="", joint="", position='kv="1" dampratio="1"'))


def test_a_joints_actuatorfrcrange_clamps_its_actuators_total():
    mj, sm = both(ARM.format(compiler="", joint='actuatorfrcrange="-3 4"', position=""))
    rng = np.random.default_rng(1)
    clamped = 0
    for _ in range(10):
        d, sim = qacc_both(mj, sm, rng.normal(size=2), rng.normal(size=2), rng.uniform(-2, 2, 2))
        clamped += int((np.abs(d.qfrc_actuator) >= 3 - 1e-12).any())
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-9, atol=1e-9)
    assert clamped >= 5
    # without it the same controls accelerate differently
    mj2, sm2 = both(ARM.format(compiler="", joint="", position=""))
    d2, sim2 = qacc_both(mj2, sm2, [0.3, 0.2], [0, 0], [2, -2])
    d1, sim1 = qacc_both(mj, sm, [0.3, 0.2], [0, 0], [2, -2])
    assert np.abs(sim1.qacc - sim2.qacc).max() > 1


def test_boundmass_and_boundinertia_raise_light_bodies_as_mujoco_does():
    xml = ARM.format(compiler='boundmass="3" boundinertia="0.5"', joint="", position="")
    mj, sm = both(xml)
    np.testing.assert_allclose(sm.body_mass, mj.body_mass, rtol=1e-12)
    assert list(sm.body_mass) == [0, 3, 3]
    d, sim = qacc_both(mj, sm, [0.3, -0.4], [1, -1], [0.2, 0.1])
    np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("shape, size", [("sphere", ".02"), ("box", ".1 .2 .3"), ("capsule", ".05 .2"), ("cylinder", ".05 .2")])
@pytest.mark.parametrize("extra", ["", 'mass="2"', 'density="300"'])
def test_shellinertia_puts_a_primitives_mass_on_its_surface_as_mujoco_does(shape, size, extra):
    xml = f"""<mujoco><worldbody><body><freejoint/><geom type="{shape}" size="{size}" pos=".1 0 0" euler="10 20 30"
        shellinertia="true" {extra}/></body></worldbody></mujoco>"""
    mj, sm = both(xml)
    np.testing.assert_allclose(sm.body_mass, mj.body_mass, rtol=1e-12)
    moments = np.sort(np.linalg.eigvalsh(np.asarray(sm.body_inertia_tensor)[1]))
    np.testing.assert_allclose(moments, np.sort(mj.body_inertia[1]), rtol=1e-9)


def test_shellinertia_on_an_ellipsoid_is_warned_and_solid():
    with pytest.warns(sinew.ModelWarning, match="shellinertia"):
        sm = sinew.Model.from_mjcf_string('<mujoco><worldbody><body><freejoint/><geom type="ellipsoid" size=".1 .2 .3" shellinertia="true"/></body></worldbody></mujoco>')
    assert sm.body_mass[1] == pytest.approx(1000 * 4 / 3 * np.pi * 0.006)


MOCAP = """
<mujoco>
  <worldbody>
    <geom type="plane" size="2 2 .1"/>
    <body name="target" mocap="true" pos="0.2 0 0.5"><geom type="sphere" size="0.03" contype="0" conaffinity="0"/></body>
    <body name="box" pos="0 0 0.5"><freejoint/><geom type="box" size="0.05 0.05 0.05"/></body>
  </worldbody>
  <equality><weld body1="box" body2="target"/></equality>
  <keyframe><key name="k" qpos="0 0 0.5 1 0 0 0" mpos="0.1 0.2 0.3" mquat="0 1 0 0"/></keyframe>
</mujoco>
"""


def test_a_mocap_body_is_placed_per_world_and_what_is_welded_to_it_follows():
    sm = sinew.Model.from_mjcf_string(MOCAP)
    assert sm.mocap_bodies == [sm.body_names.index("target")]
    key = sm.keyframe("k")
    np.testing.assert_array_equal(key["mpos"], [[0.1, 0.2, 0.3]])
    np.testing.assert_array_equal(key["mquat"], [[0, 1, 0, 0]])
    b = sinew.Batch(sm, 2)
    t = sm.mocap_bodies[0]
    pos = b.params("body_pos")
    pos[1, t] = [0.5, 0.5, 0.8]
    b.set_params("body_pos", pos)
    b.step(500)
    box = sm.body_names.index("box")
    # each box held where its world's target went (the weld keeps their offset at qpos0)
    np.testing.assert_allclose(b.xpos[0, box], [0.0, 0.0, 0.5], atol=2e-3)
    np.testing.assert_allclose(b.xpos[1, box], [0.3, 0.5, 0.8], atol=2e-3)
    for bad in ('<body mocap="true"><joint/><geom size="1"/></body>', '<body><body mocap="true"><geom size="1"/></body></body>'):
        with pytest.raises(sinew.ModelError, match="mocap"):
            sinew.Model.from_mjcf_string(f"<mujoco><worldbody>{bad}</worldbody></mujoco>")


def test_included_files_may_be_mujocoinclude_and_keep_their_own_mesh_paths(tmp_path):
    (tmp_path / "robot" / "assets").mkdir(parents=True)
    (tmp_path / "robot" / "assets" / "cube.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    # Menagerie's mjx_panda.xml names its meshes with their directory under meshdir="assets"
    (tmp_path / "robot" / "robot.xml").write_text(
        '<mujocoinclude><compiler meshdir="assets"/><asset><mesh name="m" file="assets/cube.obj"/></asset>'
        '<worldbody><body><freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujocoinclude>')
    (tmp_path / "scene.xml").write_text('<mujoco><include file="robot/robot.xml"/></mujoco>')
    sm = sinew.Model.from_mjcf(str(tmp_path / "scene.xml"))
    mj = mujoco.MjModel.from_xml_path(str(tmp_path / "scene.xml"))
    np.testing.assert_allclose(sm.body_mass, mj.body_mass, rtol=1e-9)


def test_a_repeated_pair_replaces_the_earlier_one_with_a_warning():
    xml = """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 .1"/>
      <body><freejoint/><geom name="ball" size="0.1"/></body></worldbody>
      <contact><pair geom1="ball" geom2="floor" friction="0.5"/><pair geom1="ball" geom2="floor" friction="0.7"/></contact></mujoco>"""
    with pytest.warns(sinew.ModelWarning, match="paired again"):
        sm = sinew.Model.from_mjcf_string(xml)
    assert any("replaces the earlier one" in w for w in sm.warnings)


def test_xml_only_mujocos_parser_accepts_loads(tmp_path):
    path = tmp_path / "loose.xml"
    path.write_text('<mujoco>\n<!-- an old -- comment -->\n<worldbody>\n<body><freejoint/>'
                    '<geom name="g"type="box" size="0.1 0.1 0.1"/></body></worldbody></mujoco>')
    mj = mujoco.MjModel.from_xml_path(str(path))
    sm = sinew.Model.from_mjcf(str(path))
    assert sm.ngeom == mj.ngeom == 1 and sm.nq == 7


def test_actuator_ranges_in_a_class_are_shared_by_every_actuator_kind():
    # MuJoCo's class holds one actuator default: <motor ctrlrange> reaches a <position>
    xml = """<mujoco><default><default class="hand"><motor ctrlrange="-0.7 0.7"/><position ctrllimited="true" kp="10"/></default></default>
      <worldbody><body><joint name="j" range="-1 1"/><geom size="0.1"/></body></worldbody>
      <actuator><position class="hand" joint="j"/></actuator></mujoco>"""
    mj, sm = both(xml)
    np.testing.assert_array_equal(sm.actuator_ctrlrange, mj.actuator_ctrlrange)
    np.testing.assert_array_equal(sm.actuator_ctrlrange, [[-0.7, 0.7]])


def test_unnamed_textures_inertia_groups_and_bright_colours_load_as_in_mujoco(tmp_path):
    xml = """<mujoco><compiler inertiagrouprange="0 2"/>
      <asset><texture type="2d" builtin="checker" file="wood.png" width="8" height="8"/><material name="m" texture="wood"/></asset>
      <worldbody><light diffuse="1.5 1.5 1.5"/>
        <body><freejoint/><geom size="0.1" material="m"/><geom size="0.3" group="3" rgba="0.2 1.7 0.2 1"/></body></worldbody></mujoco>"""
    sm = sinew.Model.from_mjcf_string(xml)
    # the group-3 geom adds no mass: a 0.1 m sphere's 4.19 kg
    np.testing.assert_allclose(sm.body_mass[1], 1000 * 4 / 3 * np.pi * 0.1**3, rtol=1e-12)


def test_a_muscle_written_as_general_is_the_muscle():
    body = """<worldbody><body><joint name="j" range="-60 60" limited="true"/><geom size="0.1" pos="0.3 0 0"/></body></worldbody>
      <tendon><fixed name="t"><joint joint="j" coef="0.1"/></fixed></tendon>"""
    short = f"<mujoco>{body}<actuator><muscle tendon=\"t\" lengthrange=\"-0.1 0.1\" force=\"5\"/></actuator></mujoco>"
    prm = "0.75 1.05 5 200 0.5 1.6 1.5 1.3 1.2"
    general = (f"<mujoco>{body}<actuator><general tendon=\"t\" lengthrange=\"-0.1 0.1\" gaintype=\"muscle\" biastype=\"muscle\" "
               f"dyntype=\"muscle\" gainprm=\"{prm}\" biasprm=\"{prm}\" dynprm=\"0.01 0.04 0\" ctrllimited=\"true\" ctrlrange=\"0 1\"/></actuator></mujoco>")
    mj, sm = both(general)
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    ref = sinew.Sim(sinew.Model.from_mjcf_string(short))
    for s in (sim, ref):
        s.ctrl[:] = 0.7
        s.step(200)
    d.ctrl[:] = 0.7
    for _ in range(200):
        mujoco.mj_step(mj, d)
    np.testing.assert_array_equal(sim.get_state(), ref.get_state())
    assert 0.01 < abs(sim.qpos[0]) < 1.0  # moved, within its range
    np.testing.assert_allclose(sim.qpos, d.qpos, atol=1e-9)


def test_a_contact_sensors_force_data_is_left_out_with_a_warning():
    xml = """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 .1"/><body><freejoint/><geom name="foot" size="0.1"/></body></worldbody>
      <sensor><contact name="c" geom1="foot" geom2="floor" reduce="mindist" num="1" data="found"/>
      <contact name="f" geom1="foot" geom2="floor" data="found force"/><framepos objtype="body" objname="world"/></sensor></mujoco>"""
    sm = sinew.Model.from_mjcf_string(xml)
    assert any("<contact> sensor 'f'" in w and "data 'force' is not computed" in w for w in sm.warnings)
    assert sm.sensor_names[0] == "c" and "f" not in sm.sensor_names


def test_a_plane_on_a_body_fixed_to_the_world_stays_a_plane_and_on_a_moving_body_becomes_a_slab():
    fixed = """<mujoco><worldbody><body name="wall" pos="0.5 0 0"><geom name="w" type="plane" size="0 0 .01" zaxis="-1 0 0"/></body>
      <body pos="0.3 0 0.5"><freejoint/><geom size="0.1"/></body></worldbody><option gravity="9.81 0 0"/></mujoco>"""
    mj, sm = both(fixed)
    assert not sm.warnings
    sim = sinew.Sim(sm)
    sim.step(1000)
    # the ball falls sideways onto the wall and rests against it: its centre 0.1 before x = 0.5
    assert abs(sim.qpos[0] - 0.4) < 1e-3
    moving = fixed.replace('<body name="wall" pos="0.5 0 0">', '<body name="wall" pos="0.5 0 0"><joint type="slide" axis="0 0 1"/><geom size="0.01"/>')
    sm2 = sinew.Model.from_mjcf_string(moving.replace('size="0 0 .01"', 'size="0.5 0.5 .01"'))
    assert any("slab" in w for w in sm2.warnings)


def test_implicitfast_treats_a_servos_damping_implicitly_as_mujoco_does():
    """A stiff, heavily damped servo at a coarse step: explicit damping diverges, MuJoCo's
    implicitfast (the servo's kv with the joint's damping inside the step's inverse) does not, and
    sinew steps as MuJoCo does."""
    xml = """<mujoco><option timestep="0.01" integrator="{}" gravity="0 0 -9.81"/>
      <worldbody><body><joint name="j" axis="0 1 0" damping="0.1"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.2"/></body></worldbody>
      <actuator><position joint="j" kp="400" kv="30"/></actuator></mujoco>"""
    mj, sm = both(xml.format("implicitfast"))
    assert sm.integrator == "implicitfast"
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    d.ctrl[:] = sim.ctrl[:] = 0.5
    for _ in range(200):
        mujoco.mj_step(mj, d)
    sim.step(200)
    np.testing.assert_allclose(sim.qpos, d.qpos, atol=1e-9)
    np.testing.assert_allclose(sim.qpos, [0.5], atol=1e-3)
    explicit = sinew.Sim(sinew.Model.from_mjcf_string(xml.format("Euler")))
    explicit.ctrl[:] = 0.5
    with pytest.raises(sinew.SimulationError):
        explicit.step(200)


def test_a_joint_damped_past_the_state_bound_is_held_still_as_in_mujoco():
    """gymnasium-robotics' Fetch pins its base's slides with damping 1e11, beyond the 1e10 bound on
    other numbers: implicit in the Euler step, it loads, holds its slide still under gravity and
    lets the arm swing as MuJoCo's step does; the per-world damping takes the value back, and
    one beyond 1e15 is refused by name."""
    xml = """<mujoco><option timestep="0.002"/><worldbody><body pos="0 0 1">
      <joint name="base" type="slide" axis="0 0 1" damping="{}"/><geom type="box" size=".2 .2 .1" mass="50"/>
      <body pos="0 0 .2"><joint name="arm" axis="0 1 0" damping="1"/>
        <geom type="capsule" fromto="0 0 0 .5 0 0" size=".03" mass="2"/></body></body></worldbody></mujoco>"""
    mj, sm = both(xml.format("1e+11"))
    d, sim = mujoco.MjData(mj), sinew.Sim(sm)
    for _ in range(500):
        mujoco.mj_step(mj, d)
    sim.step(500)
    np.testing.assert_allclose(sim.qpos, d.qpos, atol=1e-12)
    assert abs(sim.qpos[0]) < 1e-8 and abs(sim.qpos[1]) > 1.0, "the base held, the arm swung"
    b = sinew.Batch(sm, 2)
    b.set_params("dof_damping", b.params("dof_damping"))
    with pytest.raises(sinew.ModelError, match="damping"):
        sinew.Model.from_mjcf_string(xml.format("1e16"))


def prism(r, h, n=12):
    """An n-sided prism's vertices (radius r, height h) as an inline mesh's `vertex`."""
    pts = [(r * np.cos(a), r * np.sin(a), z) for a in 2 * np.pi * np.arange(n) / n for z in (0.0, h)]
    return " ".join(f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in pts)


def test_a_link_meshed_into_its_base_around_its_hinge_is_left_unpushed():
    """As robosuite's ARX5: a link's mesh overlaps its base's along the link's hinge axis at rest
    (0.8 mm here; the ARX5's 2 mm leaves collision at load, beyond 1 mm). Those contacts' normals
    are rows the joints cannot move (K at round-off, not zero), so the projection's push 1/K
    would be unbounded; they are left out, and the arm hangs from its limits."""
    xml = f"""<mujoco><compiler angle="radian"/>
      <asset><mesh name="base" vertex="{prism(0.1, 0.05)}"/><mesh name="link" vertex="{prism(0.05, 0.08)}"/></asset>
      <worldbody><body name="base" euler="0.3 0.2 0.1"><geom type="mesh" mesh="base"/>
        <body name="link" pos="0 0 0.0492"><joint axis="0 0 1" range="0 3" frictionloss="0.001" damping="0.1"/><geom type="mesh" mesh="link" pos="0.01 0 0"/>
          <body pos="0.05 0 0.08"><joint axis="0 1 0" range="0 3"/><geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02"/></body></body></body>
      </worldbody></mujoco>"""
    model = sinew.Model.from_mjcf_string(xml)
    assert not any("overlap at qpos0" in w for w in model.warnings)
    sim = sinew.Sim(model)
    sim.step(300)
    assert any(c["geom1"] == 0 and c["geom2"] == 1 for c in sim.contacts) and np.abs(sim.qvel).max() < 1e-3
    assert np.all(sim.qpos >= -1e-4) and np.all(sim.qpos <= 3)


def test_a_general_actuator_reads_only_the_parameters_its_types_use():
    """MyoSuite's simple arms: a `<general>` of fixed gain and no bias whose class shares a muscle's
    ten `gainprm` and `biasprm`; MuJoCo reads gainprm[0] only (affine reads three), and so does
    sinew."""
    xml = """<mujoco><worldbody><body><joint name="j" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
      <body pos="0.3 0 0"><joint name="k" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></body></worldbody>
      <actuator><general joint="j" gainprm="2 0 2 2 0 0 0 0 0 0" biasprm="0 0 2 2 0 0 0 0 0 0"/>
        <general joint="k" gaintype="affine" biastype="affine" gainprm="3 0.5 -0.1 7 7" biasprm="0.2 -1 -0.3 9 9"/></actuator></mujoco>"""
    mj, sm = both(xml)
    d, sim = qacc_both(mj, sm, [0.3, -0.4], [0.5, -1.0], [0.7, -0.6])
    np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-10, atol=1e-10)
    assert abs(d.actuator_force[0] - 2 * 0.7) < 1e-12


def test_actuator_force_ranges_are_mujocos():
    xml = ARM.format(compiler="", joint="", position='forcerange="-3 4"').replace(
        '<position name="a_elbow" joint="elbow" class="servo"/>', '<position name="a_elbow" joint="elbow" forcelimited="false"/>')
    mj, sm = both(xml)
    np.testing.assert_array_equal(sm.actuator_forcerange[0], mj.actuator_forcerange[0])
    assert not mj.actuator_forcelimited[1] and (sm.actuator_forcerange[1] == [-np.inf, np.inf]).all()
