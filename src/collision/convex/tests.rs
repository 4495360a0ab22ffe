//! The separating-axis test's paths against each other: hinted against full, detailed hulls
//! along their normal, supports and point distances.

use glam::{DMat3, DQuat, DVec3};

use super::{point_polytope, polytopes, Kept, Polytope, PosedHull};
use crate::geometry::Hull;

/// Points on an ellipsoid of semi-axes `radii`, `n` of them along a Fibonacci spiral.
pub(in crate::collision) fn ellipsoid_points(n: usize, radii: DVec3) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let (r, t) = ((1.0 - z * z).sqrt(), golden * i as f64);
            radii * DVec3::new(r * t.cos(), r * t.sin(), z)
        })
        .collect()
}

#[test]
fn a_hinted_test_finds_what_the_full_test_finds() {
    // hulls of ~180 edges each: 32,000 edge pairs, above the hinted threshold
    let (ha, hb) = (Hull::new(&ellipsoid_points(60, DVec3::new(0.1, 0.07, 0.05))).unwrap(), Hull::new(&ellipsoid_points(64, DVec3::new(0.08, 0.08, 0.06))).unwrap());
    assert!(ha.edges.len() * hb.edges.len() > 4096);
    let mut x: u64 = 3;
    let mut rnd = || {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut touching = 0;
    for _ in 0..200 {
        let rot = |r: &mut dyn FnMut() -> f64| DMat3::from_quat(DQuat::from_xyzw(r(), r(), r(), r()).normalize());
        let (ra, rb) = (rot(&mut rnd), rot(&mut rnd));
        let c = DVec3::new(rnd(), rnd(), rnd()).normalize() * 0.13;
        let (a, b) = (PosedHull { hull: &ha, c: DVec3::ZERO, rot: ra }, PosedHull { hull: &hb, c, rot: rb });
        let full = polytopes(&a, &b, 0.0, 0.2, None, &mut Kept::default());
        if full.is_empty() {
            continue;
        }
        touching += 1;
        // the hint: the deepest point pair's normal, as EPA gives it (from B to A)
        let hint = full.iter().min_by(|p, q| p.3.total_cmp(&q.3)).unwrap().2;
        let hinted = polytopes(&a, &b, 0.0, 0.2, Some(hint), &mut Kept::default());
        let deepest = |m: &super::Manifold| m.iter().map(|p| p.3).fold(f64::INFINITY, f64::min);
        assert!((deepest(&full) - deepest(&hinted)).abs() < 1e-12, "{full:?} vs {hinted:?}");
        assert_eq!(full.len(), hinted.len());
    }
    assert!(touching > 20, "{touching} touching poses");
}

#[test]
fn detailed_hulls_collide_along_the_normal_at_their_true_depth() {
    // two spheres of 3,000 vertices (9,000 edges each): collided along the normal
    let ball = Hull::new(&ellipsoid_points(3000, DVec3::splat(0.1))).unwrap();
    assert!(ball.edges.len() * ball.edges.len() > 250_000);
    let a = PosedHull { hull: &ball, c: DVec3::new(0.0, 0.0, 0.199), rot: DMat3::IDENTITY };
    let b = PosedHull { hull: &ball, c: DVec3::ZERO, rot: DMat3::IDENTITY };
    let m = polytopes(&a, &b, 0.0, 0.2, Some(DVec3::Z), &mut Kept::default());
    assert!(!m.is_empty());
    // 1 mm deep, to the hulls' faceting (a 3,000-point sphere's faces lie within 0.1 mm of it)
    let d = m.iter().map(|p| p.3).fold(f64::INFINITY, f64::min);
    assert!((d + 0.001).abs() < 3e-4, "depth {d}");
    assert!(m.iter().all(|p| p.2.dot(DVec3::Z) > 0.99));
    let apart = PosedHull { hull: &ball, c: DVec3::new(0.0, 0.0, 0.21), rot: DMat3::IDENTITY };
    assert!(polytopes(&apart, &b, 0.0, 0.2, Some(DVec3::Z), &mut Kept::default()).is_empty());
}

#[test]
fn a_point_s_distance_is_the_nearest_face_s() {
    // beside every face's nearest point (no face passed by) and, inside, the least
    // penetration: points around a posed hull of 400 faces, outside, near and inside
    let hull = Hull::new(&ellipsoid_points(200, DVec3::new(0.1, 0.06, 0.04))).unwrap();
    let p = PosedHull { hull: &hull, c: DVec3::new(0.3, -0.2, 0.1), rot: DMat3::from_quat(DQuat::from_xyzw(0.3, -0.2, 0.5, 0.8).normalize()) };
    let face_point = |f: usize, q: DVec3| {
        let (n, d) = p.plane(f);
        let on = q - n * (n.dot(q) - d);
        let k = p.face_len(f);
        let v = |i: usize| p.vert(p.face_vert(f, i % k));
        if (0..k).all(|i| (v(i + 1) - v(i)).cross(n).dot(on - v(i)) <= 0.0) {
            on
        } else {
            (0..k).map(|i| crate::collision::shapes::closest_on_segment(v(i), v(i + 1), q)).min_by(|a, b| a.distance_squared(q).total_cmp(&b.distance_squared(q))).unwrap()
        }
    };
    let (mut outside, mut inside) = (0, 0);
    for i in 0..2000 {
        let dir = ellipsoid_points(2000, DVec3::ONE)[i];
        let q = p.c + dir * (0.02 + 0.15 * (i % 7) as f64 / 6.0);
        let (normal, dist) = point_polytope(&p, q);
        let top = (0..p.nface()).map(|f| p.plane(f).0.dot(q) - p.plane(f).1).fold(f64::NEG_INFINITY, f64::max);
        if top <= 0.0 {
            assert!((dist - top).abs() < 1e-12, "{dist} {top}");
            inside += 1;
        } else {
            let nearest = (0..p.nface()).map(|f| face_point(f, q).distance(q)).fold(f64::INFINITY, f64::min);
            assert!((dist - nearest).abs() < 1e-12, "{dist} {nearest}");
            assert!((p.support(normal) - normal.dot(q) + dist).abs() < 1e-9, "normal {normal}");
            outside += 1;
        }
    }
    assert!(outside > 500 && inside > 100, "{outside} {inside}");
}

#[test]
fn a_hull_s_support_climbs_to_its_farthest_vertex_from_anywhere() {
    let hull = Hull::new(&ellipsoid_points(3000, DVec3::new(0.1, 0.06, 0.04))).unwrap();
    for (i, d) in ellipsoid_points(500, DVec3::ONE).into_iter().enumerate() {
        let best = hull.vert.iter().map(|v| v.dot(d)).fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(hull.support(d).1, best);
        assert_eq!(hull.support_from(d, Some(i * 5 % hull.vert.len())).1, best);
    }
}
