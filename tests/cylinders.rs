//! Cylinders collide as cylinders (not as capsules): the distance to a sphere and to a plane equals
//! the closed form at random poses, a cylinder rests on a cap or its side at its own height on a
//! plane, a box, another cylinder and a height field, things rest on its cap, and one rolling down
//! an incline accelerates at (2/3) g sin θ.

#![allow(clippy::needless_range_loop)] // tests/common follows the math's index notation
mod common;

use glam::{DQuat, DVec3};
use sinew::{Model, State};

/// Geom `a` on a free body at `pos`/`quat` and geom `b` fixed at the origin with `quat_b`, no
/// gravity, a 5 cm margin on every geom.
fn pair(a: &str, pos: DVec3, quat: DQuat, b: &str, quat_b: DQuat) -> String {
    format!(
        r#"<mujoco><option gravity="0 0 0" timestep="1e-9"/><default><geom margin="0.05"/></default><worldbody>
        <geom {b} quat="{} {} {} {}"/>
        <body pos="{} {} {}" quat="{} {} {} {}"><freejoint/><geom {a}/></body></worldbody></mujoco>"#,
        quat_b.w, quat_b.x, quat_b.y, quat_b.z, pos.x, pos.y, pos.z, quat.w, quat.x, quat.y, quat.z
    )
}

/// The least contact distance of the scene (None: no contact within the margin).
fn least(xml: &str) -> Option<f64> {
    let m = Model::from_mjcf(xml).unwrap();
    let mut s = State::new(&m);
    s.step(&m);
    s.data.coll.contacts.iter().map(|c| c.dist).min_by(f64::total_cmp)
}

fn unit_quat(r: &mut common::Rng) -> DQuat {
    DQuat::from_xyzw(r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)).normalize()
}

/// Distance from point `q` to the cylinder (radius r, half-length h, axis z) posed by `rot` at the
/// origin: positive outside, minus the depth inside.
fn point_to_cylinder(q: DVec3, rot: DQuat, r: f64, h: f64) -> f64 {
    let l = rot.inverse() * q;
    let (dr, dz) = ((l.x * l.x + l.y * l.y).sqrt() - r, l.z.abs() - h);
    if dr > 0.0 && dz > 0.0 { dr.hypot(dz) } else { dr.max(dz) }
}

#[test]
fn a_sphere_and_a_plane_find_a_cylinder_at_its_exact_distance() {
    let (r, h, rs) = (0.08, 0.12, 0.06);
    let mut rng = common::Rng(5);
    let mut touching = 0;
    for _ in 0..300 {
        let pos = DVec3::new(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
        let qb = unit_quat(&mut rng);
        let exact = point_to_cylinder(pos, qb, r, h) - rs;
        let found = least(&pair(&format!(r#"type="sphere" size="{rs}""#), pos, DQuat::IDENTITY, &format!(r#"type="cylinder" size="{r} {h}""#), qb));
        match found {
            Some(d) => {
                assert!((d - exact).abs() < 1e-12, "sphere at {pos}: distance {d}, exact {exact}");
                touching += (d < 0.0) as usize;
            }
            None => assert!(exact > 0.045, "sphere at {pos}: no contact at distance {exact}"),
        }
    }
    assert!(touching > 30, "only {touching} overlapping cases");
    // the plane z = 0 against a cylinder at random orientations: its lowest point
    for _ in 0..100 {
        let (z, q) = (rng.uniform(-0.05, 0.2), unit_quat(&mut rng));
        let a = q * DVec3::Z;
        let exact = z - h * a.z.abs() - r * (1.0 - a.z * a.z).max(0.0).sqrt();
        let found = least(&pair(&format!(r#"type="cylinder" size="{r} {h}""#), DVec3::new(0.0, 0.0, z), q, r#"type="plane" size="1 1 0.1""#, DQuat::IDENTITY));
        match found {
            Some(d) => assert!((d - exact).abs() < 1e-12, "plane: distance {d}, exact {exact}"),
            None => assert!(exact > 0.045, "plane: no contact at distance {exact}"),
        }
    }
}

/// Steps `xml` (a free body named "c") for `seconds`; its final position and the z of its
/// local z axis, and the deepest penetration met on the way.
fn settle(xml: &str, seconds: f64) -> (DVec3, DVec3, f64) {
    let m = Model::from_mjcf(xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    let mut s = State::new(&m);
    let mut deepest: f64 = 0.0;
    for _ in 0..(seconds / m.opt.timestep) as usize {
        s.step(&m);
        deepest = s.data.coll.contacts.iter().map(|c| c.dist).fold(deepest, f64::min);
    }
    let q = DQuat::from_xyzw(s.qpos[4], s.qpos[5], s.qpos[6], s.qpos[3]);
    (DVec3::new(s.qpos[0], s.qpos[1], s.qpos[2]), q * DVec3::Z, deepest)
}

#[test]
fn a_cylinder_rests_on_its_cap_or_its_side_at_its_own_height() {
    // radius 0.05, half-length 0.1, dropped 2 cm above its resting height on supports whose top
    // is at z = 0.2
    let supports = [
        ("plane", r#"<geom type="plane" size="5 5 0.1" pos="0 0 0.2"/>"#),
        ("box", r#"<geom type="box" size="0.3 0.3 0.1" pos="0 0 0.1"/>"#),
        ("cylinder", r#"<geom type="cylinder" size="0.3 0.1" pos="0 0 0.1"/>"#),
        ("height field", r#"<geom type="hfield" hfield="flat" pos="0 0 0.2"/>"#),
    ];
    let asset = r#"<asset><hfield name="flat" nrow="5" ncol="5" size="0.5 0.5 0.1 0.1" elevation="0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0"/></asset>"#;
    for (name, support) in supports {
        for (pose, quat, rest) in [("upright", "1 0 0 0", 0.1), ("lying", "0.7071068 0.7071068 0 0", 0.05)] {
            let xml = format!(
                r#"<mujoco><option timestep="0.002"/>{asset}<worldbody>{support}
                <body name="c" pos="0.01 -0.02 {}" quat="{quat}"><freejoint/><geom type="cylinder" size="0.05 0.1"/></body></worldbody></mujoco>"#,
                0.22 + rest
            );
            let (p, axis, deepest) = settle(&xml, 1.0);
            assert!((p.z - (0.2 + rest)).abs() < 2e-4, "{pose} on a {name}: rests at z = {}, not {}", p.z, 0.2 + rest);
            assert!(deepest > -1e-3, "{pose} on a {name}: {deepest} deep");
            let tilt = if pose == "upright" { 1.0 - axis.z } else { axis.z.abs() };
            assert!(tilt < 1e-6, "{pose} on a {name}: its axis turned to {axis}");
        }
    }
}

#[test]
fn a_box_a_capsule_and_a_cylinder_rest_on_a_cylinders_cap() {
    // the fixed cylinder's cap at z = 0.2
    let loads = [
        ("box", r#"type="box" size="0.04 0.03 0.02""#, 0.02, DVec3::Z),
        ("capsule", r#"type="capsule" size="0.02 0.05" quat="0.7071068 0 0.7071068 0""#, 0.02, DVec3::X),
        ("cylinder", r#"type="cylinder" size="0.03 0.04""#, 0.04, DVec3::Z),
    ];
    for (name, geom, rest, along) in loads {
        let xml = format!(
            r#"<mujoco><option timestep="0.002"/><worldbody><geom type="cylinder" size="0.15 0.1" pos="0 0 0.1"/>
            <body name="c" pos="0.02 0.01 {}"><freejoint/><geom {geom}/></body></worldbody></mujoco>"#,
            0.21 + rest
        );
        let (p, _, deepest) = settle(&xml, 1.0);
        assert!((p.z - (0.2 + rest)).abs() < 2e-4, "a {name} rests at z = {}, not {}", p.z, 0.2 + rest);
        assert!(deepest > -1e-3, "a {name}: {deepest} deep");
        // its own axis kept (the capsule's lies along x)
        let m = Model::from_mjcf(&xml).unwrap();
        let mut s = State::new(&m);
        for _ in 0..500 {
            s.step(&m);
        }
        let q = DQuat::from_xyzw(s.qpos[4], s.qpos[5], s.qpos[6], s.qpos[3]);
        let local = if name == "capsule" { DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2) * DVec3::Z } else { DVec3::Z };
        assert!((q * local).dot(along) > 1.0 - 1e-6, "a {name} tipped: axis {}", q * local);
    }
}

#[test]
fn a_cylinder_rolls_down_an_incline_at_two_thirds_g_sin_theta() {
    // a solid cylinder rolling without slipping: a = g sin θ / (1 + I / (m r²)) = (2/3) g sin θ
    let theta: f64 = 0.2;
    let (r, g) = (0.05, 9.81);
    let q = DQuat::from_rotation_y(theta);
    let normal = q * DVec3::Z;
    let centre = normal * (r + 1e-4);
    let along = q * DVec3::X;
    let body = q * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    let xml = format!(
        r#"<mujoco><option timestep="0.001" gravity="0 0 -{g}"/><worldbody>
        <geom type="plane" size="5 5 0.1" quat="{} {} {} {}" friction="1"/>
        <body name="c" pos="{} {} {}" quat="{} {} {} {}"><freejoint/><geom type="cylinder" size="{r} 0.1" friction="1"/></body>
        </worldbody></mujoco>"#,
        q.w, q.x, q.y, q.z, centre.x, centre.y, centre.z, body.w, body.x, body.y, body.z
    );
    let m = Model::from_mjcf(&xml).unwrap();
    let mut s = State::new(&m);
    let t = 1.0;
    for _ in 0..(t / m.opt.timestep) as usize {
        s.step(&m);
    }
    let p = DVec3::new(s.qpos[0], s.qpos[1], s.qpos[2]);
    let downhill = if along.z < 0.0 { along } else { -along };
    let travelled = (p - centre).dot(downhill);
    let exact = 0.5 * (2.0 / 3.0) * g * theta.sin() * t * t;
    assert!((travelled - exact).abs() < 2e-3 * exact, "rolled {travelled} m in {t} s, exact {exact}");
    // still on its side, on the plane
    assert!(((p.dot(normal)) - r).abs() < 2e-4, "height above the plane {}", p.dot(normal));
}
