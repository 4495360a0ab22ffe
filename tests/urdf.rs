//! URDF as MuJoCo reads it: a fixed root and fixed children fused into their parents (masses
//! and inertias combined by the parallel-axis theorem), joint kinds, limits, damping and friction,
//! `<mimic>` as a joint equality that holds in motion, a floating base, `package://` meshes found
//! through the caller's directories, optional motors and visual geometry, and clear errors.

use sinew::model::{GeomType, JointType};
use sinew::urdf::{to_mjcf, UrdfOptions};
use sinew::{Model, State};

const ROBOT: &str = r#"<robot name="t">
  <material name="red"><color rgba="1 0 0 1"/></material>
  <link name="base"><inertial><origin xyz="0 0 0.1"/><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="plate"/><origin xyz="0.1 0 0" rpy="0 0 0.5"/></joint>
  <link name="plate"><collision><origin xyz="0 0 0.05"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="plate"/><child link="arm"/><origin xyz="0 0 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/><dynamics damping="0.5" friction="0.1"/></joint>
  <link name="arm"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.001"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.03" length="0.4"/></geometry></collision>
    <visual><geometry><sphere radius="0.1"/></geometry><material name="red"/></visual></link>
  <joint name="weld" type="fixed"><parent link="arm"/><child link="weight"/><origin xyz="0.1 0 0.4"/></joint>
  <link name="weight"><inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="j2" type="continuous"><parent link="arm"/><child link="tip"/><origin xyz="0 0 0.4"/></joint>
  <link name="tip"><inertial><mass value="0.5"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.003"/></inertial></link>
  <joint name="j3" type="prismatic"><parent link="tip"/><child link="slider"/><axis xyz="1 0 0"/><limit lower="-0.5" upper="0.5" effort="5"/><mimic joint="j2" multiplier="0.2" offset="0.1"/></joint>
  <link name="slider"><inertial><mass value="0.2"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
</robot>"#;

fn load(text: &str, opts: &UrdfOptions) -> Model {
    Model::from_mjcf(&to_mjcf(text, None, opts).unwrap()).unwrap()
}

#[test]
fn fixed_links_fuse_into_their_parents() {
    let m = load(ROBOT, &UrdfOptions::default());
    // base and plate are fixed to the world: their geoms are the world's, their mass gone
    assert_eq!(m.body_name, ["world", "arm", "tip", "slider"]);
    assert_eq!(m.geom_type.iter().filter(|&&t| t != GeomType::Cylinder).count(), 2);
    assert_eq!(m.geom_body[..2], [0, 0]);
    // the weight (0.5 kg at (0.1, 0, 0.4)) fused into the arm (1 kg at (0, 0, 0.2))
    assert!((m.body_mass[1] - 1.5).abs() < 1e-12);
    let com = (glam::DVec3::new(0.0, 0.0, 0.2) * 1.0 + glam::DVec3::new(0.1, 0.0, 0.4) * 0.5) / 1.5;
    assert!((m.body_ipos[1] - com).length() < 1e-12, "{}", m.body_ipos[1]);
    // about the common centre: I_yy = 0.02 + 0.001 + Σ m (dx² + dz²)
    let d1 = glam::DVec3::new(0.0, 0.0, 0.2) - com;
    let d2 = glam::DVec3::new(0.1, 0.0, 0.4) - com;
    let iyy = 0.021 + 1.0 * (d1.x * d1.x + d1.z * d1.z) + 0.5 * (d2.x * d2.x + d2.z * d2.z);
    assert!((m.body_inertia[1].y_axis.y - iyy).abs() < 1e-12, "{} vs {iyy}", m.body_inertia[1].y_axis.y);
}

#[test]
fn joints_keep_their_kinds_limits_damping_and_friction() {
    let m = load(ROBOT, &UrdfOptions::default());
    assert_eq!(m.jnt_type, [JointType::Hinge, JointType::Hinge, JointType::Slide]);
    assert_eq!((m.jnt_limited.clone(), m.jnt_range[0], m.jnt_range[2]), (vec![true, false, true], [-1.0, 1.0], [-0.5, 0.5]));
    assert_eq!((m.dof_damping[0], m.dof_frictionloss[0]), (0.5, 0.1));
    // the revolute joint's axis (0 1 0) in the arm's frame, which the origin's rpy turned
    assert!((m.jnt_axis[0] - glam::DVec3::Y).length() < 1e-12);
    assert_eq!(m.nu, 0);
}

#[test]
fn a_mimic_joint_follows_its_leader_in_motion() {
    let m = load(ROBOT, &UrdfOptions::default());
    assert_eq!(m.eq_polycoef.len(), 1);
    let mut s = State::new(&m);
    s.qvel[1] = 3.0;
    let mut worst = 0.0f64;
    for _ in 0..500 {
        s.step(&m);
        worst = worst.max((s.qpos[2] - (0.1 + 0.2 * s.qpos[1])).abs());
    }
    assert!(worst < 1e-6, "the mimic joint strays {worst} from its leader");
}

#[test]
fn options_float_the_base_add_motors_and_keep_visuals() {
    let m = load(ROBOT, &UrdfOptions { floating_base: true, motors: true, visual: true, ..Default::default() });
    // the root (with its fused plate) is a free body
    assert_eq!(m.body_name[1], "base");
    assert_eq!(m.jnt_type[0], JointType::Free);
    assert!((m.body_mass[1] - 2.0).abs() < 1e-12);
    // motors on the joints with an effort limit, the mimic joint left to its equality
    assert_eq!(m.nu, 1);
    assert_eq!(m.actuator_ctrlrange[0], [-10.0, 10.0]);
    // the visual sphere is drawn, massless and without contacts
    let v = (0..m.ngeom).find(|&g| m.geom_type[g] == GeomType::Sphere && m.geom_size[g][0] == 0.1).expect("visual geom");
    assert_eq!((m.geom_contype[v], m.geom_conaffinity[v]), (0, 0));
    assert_eq!(m.vis.geom_rgba[v], [1.0, 0.0, 0.0, 1.0]);
    assert!((m.body_mass[2] - 1.5).abs() < 1e-12);
}

#[test]
fn package_meshes_are_found_through_the_callers_directories() {
    let dir = std::env::temp_dir().join(format!("sinew-urdf-{}", std::process::id()));
    let pkg = dir.join("pkgs/my_robot/meshes");
    std::fs::create_dir_all(&pkg).unwrap();
    let obj = "v -0.1 -0.1 -0.1\nv 0.1 -0.1 -0.1\nv 0 0.1 -0.1\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    std::fs::write(pkg.join("tet.obj"), obj).unwrap();
    let urdf = r#"<robot name="m"><link name="a"/><joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>
        <link name="b"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
        <collision><geometry><mesh filename="package://my_robot/meshes/tet.obj" scale="2 2 2"/></geometry></collision></link></robot>"#;
    std::fs::write(dir.join("robot.urdf"), urdf).unwrap();
    let path = dir.join("robot.urdf");
    for packages in [vec![dir.join("pkgs")], vec![dir.join("pkgs/my_robot")]] {
        let m = Model::from_urdf_file(&path, &UrdfOptions { package_dirs: packages, ..Default::default() }).unwrap();
        assert_eq!(m.meshes.len(), 1);
        assert!((m.geom_rbound[0] - 2.0 * m.meshes[0].vert.iter().map(|v| v.length() / 2.0).fold(0.0, f64::max)).abs() < 1e-9);
    }
    // without the directory: an error naming the URI
    let e = Model::from_urdf_file(&path, &UrdfOptions::default()).unwrap_err().to_string();
    assert!(e.contains("package://my_robot/meshes/tet.obj") && e.contains("not found"), "{e}");
    // a URDF file given where MJCF is expected is read as URDF
    let e = Model::from_mjcf_file(&path).unwrap_err().to_string();
    assert!(e.contains("package://my_robot"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_urdf_is_a_clear_error() {
    let cases = [
        ("<mujoco/>", "<robot>"),
        (r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#, "exactly one root"),
        (r#"<robot name="r"><link name="a"/><joint name="j" type="revolute"><parent link="a"/><child link="zz"/></joint></robot>"#, "unknown link 'zz'"),
        (r#"<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="planar"><parent link="a"/><child link="b"/></joint></robot>"#, "planar"),
        (r#"<robot name="r"><link name="a"><collision><geometry><box size="1 0 1"/></geometry></collision></link></robot>"#, "positive"),
        (r#"<robot name="r"><link name="a"><inertial><mass value="-1"/></inertial></link></robot>"#, "negative mass"),
        (r#"<robot name="r"><link name="a"/><link name="a"/></robot>"#, "duplicate link"),
        (
            r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
            <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
            <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#,
            "loop",
        ),
    ];
    for (text, says) in cases {
        let e = to_mjcf(text, None, &UrdfOptions::default()).map(|x| Model::from_mjcf(&x).map(|_| ())).and_then(|r| r).unwrap_err().to_string();
        assert!(e.contains(says), "{text}: {e}");
    }
}
