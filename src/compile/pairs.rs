//! The collision data a model carries, decided once at compile time: bounding radii, MuJoCo's
//! configuration-independent pair filters, and each pair's broadphase test (run by
//! `collision`).

use glam::DVec3;

use crate::model::{GeomPair, GeomType, Model, PairTest, WORLD};

/// Bounding radius of a geom about its centre (planes: infinite).
pub fn geom_rbound(kind: GeomType, s: [f64; 3]) -> f64 {
    match kind {
        GeomType::Plane => f64::INFINITY,
        GeomType::Sphere => s[0],
        GeomType::Capsule | GeomType::Cylinder => s[0] + s[1],
        GeomType::Box => DVec3::from_array(s).length(),
        GeomType::Ellipsoid => s[0].max(s[1]).max(s[2]),
    }
}

/// Whether geoms i and j may collide at all (independent of configuration).
pub fn can_collide(m: &Model, i: usize, j: usize) -> bool {
    let (bi, bj) = (m.geom_body[i], m.geom_body[j]);
    if bi == bj {
        return false;
    }
    if m.geom_contype[i] & m.geom_conaffinity[j] == 0 && m.geom_contype[j] & m.geom_conaffinity[i] == 0 {
        return false;
    }
    // both static
    if m.body_node[bi] == WORLD && m.body_node[bj] == WORLD {
        return false;
    }
    // parent–child, unless the parent is the world
    let (pi, pj) = (m.body_parent[bi], m.body_parent[bj]);
    if (pi == bj && bj != 0) || (pj == bi && bi != 0) {
        return false;
    }
    !m.exclude_pairs.contains(&(bi.min(bj), bi.max(bj)))
}

/// The broadphase test of geoms i < j, which [`can_collide`].
pub fn geom_pair(m: &Model, i: usize, j: usize) -> GeomPair {
    let margin = m.geom_margin[i].max(m.geom_margin[j]);
    let (ri, rj) = (m.geom_rbound[i], m.geom_rbound[j]);
    let (test, radii) = match (ri.is_finite(), rj.is_finite()) {
        (true, true) => (PairTest::Spheres, ri + rj),
        (false, true) if m.geom_type[i] == GeomType::Plane => (PairTest::Plane { plane: i, other: j, group: None }, rj),
        (true, false) if m.geom_type[j] == GeomType::Plane => (PairTest::Plane { plane: j, other: i, group: None }, ri),
        _ => (PairTest::Always, 0.0),
    };
    GeomPair { g1: i, g2: j, test, margin, radii }
}
