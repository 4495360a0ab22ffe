//! Ellipsoids collide as ellipsoids: a round one meets every shape as the sphere of its radius
//! does (the closed forms against the support-function contacts), and an ellipsoid comes to rest on
//! each shape at its own half-width.

#![allow(clippy::needless_range_loop)] // tests/common follows the math's index notation
mod common;

use sinew::{Model, State};

/// Geom `a` on a free body at `pos`/`quat` and geom `b` fixed at the origin, no gravity, every
/// geom with a 5 cm margin (so contacts of shapes apart are listed with their distance).
fn pair(a: &str, pos: [f64; 3], quat: [f64; 4], b: &str, quat_b: [f64; 4]) -> String {
    let [x, y, z] = pos;
    let [qw, qx, qy, qz] = quat;
    let [bw, bx, by, bz] = quat_b;
    format!(
        r#"<mujoco><option gravity="0 0 0" timestep="1e-9"/><default><geom margin="0.05"/></default><worldbody>
        <geom {b} quat="{bw} {bx} {by} {bz}"/>
        <body pos="{x} {y} {z}" quat="{qw} {qx} {qy} {qz}"><freejoint/><geom {a}/></body></worldbody></mujoco>"#
    )
}

/// (distance, normal) of the one contact of the scene, if any.
fn contact(xml: &str) -> Option<(f64, glam::DVec3)> {
    let m = Model::from_mjcf(xml).unwrap();
    let mut s = State::new(&m);
    s.step(&m);
    let c = &s.data.coll.contacts;
    assert!(c.len() <= 1, "{xml}: {} contacts", c.len());
    c.first().map(|c| (c.dist, c.normal))
}

fn unit_quat(r: &mut common::Rng) -> [f64; 4] {
    let q = [r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0), r.uniform(-1.0, 1.0)];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

#[test]
fn a_round_ellipsoid_meets_every_shape_as_the_sphere_does() {
    let others = [
        r#"type="sphere" size="0.08""#,
        r#"type="capsule" size="0.05 0.12""#,
        r#"type="box" size="0.1 0.07 0.05""#,
        r#"type="ellipsoid" size="0.08 0.08 0.08""#,
    ];
    let mut r = common::Rng(11);
    let mut touching = 0;
    for other in others {
        for _ in 0..200 {
            let pos = [r.uniform(-0.2, 0.2), r.uniform(-0.2, 0.2), r.uniform(-0.2, 0.2)];
            let (qa, qb) = (unit_quat(&mut r), unit_quat(&mut r));
            let sphere = contact(&pair(r#"type="sphere" size="0.1""#, pos, qa, other, qb));
            let ellipsoid = contact(&pair(r#"type="ellipsoid" size="0.1 0.1 0.1""#, pos, qa, other, qb));
            match (sphere, ellipsoid) {
                (Some((d1, n1)), Some((d2, n2))) => {
                    assert!((d1 - d2).abs() < 1e-9, "{other} at {pos:?}: distance {d2} against the sphere's {d1}");
                    assert!(n1.dot(n2) > 1.0 - 1e-12, "{other} at {pos:?}: normal {n2} against the sphere's {n1}");
                    touching += (d1 < 0.0) as usize;
                }
                // at the edge of the margin round-off may decide either way
                (None, None) | (Some((_, _)), None) | (None, Some((_, _))) if sphere.or(ellipsoid).is_none_or(|(d, _)| d > 0.045) => {}
                (a, b) => panic!("{other} at {pos:?}: the sphere finds {a:?}, the ellipsoid {b:?}"),
            }
        }
    }
    assert!(touching > 100, "only {touching} overlapping cases");
}

#[test]
fn an_ellipsoid_rests_on_every_shape_at_its_half_width() {
    // semi-axes 0.12, 0.07, 0.04, its shortest vertical and its longest along y, dropped centred
    // on a fixed shape whose top is at z = 0.2 (curved no more than keeps it stable)
    let supports = [
        r#"<geom type="plane" size="5 5 0.1" pos="0 0 0.2"/>"#,
        r#"<geom type="box" size="0.3 0.3 0.1" pos="0 0 0.1"/>"#,
        r#"<geom type="sphere" size="0.2"/>"#,
        r#"<geom type="capsule" size="0.05 0.3" pos="0 0 0.15" quat="0.7071068 0 0.7071068 0"/>"#,
        r#"<geom type="ellipsoid" size="0.3 0.25 0.2"/>"#,
    ];
    for support in supports {
        let xml = format!(
            r#"<mujoco><option timestep="0.002"/><worldbody>{support}
            <body pos="0 0 0.35" quat="0.7071068 0 0 0.7071068"><freejoint/><geom type="ellipsoid" size="0.12 0.07 0.04"/></body></worldbody></mujoco>"#
        );
        let m = Model::from_mjcf(&xml).unwrap();
        let mut s = State::new(&m);
        for _ in 0..1000 {
            s.step(&m);
        }
        let z = s.qpos[2];
        assert!((z - 0.24).abs() < 1e-6, "{support}: rests at z = {z}, expected 0.24");
        assert!(s.qvel.iter().all(|v| v.abs() < 1e-5), "{support}: still moving {:?}", s.qvel);
    }
}
