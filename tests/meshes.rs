//! Meshes: mass properties as MuJoCo computes them (a box written as a mesh weighs and turns as
//! the primitive box), hulls as collision shapes (a mesh box rests, slides and tips exactly as the
//! primitive box; a convex mesh holds on a slope below its friction angle; ten meshes dropped into
//! a bin settle without fallback or penetration), and contacts of hulls against every primitive.

#![allow(clippy::needless_range_loop)] // tests/common follows the math's index notation
mod common;

use sinew::model::GeomType;
use sinew::{Model, State};

/// A box of half-sides 0.25 × 0.125 × 0.0625 (exact in single precision) as mesh vertices.
const BOX_VERTS: &str = "-.25 -.125 -.0625  .25 -.125 -.0625  -.25 .125 -.0625  .25 .125 -.0625  \
                         -.25 -.125 .0625  .25 -.125 .0625  -.25 .125 .0625  .25 .125 .0625";

/// A free body over a plane whose one geom is `geom`, with the `<asset>` given.
fn free_body(asset: &str, geom: &str, pos: &str, quat: &str) -> String {
    format!(
        r#"<mujoco><option timestep="0.002"/><asset>{asset}</asset><worldbody>
        <geom type="plane" size="5 5 0.1" friction="0.6"/>
        <body pos="{pos}" quat="{quat}"><freejoint/>{geom}</body></worldbody></mujoco>"#
    )
}

/// The same scene with the box as a primitive and as a mesh.
fn box_pair(pos: &str, quat: &str) -> (Model, Model) {
    let primitive = free_body("", r#"<geom type="box" size=".25 .125 .0625"/>"#, pos, quat);
    let mesh = free_body(&format!(r#"<mesh name="b" vertex="{BOX_VERTS}"/>"#), r#"<geom type="mesh" mesh="b"/>"#, pos, quat);
    (Model::from_mjcf(&primitive).unwrap(), Model::from_mjcf(&mesh).unwrap())
}

#[test]
fn a_box_mesh_weighs_and_turns_as_the_primitive() {
    let (p, m) = box_pair("0 0 1", "1 0 0 0");
    assert_eq!(m.geom_type[1], GeomType::Mesh);
    assert!((p.body_mass[1] - m.body_mass[1]).abs() <= 1e-12 * p.body_mass[1], "{} vs {}", p.body_mass[1], m.body_mass[1]);
    let (ip, im) = (p.body_inertia[1], m.body_inertia[1]);
    let scale = ip.x_axis.x.abs().max(ip.y_axis.y.abs()).max(ip.z_axis.z.abs());
    for c in 0..3 {
        assert!((ip.col(c) - im.col(c)).abs().max_element() <= 1e-12 * scale, "inertia {ip} vs {im}");
    }
    assert!(m.body_ipos[1].length() < 1e-15);
}

/// Steps both models from the same state; the largest difference of qpos over the run, and the
/// final state of the mesh model.
fn run_pair(p: &Model, m: &Model, qvel: [f64; 6], steps: usize) -> (f64, State) {
    let (mut sp, mut sm) = (State::new(p), State::new(m));
    sp.qvel.copy_from_slice(&qvel);
    sm.qvel.copy_from_slice(&qvel);
    let mut worst = 0.0f64;
    for _ in 0..steps {
        sp.step(p);
        sm.step(m);
        worst = worst.max(common::rel_err(&sp.qpos, &sm.qpos));
    }
    (worst, sm)
}

#[test]
fn a_box_mesh_rests_slides_and_tips_as_the_primitive_box() {
    // resting (dropped flat), sliding (thrown along the floor) and tipping (dropped on an edge)
    let cases = [
        ("0 0 0.1", "1 0 0 0", [0.0; 6], "rests"),
        ("0 0 0.0625", "1 0 0 0", [2.0, 0.5, 0.0, 0.0, 0.0, 0.0], "slides"),
        ("0 0 0.3", "0.9659258 0.2588190 0 0", [0.0, 0.0, 0.0, 0.0, 0.0, 1.0], "tips"),
    ];
    for (pos, quat, qvel, what) in cases {
        let (p, m) = box_pair(pos, quat);
        let (worst, s) = run_pair(&p, &m, qvel, 1000);
        assert!(worst < 1e-9, "{what}: the mesh box's qpos differs from the primitive's by {worst:e}");
        let stats = s.data.constraints.stats;
        assert_eq!(stats.fallback_pgs + stats.fallback_zero, 0, "{what}: fallback solves");
        assert!(s.qvel.iter().all(|v| v.abs() < 1e-6), "{what}: not at rest after 2 s: {:?}", s.qvel);
    }
}

/// A convex mesh that is not a box: a hexagonal frustum, its base (radius 0.1) at z = −0.04 and its
/// top (radius 0.06) at z = 0.04 in the file's frame.
const GEM: &str = r#"<mesh name="gem" vertex="0.1 0 -0.04  0.05 0.08660254 -0.04  -0.05 0.08660254 -0.04  -0.1 0 -0.04  -0.05 -0.08660254 -0.04  0.05 -0.08660254 -0.04
    0.06 0 0.04  0.03 0.05196152 0.04  -0.03 0.05196152 0.04  -0.06 0 0.04  -0.03 -0.05196152 0.04  0.03 -0.05196152 0.04"/>"#;

#[test]
fn a_convex_mesh_holds_on_a_slope_below_its_friction_angle_and_slides_above() {
    for (deg, holds) in [(25.0f64, true), (35.0, false)] {
        // friction 0.6: the friction angle is 31.0°
        let (s, c) = ((deg.to_radians() / 2.0).sin(), (deg.to_radians() / 2.0).cos());
        let xml = format!(
            r#"<mujoco><option timestep="0.002"/><asset>{GEM}</asset><worldbody>
            <geom type="plane" size="5 5 0.1" friction="0.6" quat="{c} 0 {s} 0"/>
            <body pos="0 0 0.045" quat="{c} 0 {s} 0"><freejoint/><geom type="mesh" mesh="gem" friction="0.6"/></body></worldbody></mujoco>"#
        );
        let m = Model::from_mjcf(&xml).unwrap();
        let mut st = State::new(&m);
        for _ in 0..100 {
            st.step(&m);
        }
        let start = [st.qpos[0], st.qpos[1], st.qpos[2]];
        for _ in 0..500 {
            st.step(&m);
        }
        let moved = ((st.qpos[0] - start[0]).powi(2) + (st.qpos[1] - start[1]).powi(2) + (st.qpos[2] - start[2]).powi(2)).sqrt();
        if holds {
            assert!(moved < 1e-6, "{deg}°: the gem slid {moved} m below the friction angle");
        } else {
            assert!(moved > 0.05, "{deg}°: the gem held ({moved} m) above the friction angle");
        }
        let stats = st.data.constraints.stats;
        assert_eq!(stats.fallback_pgs + stats.fallback_zero, 0, "{deg}°: fallback solves");
    }
}

#[test]
fn ten_convex_meshes_dropped_into_a_bin_settle_without_penetration() {
    let mut bodies = String::new();
    let mut rng = common::Rng(7);
    for k in 0..10 {
        let (x, y) = (rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15));
        let q = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
        let mesh = if k % 2 == 0 { "gem" } else { "b" };
        bodies += &format!(
            r#"<body pos="{x} {y} {}" quat="{} {} {} {}"><freejoint/><geom type="mesh" mesh="{mesh}" mass="0.5"/></body>"#,
            0.3 + 0.25 * k as f64,
            q[0], q[1], q[2], q[3]
        );
    }
    let wall = |pos: &str, size: &str| format!(r#"<geom type="box" pos="{pos}" size="{size}"/>"#);
    let xml = format!(
        r#"<mujoco><option timestep="0.002"/><asset>{GEM}<mesh name="b" vertex="{BOX_VERTS}" scale="0.4 0.4 0.4"/></asset><worldbody>
        <geom type="plane" size="5 5 0.1"/>{}{}{}{}{bodies}</worldbody></mujoco>"#,
        wall("0.4 0 0.3", "0.05 0.45 0.3"),
        wall("-0.4 0 0.3", "0.05 0.45 0.3"),
        wall("0 0.4 0.3", "0.45 0.05 0.3"),
        wall("0 -0.4 0.3", "0.45 0.05 0.3"),
    );
    let m = Model::from_mjcf(&xml).unwrap();
    let mut s = State::new(&m);
    let mut deepest = 0.0f64;
    for step in 0..3000 {
        s.step(&m);
        // once settled (the last 2 s): no contact deeper than 1e-6 m
        if step >= 2000 {
            deepest = s.data.coll.contacts.iter().fold(deepest, |d, c| d.min(c.dist));
        }
    }
    assert!(deepest > -1e-6, "settled pile penetrates {deepest:e} m");
    let speed = s.qvel.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(speed < 1e-3, "not settled after 6 s: |qvel| up to {speed}");
    for b in 1..m.nbody {
        let z = s.qpos[7 * (b - 1) + 2];
        assert!((0.0..0.6).contains(&z), "body {b} left the bin (z = {z})");
    }
    // every LCP of the pile solved exactly: Lemke (strictly copositive on its last attempt) or,
    // where the force LCP has no exact answer, the step's impulses
    let stats = s.data.constraints.stats;
    eprintln!("{stats:?}");
    assert!(stats.fallback_zero == 0 && stats.inexact == 0 && stats.fallback_pgs == 0, "fallback solves: {stats:?}");
}

#[test]
fn a_mesh_meets_every_primitive_at_its_surface() {
    // each primitive dropped on a resting mesh box comes to rest on its top face (z = 0.125)
    let shapes = [
        (r#"<geom type="sphere" size="0.05"/>"#, 0.05),
        (r#"<geom type="capsule" size="0.03 0.08" quat="0.7071068 0.7071068 0 0"/>"#, 0.03),
        (r#"<geom type="box" size="0.05 0.05 0.04"/>"#, 0.04),
        (r#"<geom type="mesh" mesh="gem"/>"#, 0.04),
    ];
    for (geom, below) in shapes {
        let xml = format!(
            r#"<mujoco><option timestep="0.002"/><asset>{GEM}<mesh name="b" vertex="{BOX_VERTS}"/></asset><worldbody>
            <geom type="plane" size="5 5 0.1"/>
            <body pos="0 0 0.0625"><geom type="mesh" mesh="b"/></body>
            <body pos="0.05 0.02 0.4"><freejoint/>{geom}</body></worldbody></mujoco>"#
        );
        let m = Model::from_mjcf(&xml).unwrap();
        let mut s = State::new(&m);
        for _ in 0..1500 {
            s.step(&m);
        }
        let z = s.qpos[2];
        assert!((z - (0.125 + below)).abs() < 1e-6, "{geom}: rests at z = {z}, expected {}", 0.125 + below);
        assert!(s.qvel.iter().all(|v| v.abs() < 1e-5), "{geom}: still moving {:?}", s.qvel);
    }
}

/// The box's corners and its twelve triangles (outward).
fn box_triangles() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = (0..8).map(|k| [if k & 1 != 0 { 0.25 } else { -0.25 }, if k & 2 != 0 { 0.125 } else { -0.125 }, if k & 4 != 0 { 0.0625 } else { -0.0625 }]).collect();
    let quads = [[1, 3, 7, 5], [0, 4, 6, 2], [2, 6, 7, 3], [0, 1, 5, 4], [4, 5, 7, 6], [0, 2, 3, 1]];
    let f = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    (v, f)
}

#[test]
fn mesh_files_of_every_format_load_as_the_inline_mesh() {
    let dir = std::env::temp_dir().join(format!("sinew-meshes-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("assets")).unwrap();
    let (v, f) = box_triangles();
    // binary STL: header, count, then per triangle a normal, three vertices and two spare bytes
    let mut stl = vec![0u8; 80];
    stl.extend((f.len() as u32).to_le_bytes());
    for t in &f {
        stl.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        for &i in t {
            stl.extend(v[i as usize].iter().flat_map(|x| x.to_le_bytes()));
        }
        stl.extend([0u8; 2]);
    }
    std::fs::write(dir.join("assets/box.stl"), stl).unwrap();
    let mut ascii = String::from("solid box\n");
    for t in &f {
        ascii += "facet normal 0 0 0\nouter loop\n";
        for &i in t {
            let p = v[i as usize];
            ascii += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        ascii += "endloop\nendfacet\n";
    }
    std::fs::write(dir.join("assets/ascii.stl"), ascii + "endsolid box\n").unwrap();
    // OBJ with quads (1-based)
    let mut obj: String = v.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).collect();
    for q in [[1, 3, 7, 5], [0, 4, 6, 2], [2, 6, 7, 3], [0, 1, 5, 4], [4, 5, 7, 6], [0, 2, 3, 1]] {
        obj += &format!("f {} {} {} {}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
    std::fs::write(dir.join("assets/box.obj"), obj).unwrap();
    // MuJoCo's .msh: counts, vertices, faces
    let mut msh: Vec<u8> = [8i32, 0, 0, f.len() as i32].iter().flat_map(|x| x.to_le_bytes()).collect();
    msh.extend(v.iter().flatten().flat_map(|x| x.to_le_bytes()));
    msh.extend(f.iter().flatten().flat_map(|&i| (i as i32).to_le_bytes()));
    std::fs::write(dir.join("assets/box.msh"), msh).unwrap();
    let inline = Model::from_mjcf(&free_body(&format!(r#"<mesh name="b" vertex="{BOX_VERTS}"/>"#), r#"<geom type="mesh" mesh="b"/>"#, "0 0 1", "1 0 0 0")).unwrap();
    for file in ["box.stl", "ascii.stl", "box.obj", "box.msh"] {
        let xml = format!(
            r#"<mujoco><compiler meshdir="assets"/><asset><mesh file="{file}"/></asset><worldbody>
            <body><freejoint/><geom type="mesh" mesh="{}"/></body></worldbody></mujoco>"#,
            file.split('.').next().unwrap()
        );
        let path = dir.join("model.xml");
        std::fs::write(&path, xml).unwrap();
        let m = Model::from_mjcf_file(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!((m.body_mass[1] - inline.body_mass[1]).abs() < 1e-12, "{file}: mass {} vs {}", m.body_mass[1], inline.body_mass[1]);
        assert_eq!(m.meshes[0].hull.faces.len(), 6, "{file}: the hull of a box has six faces");
    }
    // a missing file names the element and its line
    std::fs::write(dir.join("model.xml"), r#"<mujoco><asset><mesh file="nothing.stl"/></asset></mujoco>"#).unwrap();
    let e = Model::from_mjcf_file(&dir.join("model.xml")).unwrap_err().to_string();
    assert!(e.contains("nothing.stl") && e.contains("mesh") && e.contains("line 1"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_meshes_are_clear_errors() {
    let cases = [
        (r#"<mesh name="m" vertex="0 0 0 1 0 0 0 1 0"/>"#, "at least 4"),
        (r#"<mesh name="m" vertex="0 0 0 1 0 0 0 1 0 1 1 0"/>"#, "volume"),
        (r#"<mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1" face="0 1 9"/>"#, "face"),
        (r#"<mesh name="m" vertex="0 0 0 1 0 0 0 1"/>"#, "triples"),
    ];
    for (asset, says) in cases {
        let xml = format!(r#"<mujoco><asset>{asset}</asset><worldbody><body><freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>"#);
        let e = Model::from_mjcf(&xml).unwrap_err().to_string();
        assert!(e.contains(says), "{asset}: {e}");
    }
    let e = Model::from_mjcf(r#"<mujoco><worldbody><geom type="mesh" mesh="none"/></worldbody></mujoco>"#).unwrap_err().to_string();
    assert!(e.contains("unknown mesh 'none'"), "{e}");
}

#[test]
fn malformed_mesh_files_are_errors_not_crashes() {
    let dir = std::env::temp_dir().join(format!("sinew-badmesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut stl = vec![0u8; 80];
    stl.extend(1_000_000u32.to_le_bytes());
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("short.stl", vec![1, 2, 3]),
        ("count.stl", stl),
        ("garbage.obj", b"v 1 2\nf 1 2 3 4 5\nv nan 0 0\n".to_vec()),
        ("faces.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 9\n".to_vec()),
        ("sizes.msh", [-4i32, 0, 0, 0].iter().flat_map(|x| x.to_le_bytes()).collect()),
        ("huge.msh", [i32::MAX, 0, 0, 1].iter().flat_map(|x| x.to_le_bytes()).collect()),
        ("empty.obj", vec![]),
    ];
    for (name, bytes) in cases {
        std::fs::write(dir.join(name), bytes).unwrap();
        let xml = format!(r#"<mujoco><asset><mesh name="m" file="{name}"/></asset><worldbody><body><freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>"#);
        std::fs::write(dir.join("model.xml"), xml).unwrap();
        let e = Model::from_mjcf_file(&dir.join("model.xml")).expect_err(name).to_string();
        assert!(e.contains("mesh"), "{name}: {e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_files_normals_follow_its_mesh_into_the_mesh_frame() {
    // a box whose OBJ gives one normal per face; placed by a reference frame and mirrored, each
    // triangle's corner normals stay its outward face normal
    let dir = std::env::temp_dir().join(format!("sinew-normals-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (v, _) = box_triangles();
    let mut obj: String = v.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).collect();
    obj += "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n";
    for (k, q) in [[1, 3, 7, 5], [0, 4, 6, 2], [2, 6, 7, 3], [0, 1, 5, 4], [4, 5, 7, 6], [0, 2, 3, 1]].iter().enumerate() {
        obj += &format!("f {}//{n} {}//{n} {}//{n} {}//{n}\n", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1, n = k + 1);
    }
    std::fs::write(dir.join("box.obj"), obj).unwrap();
    let xml = r#"<mujoco><asset><mesh file="box.obj" refquat="0.9 0.1 0.3 0.2" scale="-1 2 1"/></asset><worldbody>
        <body><freejoint/><geom type="mesh" mesh="box"/></body></worldbody></mujoco>"#;
    std::fs::write(dir.join("model.xml"), xml).unwrap();
    let m = Model::from_mjcf_file(&dir.join("model.xml")).unwrap();
    let mesh = &m.meshes[0];
    assert_eq!(mesh.corner_normal.len(), mesh.face.len());
    for (f, corners) in mesh.face.iter().zip(&mesh.corner_normal) {
        let [a, b, c] = f.map(|i| mesh.vert[i as usize]);
        let outward = (b - a).cross(c - a).normalize();
        for n in corners {
            assert!(n.dot(outward) > 1.0 - 1e-6, "corner normal {n} against face normal {outward}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// An n-sided prism of radius r and half-height h about (x0, 0, 0) as mesh vertices.
fn prism_verts(n: usize, r: f64, h: f64, x0: f64) -> String {
    (0..2 * n).map(|k| {
        let a = std::f64::consts::TAU * (k % n) as f64 / n as f64;
        format!("{} {} {} ", x0 + r * a.cos(), r * a.sin(), if k < n { -h } else { h })
    }).collect()
}

#[test]
fn a_hulls_box_follows_it_into_the_mesh_frame() {
    // the hull moves from the file's frame into the mass frame (here 0.5 m away and turned, the
    // prism's axis becoming a principal one): its box (the oriented-box midphase's) must bound
    // its vertices there. Left in the file's frame, it declared overlapping meshes apart
    let verts = prism_verts(40, 0.1, 0.3, 0.5);
    let xml = format!(r#"<mujoco><asset><mesh name="p" vertex="{verts}"/></asset><worldbody>
        <body><freejoint/><geom type="mesh" mesh="p"/></body></worldbody></mujoco>"#);
    let m = Model::from_mjcf(&xml).unwrap();
    let hull = &m.meshes[0].hull;
    let lo = hull.vert.iter().fold(glam::DVec3::INFINITY, |a, &v| a.min(v));
    let hi = hull.vert.iter().fold(glam::DVec3::NEG_INFINITY, |a, &v| a.max(v));
    assert!(m.meshes[0].frame.pos.length() > 0.4, "the mass frame is moved from the file's");
    assert!((hull.bounds.0 - (lo + hi) * 0.5).length() < 1e-12 && (hull.bounds.1 - (hi - lo) * 0.5).length() < 1e-12,
        "box {:?} for vertices within {lo} .. {hi}", hull.bounds);
}

#[test]
fn a_detailed_mesh_whose_file_origin_lies_off_it_rests_on_another() {
    // two 40-sided prisms (120 edges each: a pair tested by GJK after the oriented boxes), the
    // upper one's vertices 0.5 m from its file's origin: it comes to rest on the lower one
    let lower = prism_verts(40, 0.1, 0.05, 0.0);
    let upper = prism_verts(40, 0.05, 0.05, 0.5);
    let xml = format!(r#"<mujoco><option timestep="0.002"/><asset><mesh name="lower" vertex="{lower}"/>
        <mesh name="upper" vertex="{upper}"/></asset><worldbody>
        <body pos="0 0 0.05"><geom type="mesh" mesh="lower"/></body>
        <body pos="-0.5 0 0.2"><freejoint/><geom type="mesh" mesh="upper"/></body></worldbody></mujoco>"#);
    let m = Model::from_mjcf(&xml).unwrap();
    let mut s = State::new(&m);
    for _ in 0..1000 {
        s.step(&m);
    }
    // the upper prism's centre of mass, 0.05 above the lower prism's top face at z = 0.1
    let z = s.qpos[2];
    assert!((z - 0.15).abs() < 1e-6, "rests at z = {z}, expected 0.15");
}
