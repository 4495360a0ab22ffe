//! The narrowphase: each geom as a shape in world, one arm per unordered pair of shapes, and
//! MuJoCo's rule for a pair's friction and condim.

use glam::{DMat3, DVec3};

use super::convex::{on_plane, point_polytope, polytopes, Manifold, PosedBox, PosedHull, Segment};
use super::data::{pose_axes, CollisionData, Contact, Scratch, Separation};
use super::cylinder;
use super::plane_walk::hull_on_plane;
use super::ellipsoid;
use super::terrain::hfield_contacts;
use super::shapes::{box_box, boxes_part, closest_on_segment, closest_segments, point_box, segment_box_points, shape, spheres, Shape};
use crate::dynamics::kinematics::KinData;
use crate::model::{GeomPair, Model, PairFriction};

/// The friction of a contact between geoms i and j as MuJoCo combines them: the higher-priority
/// geom's condim and coefficients, else the larger of each (a condim-1 foot on a condim-3 floor
/// has friction).
pub fn contact_friction(m: &Model, i: usize, j: usize) -> PairFriction {
    let (fi, fj) = (m.geom_friction[i], m.geom_friction[j]);
    let (coef, condim) = match m.geom_priority[i].cmp(&m.geom_priority[j]) {
        std::cmp::Ordering::Greater => (fi, m.geom_condim[i]),
        std::cmp::Ordering::Less => (fj, m.geom_condim[j]),
        std::cmp::Ordering::Equal => (std::array::from_fn(|k| fi[k].max(fj[k])), m.geom_condim[i].max(m.geom_condim[j])),
    };
    PairFriction::new(condim, coef)
}

/// Where a pair's contacts go: kept when within the margin, with the pair's friction.
struct Sink<'a> {
    m: &'a Model,
    margin: f64,
    friction: PairFriction,
}

impl Sink<'_> {
    /// Appends a contact of geoms g1 and g2 within the margin (the deepest kept when full).
    #[allow(clippy::too_many_arguments)]
    fn add(&self, cd: &mut CollisionData, g1: usize, g2: usize, feature: usize, pos: DVec3, normal: DVec3, dist: f64) {
        let c = Contact { geom1: g1, geom2: g2, feature, pos, normal, dist, friction: self.friction };
        if dist > self.margin || repeats_joint_contact(self.m, &cd.contacts, &c) {
            return;
        }
        if cd.contacts.len() < self.m.opt.max_contacts {
            cd.contacts.push(c);
        } else if let Some(widest) = (0..cd.contacts.len()).max_by(|&a, &b| cd.contacts[a].dist.total_cmp(&cd.contacts[b].dist)) {
            // full: the deepest are kept
            if cd.contacts[widest].dist > dist {
                cd.contacts[widest] = c;
            }
        }
    }
}

/// Narrowphase of geoms i and j: appends the contacts within `margin`. Returns the distance
/// between the geoms where a pair of spheres and capsules gives it exactly, a lower bound on it
/// where their oriented boxes part them before GJK, else −∞.
pub(super) fn pair(m: &Model, kin: &KinData, cd: &mut CollisionData, p: &GeomPair, margin: f64) -> f64 {
    let (i, j, explicit) = (p.g1, p.g2, p.friction);
    pose_axes(m, kin, cd, i);
    pose_axes(m, kin, cd, j);
    let (si, sj) = (shape(m, cd, i), shape(m, cd, j));
    let friction = explicit.unwrap_or_else(|| contact_friction(m, i, j));
    let sink = Sink { m, margin, friction };
    // order so that a plane or height field, if any, is geom2 (the normal then points out of it)
    let (g1, g2, s1, s2) = match (si, sj) {
        (Shape::Plane { .. } | Shape::HField { .. }, _) => (j, i, sj, si),
        _ => (i, j, si, sj),
    };
    match round_pair(&sink, cd, (g1, s1), (g2, s2)) {
        Some(d) => d,
        None => {
            // the pair's kept separation (an axis turned into world), the test's kept
            let slot = p.kept.map(|s| s as usize);
            let turn = |kept: Separation, rot: DMat3| if let Separation::Axis(n) = kept { Separation::Axis(rot * n) } else { kept };
            cd.scratch.kept.sep = slot.map_or(Separation::Unknown, |s| turn(cd.pair_kept[s], cd.geom_xmat[i]));
            cd.scratch.parted = f64::NEG_INFINITY;
            solid_pair(&sink, cd, (g1, s1), (g2, s2));
            if let Some(s) = slot {
                cd.pair_kept[s] = turn(cd.scratch.kept.sep, cd.geom_xmat[i].transpose());
            }
            cd.scratch.kept.sep = Separation::Unknown;
            cd.scratch.parted
        }
    }
}

/// Spheres and capsules against each other and against a plane: None for any other pair; the
/// distance where it is exact (two round shapes), else −∞.
fn round_pair(sink: &Sink, cd: &mut CollisionData, (g1, s1): (usize, Shape), (g2, s2): (usize, Shape)) -> Option<f64> {
    let add = |cd: &mut CollisionData, feature: usize, pos: DVec3, n: DVec3, d: f64| sink.add(cd, g1, g2, feature, pos, n, d);
    let (pos, n, d) = match (s1, s2) {
        (Shape::Sphere { c, r }, Shape::Plane { p, n }) => {
            let d = (c - p).dot(n) - r;
            add(cd, 0, c - n * (r + 0.5 * d), n, d);
            return Some(f64::NEG_INFINITY);
        }
        (Shape::Segment { a, b, r }, Shape::Plane { p, n }) => {
            for (k, e) in [a, b].into_iter().enumerate() {
                let d = (e - p).dot(n) - r;
                add(cd, k, e - n * (r + 0.5 * d), n, d);
            }
            return Some(f64::NEG_INFINITY);
        }
        (Shape::Sphere { c: c1, r: r1 }, Shape::Sphere { c: c2, r: r2 }) => spheres(c1, r1, c2, r2),
        (Shape::Sphere { c, r }, Shape::Segment { a, b, r: rs }) => spheres(c, r, closest_on_segment(a, b, c), rs),
        (Shape::Segment { a, b, r: rs }, Shape::Sphere { c, r }) => spheres(closest_on_segment(a, b, c), rs, c, r),
        (Shape::Segment { a: a1, b: b1, r: r1 }, Shape::Segment { a: a2, b: b2, r: r2 }) => {
            let (p1, p2) = closest_segments(a1, b1, a2, b2);
            spheres(p1, r1, p2, r2)
        }
        _ => return None,
    };
    add(cd, 0, pos, n, d);
    Some(d)
}

/// Every pair [`round_pair`] leaves: boxes, ellipsoids, cylinders, hulls and height fields.
fn solid_pair(sink: &Sink, cd: &mut CollisionData, (g1, s1): (usize, Shape), (g2, s2): (usize, Shape)) {
    let (m, margin) = (sink.m, sink.margin);
    let add = |cd: &mut CollisionData, feature: usize, pos: DVec3, n: DVec3, d: f64| sink.add(cd, g1, g2, feature, pos, n, d);
    let each = |cd: &mut CollisionData, found: &[(usize, DVec3, DVec3, f64)], sign: f64| {
        for &(feature, pos, n, d) in found {
            add(cd, feature, pos, sign * n, d);
        }
    };
    match (s1, s2) {
        (Shape::Box { c, rot, half }, Shape::Plane { p, n }) => {
            // the corners (feature: the corner's sign bits) within the margin
            each(cd, &on_plane(&PosedBox { c, rot, half }, p, n, margin), 1.0);
        }
        (Shape::Sphere { c, r }, Shape::Box { c: bc, rot, half }) => {
            let (n, d) = point_box(c, bc, rot, half, c - bc);
            add(cd, 0, c - n * (r + 0.5 * (d - r)), n, d - r);
        }
        (Shape::Box { c: bc, rot, half }, Shape::Sphere { c, r }) => {
            let (n, d) = point_box(c, bc, rot, half, c - bc);
            add(cd, 0, c - n * (r + 0.5 * (d - r)), -n, d - r);
        }
        (Shape::Segment { a, b, r }, Shape::Box { c: bc, rot, half }) => {
            for (k, p) in segment_box_points(a, b, bc, rot, half).into_iter().enumerate().filter(|&(k, p)| k < 2 || (p.distance(a) > 1e-9 && p.distance(b) > 1e-9)) {
                let (n, d) = point_box(p, bc, rot, half, (a + b) * 0.5 - bc);
                add(cd, k, p - n * (r + 0.5 * (d - r)), n, d - r);
            }
        }
        (Shape::Box { c: bc, rot, half }, Shape::Segment { a, b, r }) => {
            for (k, p) in segment_box_points(a, b, bc, rot, half).into_iter().enumerate().filter(|&(k, p)| k < 2 || (p.distance(a) > 1e-9 && p.distance(b) > 1e-9)) {
                let (n, d) = point_box(p, bc, rot, half, (a + b) * 0.5 - bc);
                add(cd, k, p - n * (r + 0.5 * (d - r)), -n, d - r);
            }
        }
        (Shape::Box { c: c1, rot: r1, half: h1 }, Shape::Box { c: c2, rot: r2, half: h2 }) => {
            let (points, count) = box_box((c1, r1, h1), (c2, r2, h2), margin, &mut cd.scratch.kept);
            each(cd, &points[..count], 1.0);
        }
        (Shape::Ellipsoid { c, rot, radii }, Shape::Plane { p, n }) => {
            let (pos, n, d) = ellipsoid::on_plane(c, rot, radii, p, n);
            add(cd, 0, pos, n, d);
        }
        (Shape::Ellipsoid { .. }, other) | (other, Shape::Ellipsoid { .. }) if !matches!(other, Shape::HField { .. }) => {
            if let Some((pos, n, d)) = ellipsoid::convex(s1, s2, margin, &mut cd.scratch) {
                add(cd, 0, pos, n, d);
            }
        }
        (Shape::Cylinder(cyl), Shape::Plane { p, n }) => {
            each(cd, &cylinder::on_plane(&cyl, p, n, margin), 1.0);
        }
        // a hull's GJK first meets the boxes
        (Shape::Cylinder(_), Shape::Hull { .. }) | (Shape::Hull { .. }, Shape::Cylinder(_)) if boxes_part(&s1, &s2, margin, &mut cd.scratch.parted) => {}
        (Shape::Cylinder(cyl), other) if !matches!(other, Shape::HField { .. }) => {
            let found = cylinder::pair(&cyl, other, margin, &mut cd.scratch);
            each(cd, &found, 1.0);
        }
        (other, Shape::Cylinder(cyl)) => {
            // normals from geom 2 to geom 1 (a plane or height field is geom 2 already)
            let found = cylinder::pair(&cyl, other, margin, &mut cd.scratch);
            each(cd, &found, -1.0);
        }
        (Shape::Hull { .. } | Shape::HField { .. }, _) | (_, Shape::Hull { .. } | Shape::HField { .. }) => {
            let found = convex_pair(m, (s1, g1), (s2, g2), margin, &mut cd.scratch);
            each(cd, &found, 1.0);
        }
        _ => {}
    }
}

/// Edge pairs beyond which a hull pair's separating-axis test looks near GJK's and EPA's normal
/// only (a box against a hull of under 342 edges, two hulls of 64 edges each, test every pair).
const MANY_EDGE_PAIRS: usize = 4096;

/// Contacts of a pair with a hull or a height field (shape 2; normals from shape 2 to shape 1).
fn convex_pair(m: &Model, (s1, g1): (Shape, usize), (s2, g2): (Shape, usize), margin: f64, epa: &mut Scratch) -> Manifold {
    match s2 {
        Shape::HField { p, rot, field } => hfield_contacts(field, p, rot, s1, margin, m.geom_rbound[g1], epa),
        _ => hull_pair(s1, s2, margin, m.geom_rbound[g1] + m.geom_rbound[g2], epa),
    }
}

/// Contacts of a pair with a hull (normals from shape 2 to shape 1).
fn hull_pair(s1: Shape, s2: Shape, margin: f64, scale: f64, epa: &mut Scratch) -> Manifold {
    // a pair of many edges (a robot's meshes), or a sphere and a hull of many faces: GJK and EPA
    // first (beyond the margin by more than their tolerance: no contact), then the
    // separating-axis test near their normal only
    let edges = |s: &Shape| match s {
        Shape::Hull { hull, .. } => hull.edges.len(),
        Shape::Box { .. } => 12,
        _ => 1,
    };
    let many = edges(&s1) * edges(&s2) > MANY_EDGE_PAIRS || matches!((s1, s2), (Shape::Sphere { .. }, Shape::Hull { hull, .. }) | (Shape::Hull { hull, .. }, Shape::Sphere { .. }) if hull.faces.len() > 64);
    let hint = if !matches!(s2, Shape::Plane { .. }) && many {
        if boxes_part(&s1, &s2, margin + 1e-6 * scale, &mut epa.parted) {
            return Manifold::new();
        }
        match ellipsoid::normal(s1, s2, margin + 1e-6 * scale, scale, epa) {
            Some(n) => Some(n),
            None => return Manifold::new(),
        }
    } else {
        None
    };
    let flip = |mut m: Manifold| {
        for p in m.iter_mut() {
            p.2 = -p.2;
        }
        m
    };
    let one = |feature, pos, n, d| {
        let mut m = Manifold::new();
        m.push((feature, pos, n, d));
        m
    };
    // a capsule is its core segment within margin + r: its surface is r nearer the other shape
    let rounded = |mut m: Manifold, r: f64, toward_core: f64| {
        for p in m.iter_mut() {
            p.1 -= p.2 * (toward_core * 0.5 * r);
            p.3 -= r;
        }
        m
    };
    match (s1, s2) {
        (Shape::Hull { c, rot, hull }, Shape::Plane { p, n }) => hull_on_plane(&PosedHull { hull, c, rot }, p, n, margin, epa),
        (Shape::Sphere { c, r }, Shape::Hull { c: hc, rot, hull }) | (Shape::Hull { c: hc, rot, hull }, Shape::Sphere { c, r }) => {
            let (out, d) = point_polytope(&PosedHull { hull, c: hc, rot }, c);
            let n = if matches!(s1, Shape::Sphere { .. }) { out } else { -out };
            one(0, c - out * (r + 0.5 * (d - r)), n, d - r)
        }
        (Shape::Hull { c, rot, hull }, Shape::Segment { a, b, r }) => rounded(polytopes(&PosedHull { hull, c, rot }, &Segment { a, b }, margin + r, scale, hint, &mut epa.kept), r, -1.0),
        (Shape::Segment { a, b, r }, Shape::Hull { c, rot, hull }) => flip(rounded(polytopes(&PosedHull { hull, c, rot }, &Segment { a, b }, margin + r, scale, hint.map(|n| -n), &mut epa.kept), r, -1.0)),
        (Shape::Hull { c, rot, hull }, Shape::Box { c: bc, rot: br, half }) => polytopes(&PosedHull { hull, c, rot }, &PosedBox { c: bc, rot: br, half }, margin, scale, hint, &mut epa.kept),
        (Shape::Box { c: bc, rot: br, half }, Shape::Hull { c, rot, hull }) => polytopes(&PosedBox { c: bc, rot: br, half }, &PosedHull { hull, c, rot }, margin, scale, hint, &mut epa.kept),
        (Shape::Hull { c, rot, hull }, Shape::Hull { c: c2, rot: r2, hull: h2 }) => polytopes(&PosedHull { hull, c, rot }, &PosedHull { hull: h2, c: c2, rot: r2 }, margin, scale, hint, &mut epa.kept),
        _ => Manifold::new(),
    }
}

/// Whether `c` repeats a contact of the parent or child body at the same point with the same
/// normal against the same geom, as where two capsules meet at a joint touch the floor together.
/// The joint's anchor moves with both bodies, so the two rows would be identical and K singular.
pub(super) fn repeats_joint_contact(m: &Model, contacts: &[Contact], c: &Contact) -> bool {
    let b = m.geom_body[c.geom1];
    let tol = 1e-9 * m.geom_rbound[c.geom1];
    // |Δx| > tol already puts the points farther apart than tol (√(x²) is |x| in floating point,
    // and the other squares only add): most contacts fail that before their bodies are read
    contacts.iter().any(|o| {
        o.geom2 == c.geom2
            && (o.pos.x - c.pos.x).abs() <= tol
            && o.pos.distance(c.pos) <= tol
            && { let ob = m.geom_body[o.geom1]; m.body_parent[ob] == b || m.body_parent[b] == ob }
            && o.normal.dot(c.normal) > 1.0 - 1e-12
    })
}
