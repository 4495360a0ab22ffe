//! Contacts of cylinders. A cylinder of radius r and half-length h about unit axis a is a disk
//! swept along a segment, with support s(d) = c + h sign(a·d) a + r P d / |P d|, P = I − a aᵀ
//! (`ellipsoid.rs` gives it to GJK, EPA and the Newton refinement). Its contacts with flat
//! things are lines and disks, which one closest point cannot hold, so beside that point each cap
//! offers four rim points (at 0°, 90°, 180° and 270° about the axis from the rim's point nearest
//! the other shape) tested as points against it: on a plane in closed form (a cylinder standing
//! on a cap gets four points, one lying on its side the two ends of its line), against a box, a
//! hull or a height field's prism by [`point_polytope`], against another cylinder by
//! [`point_cylinder`]; a capsule's two ends are tested as spheres against the cylinder, and a
//! box's, hull's or prism's vertices as points. Features: the closest point 0, a rim point
//! 1 + 4 × cap + k, a capsule's end 9 + end, a rim point of the other cylinder 11 + 4 × cap + k,
//! a polytope's vertex 19 + its index.

use glam::DVec3;

use arrayvec::ArrayVec;

use super::convex::{point_polytope, reduce, Manifold, Point, Polytope, PosedBox, PosedHull};
use super::prism::Prism;
use super::data::Scratch;
use super::ellipsoid;
use super::shapes::{Cyl, Shape};

impl Cyl {
    /// The unit direction normal to the axis nearest `d` (any normal one when `d` is along it).
    fn radial(&self, d: DVec3) -> DVec3 {
        // projected twice (see the support function in `ellipsoid.rs`)
        let w = d - self.axis * self.axis.dot(d);
        let w = w - self.axis * self.axis.dot(w);
        if w.length_squared() > 1e-28 * d.length_squared() { w.normalize() } else { self.axis.any_orthonormal_vector() }
    }

    /// Each cap's four rim points (feature 1 + 4 × cap + k), k = 0 the farthest along `d`.
    fn rim(&self, d: DVec3) -> [(usize, DVec3); 8] {
        let u = self.radial(d);
        let v = self.axis.cross(u);
        let dirs = [u, v, -u, -v];
        std::array::from_fn(|i| {
            let (cap, k) = (i / 4, i % 4);
            let end = if cap == 0 { -self.half } else { self.half };
            (1 + i, self.c + self.axis * end + dirs[k] * self.r)
        })
    }

    /// The least projection of a point of the cylinder on unit `n`.
    pub(super) fn lowest_along(&self, n: DVec3) -> f64 {
        let along = self.axis.dot(n);
        self.c.dot(n) - self.half * along.abs() - self.r * (1.0 - along * along).max(0.0).sqrt()
    }
}

/// Signed distance of point `q` from the cylinder and the unit normal from it toward `q`
/// (inside: out through the nearer of the side and the caps).
pub(super) fn point_cylinder(cyl: &Cyl, q: DVec3) -> (DVec3, f64) {
    let rel = q - cyl.c;
    let z = cyl.axis.dot(rel);
    let w = rel - cyl.axis * z;
    let rho = w.length();
    let side = if rho > 0.0 { w / rho } else { cyl.radial(rel) };
    let cap = cyl.axis * if z >= 0.0 { 1.0 } else { -1.0 };
    let (dr, dz) = (rho - cyl.r, z.abs() - cyl.half);
    match (dr > 0.0, dz > 0.0) {
        (true, true) => {
            let off = side * dr + cap * dz;
            let len = off.length();
            (off / len, len)
        }
        (true, false) => (side, dr),
        (false, true) => (cap, dz),
        (false, false) => if dr > dz { (side, dr) } else { (cap, dz) },
    }
}

/// Contacts of the cylinder with the plane through `p` of unit normal `n` within `margin`: the
/// rim points (normals `n`, points midway).
pub(super) fn on_plane(cyl: &Cyl, p: DVec3, n: DVec3, margin: f64) -> Manifold {
    let mut out = Manifold::new();
    for (feature, at) in cyl.rim(-n) {
        let d = (at - p).dot(n);
        if d <= margin {
            out.push((feature, at - n * (0.5 * d), n, d));
        }
    }
    out
}

/// Most candidate points of a pair gathered before reduction.
const MAX_GATHER: usize = 64;

/// Contacts of the cylinder with `other` (neither a plane nor a height field) within `margin`,
/// normals from `other` to the cylinder: the closest point (GJK or EPA, refined), then the points
/// that make a flat contact's support polygon — the rim points against `other`, and a box's or
/// hull's vertices, a cylinder's rim points or a capsule's ends against the cylinder — reduced to
/// at most [`MAX_MANIFOLD`].
pub(super) fn pair(cyl: &Cyl, other: Shape, margin: f64, epa: &mut Scratch) -> Manifold {
    let Some(closest) = ellipsoid::convex(Shape::Cylinder(*cyl), other, margin, epa) else { return Manifold::new() };
    let mut pts = Gather::new(cyl, closest, margin);
    match other {
        Shape::Box { c, rot, half } => pts.polytope(&PosedBox { c, rot, half }),
        Shape::Hull { c, rot, hull } => pts.polytope(&PosedHull { hull, c, rot }),
        Shape::Cylinder(o) => {
            pts.rim_against(|at| point_cylinder(&o, at));
            for (f, at) in o.rim(closest.1) {
                pts.against_cylinder(10 + f, at, 0.0);
            }
        }
        Shape::Segment { a, b, r } => {
            pts.against_cylinder(9, a, r);
            pts.against_cylinder(10, b, r);
        }
        _ => {}
    }
    pts.reduce()
}

/// Contacts of the cylinder with a height field's prism within `margin` (normals from the prism).
pub(super) fn with_prism(cyl: &Cyl, prism: &Prism, margin: f64, epa: &mut Scratch) -> Manifold {
    let Some(closest) = ellipsoid::with_polytope(Shape::Cylinder(*cyl), prism, margin, epa) else { return Manifold::new() };
    let mut pts = Gather::new(cyl, closest, margin);
    pts.polytope(prism);
    pts.reduce()
}

/// A pair's candidate points: the closest point first.
struct Gather<'a> {
    cyl: &'a Cyl,
    margin: f64,
    /// The cylinder's surface point of the closest point, which a rim point may repeat.
    closest: DVec3,
    normal: DVec3,
    pts: ArrayVec<Point, MAX_GATHER>,
}

impl<'a> Gather<'a> {
    fn new(cyl: &'a Cyl, (pos, n, d): ellipsoid::Touch, margin: f64) -> Self {
        let mut pts = ArrayVec::new();
        pts.push((0, pos, n, d));
        Gather { cyl, margin, closest: pos + n * (0.5 * d), normal: n, pts }
    }

    /// The cylinder's surface point `at`, `dist` from the other shape along `normal` (toward the
    /// cylinder).
    fn add(&mut self, feature: usize, at: DVec3, normal: DVec3, dist: f64) {
        let tol = 1e-9 * (self.cyl.r + self.cyl.half);
        if dist <= self.margin && at.distance(self.closest) > tol && !self.pts.is_full() {
            self.pts.push((feature, at - normal * (0.5 * dist), normal, dist));
        }
    }

    /// The other shape's point `q` (a sphere of radius `r` about it) against the cylinder.
    fn against_cylinder(&mut self, feature: usize, q: DVec3, r: f64) {
        let (out, dist) = point_cylinder(self.cyl, q);
        self.add(feature, q - out * dist, -out, dist - r);
    }

    /// The rim points from the side facing the other shape, each at the signed distance and
    /// normal `from_other` gives.
    fn rim_against(&mut self, from_other: impl Fn(DVec3) -> (DVec3, f64)) {
        for (f, at) in self.cyl.rim(-self.normal) {
            let (normal, dist) = from_other(at);
            self.add(f, at, normal, dist);
        }
    }

    /// The rim points against the polytope and its vertices (features from 19) against the
    /// cylinder. A point's distance from a convex shape is at least its separation along the
    /// pair's normal, so a point whose separation exceeds the margin is passed by without its
    /// distance (a hull of thousands of faces pays only for the points near the contact).
    fn polytope(&mut self, p: &impl Polytope) {
        let (n, margin) = (self.normal, self.margin);
        let top = p.support(n);
        self.rim_against(|at| if n.dot(at) - top > margin { (n, f64::INFINITY) } else { point_polytope(p, at) });
        let lowest = self.cyl.lowest_along(n);
        for i in 0..p.nvert() {
            let v = p.vert(i);
            if lowest - n.dot(v) <= margin {
                self.against_cylinder(19 + i, v, 0.0);
            }
        }
    }

    fn reduce(self) -> Manifold {
        reduce(&self.pts, self.normal)
    }
}
