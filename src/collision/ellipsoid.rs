//! Contacts of ellipsoids: against a plane in closed form (the deepest point along its normal),
//! against every other convex shape (sphere, capsule, box, cylinder, hull, ellipsoid, a height field's
//! prism) by GJK for the distance of shapes apart and EPA for the depth of shapes that overlap
//! (parry's implementations of Gilbert, Johnson & Keerthi 1988 and van den Bergen 2001), each
//! shape given by its support function h in world coordinates. Their normal is good to the square
//! root of their tolerance only (a curved surface), so it is refined by Newton's method on the
//! unit sphere: the signed distance is the largest separation −h₁(−n) − h₂(n) over unit normals n
//! (from shape 2 to shape 1), whose gradient is s₁(−n) − s₂(n) (the support points) and whose
//! Hessian comes from each support function's (the surface's radii of curvature). One point per
//! pair: an ellipsoid is strictly convex, so its contact with a convex shape is a point, placed at
//! the ellipsoid's support point moved half the distance (as MuJoCo collides ellipsoids: by their
//! support functions, one point). A cylinder's closest point with any shape but a plane comes
//! from here too (`cylinder.rs` adds its rim points).

use std::cell::Cell;

use glam::{DMat3, DVec3};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::shape::SupportMap;

use super::convex::Polytope;
use super::data::{Scratch, Separation};
use super::shapes::{Cyl, Shape};

/// (point midway between the surfaces, unit normal from shape 2 to shape 1, signed distance).
pub(super) type Touch = (DVec3, DVec3, f64);

/// The point of an ellipsoid of semi-axes `radii` (its own frame) farthest along `d`:
/// S² d / |S d|, S = diag(radii).
fn ellipsoid_support(radii: DVec3, d: DVec3) -> DVec3 {
    let sd = radii * d;
    let len = sd.length();
    if len > 0.0 { radii * sd / len } else { DVec3::ZERO }
}

/// The half-width of the ellipsoid (`rot`, `radii`) along unit `n`: |S Rᵀ n|.
pub(super) fn half_width(rot: DMat3, radii: DVec3, n: DVec3) -> f64 {
    (radii * (rot.transpose() * n)).length()
}

/// Contact of the ellipsoid (`c`, `rot`, `radii`) with the plane through `p` of unit normal `n`.
pub(super) fn on_plane(c: DVec3, rot: DMat3, radii: DVec3, p: DVec3, n: DVec3) -> Touch {
    let deepest = c + rot * ellipsoid_support(radii, rot.transpose() * -n);
    let d = (deepest - p).dot(n);
    (deepest - n * (0.5 * d), n, d)
}

/// A convex shape by its support function: the point farthest along a direction, and how that
/// point moves as the (unit) direction turns.
trait Convex {
    fn support(&self, d: DVec3) -> DVec3;
    /// [`Convex::support`], a hull's climbing from the vertex in `last` (updated; `u32::MAX`:
    /// none yet), for GJK's and EPA's runs of nearby directions.
    fn support_near(&self, d: DVec3, _last: &Cell<u32>) -> DVec3 {
        self.support(d)
    }
    /// ∂s/∂u at unit u (symmetric; zero on flat faces, edges and corners).
    fn turn(&self, u: DVec3) -> DMat3;
    fn centre(&self) -> DVec3;
    /// Where near unit `u` the support point jumps from one vertex to another.
    fn kinks(&self, _: DVec3) -> [Option<Kink>; 3] {
        [None; 3]
    }
}

/// A kink of a support function near a direction.
#[derive(Clone, Copy)]
enum Kink {
    /// The directions normal to this unit axis (a capsule's core, a box's edge).
    Ridge(DVec3),
    /// This one direction (a box's face normal).
    Face(DVec3),
}

impl Kink {
    fn flip(self) -> Kink {
        match self {
            Kink::Face(f) => Kink::Face(-f),
            ridge => ridge,
        }
    }
}

/// How near a direction must be to a kink (in its cosines) to be moved onto it.
const KINK: f64 = 1e-3;

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

impl Convex for Shape<'_> {
    fn support(&self, d: DVec3) -> DVec3 {
        match *self {
            Shape::Sphere { c, r } => c + d.normalize_or_zero() * r,
            Shape::Segment { a, b, r } => (if a.dot(d) >= b.dot(d) { a } else { b }) + d.normalize_or_zero() * r,
            Shape::Box { c, rot, half } => c + rot * (half * (rot.transpose() * d).signum()),
            Shape::Hull { c, rot, hull } => c + rot * hull.vert[hull.support(rot.transpose() * d).0],
            Shape::Ellipsoid { c, rot, radii } => c + rot * ellipsoid_support(radii, rot.transpose() * d),
            Shape::Cylinder(Cyl { c, axis, half, r }) => {
                let along = axis.dot(d);
                let end = if along >= 0.0 { half } else { -half };
                // w projected twice: once leaves round-off along the axis as large as a w of a
                // nearly axial d; along the axis to round-off, the cap's centre
                let w = d - axis * along;
                let w = w - axis * axis.dot(w);
                let rim = if w.length_squared() > 1e-28 * d.length_squared() { w.normalize() * r } else { DVec3::ZERO };
                c + axis * end + rim
            }
            Shape::Plane { p, .. } | Shape::HField { p, .. } => p,
        }
    }

    fn support_near(&self, d: DVec3, last: &Cell<u32>) -> DVec3 {
        let Shape::Hull { c, rot, hull } = *self else { return self.support(d) };
        let (i, _) = hull.support_from(rot.transpose() * d, (last.get() != u32::MAX).then_some(last.get() as usize));
        last.set(i as u32);
        c + rot * hull.vert[i]
    }

    fn turn(&self, u: DVec3) -> DMat3 {
        match *self {
            // the rounding of radius r: r (I − u uᵀ)
            Shape::Sphere { r, .. } | Shape::Segment { r, .. } => (DMat3::IDENTITY - outer(u, u)) * r,
            // s = R S² u' / |S u'|, u' = Rᵀ u
            Shape::Ellipsoid { rot, radii, .. } => {
                let (ul, s2) = (rot.transpose() * u, radii * radii);
                let len = (radii * ul).length();
                rot * (DMat3::from_diagonal(s2) / len - outer(s2 * ul, s2 * ul) / (len * len * len)) * rot.transpose()
            }
            // the rim of radius r: w = P u (P = I − a aᵀ), s = r w / |w|, ∂s/∂u = r (P − ŵ ŵᵀ) / |w|
            Shape::Cylinder(Cyl { axis, r, .. }) => {
                let w = u - axis * axis.dot(u);
                let rho = w.length();
                if rho < KINK {
                    return DMat3::ZERO;
                }
                let wh = w / rho;
                (DMat3::IDENTITY - outer(axis, axis) - outer(wh, wh)) * (r / rho)
            }
            _ => DMat3::ZERO,
        }
    }

    fn kinks(&self, u: DVec3) -> [Option<Kink>; 3] {
        match *self {
            Shape::Segment { a, b, .. } => [(b - a).try_normalize().filter(|e| e.dot(u).abs() < KINK).map(Kink::Ridge), None, None],
            // the side (the support jumps from cap to cap) and the nearer cap's face (it jumps
            // around the rim), always tried: GJK's normal may lie farther from a face than
            // `KINK`, and either is kept only if it separates more
            Shape::Cylinder(Cyl { axis, .. }) => [Some(Kink::Ridge(axis)), Some(Kink::Face(axis * axis.dot(u).signum())), None],
            Shape::Box { rot, .. } => {
                // an edge along each axis u is nearly normal to; a face where two are
                let ul = rot.transpose() * u;
                let flat = [0, 1, 2].map(|k| ul[k].abs() < KINK);
                let face = (flat.iter().filter(|&&f| f).count() == 2).then(|| flat.iter().position(|&f| !f)).flatten();
                let ridge = |k: usize| flat[k].then(|| Kink::Ridge(rot.col(k)));
                match face {
                    Some(k) => [Some(Kink::Face(rot.col(k) * ul[k].signum())), ridge((k + 1) % 3), ridge((k + 2) % 3)],
                    None => [ridge(0), ridge(1), ridge(2)],
                }
            }
            _ => [None; 3],
        }
    }

    fn centre(&self) -> DVec3 {
        match *self {
            Shape::Sphere { c, .. } | Shape::Box { c, .. } | Shape::Hull { c, .. } | Shape::Ellipsoid { c, .. } | Shape::Cylinder(Cyl { c, .. }) => c,
            Shape::Segment { a, b, .. } => (a + b) * 0.5,
            Shape::Plane { p, .. } | Shape::HField { p, .. } => p,
        }
    }
}

/// A polytope as a convex shape (its farthest vertex).
struct Vertices<'a, P: Polytope>(&'a P);

impl<P: Polytope> Convex for Vertices<'_, P> {
    fn support(&self, d: DVec3) -> DVec3 {
        let p = self.0;
        (0..p.nvert()).map(|i| p.vert(i)).fold((f64::NEG_INFINITY, DVec3::ZERO), |b, v| if v.dot(d) > b.0 { (v.dot(d), v) } else { b }).1
    }

    fn turn(&self, _: DVec3) -> DMat3 {
        DMat3::ZERO
    }

    fn centre(&self) -> DVec3 {
        self.0.centre()
    }
}

fn to_parry(v: DVec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn from_parry(v: Vector) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// A convex shape's support function for parry.
struct Parry<'a, C: Convex>(&'a C, Cell<u32>, Frame);

/// How parry reads a shape: its points p as o + (p − o) k (scaled about o).
#[derive(Clone, Copy)]
struct Frame {
    o: DVec3,
    k: f64,
}

impl<C: Convex> SupportMap for Parry<'_, C> {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let Frame { o, k } = self.2;
        let p = self.0.support_near(from_parry(dir), &self.1);
        to_parry(if k == 1.0 { p } else { o + (p - o) * k })
    }
}

/// Contact of shapes 1 and 2 (neither a plane nor a height field; one an ellipsoid or a cylinder)
/// within `margin`, placed at the support point of the shape whose support point is most
/// nearly unique (an ellipsoid's or sphere's always is; a box's is a corner).
pub(super) fn convex(s1: Shape, s2: Shape, margin: f64, epa: &mut Scratch) -> Option<Touch> {
    let rank = |s: &Shape| match s {
        Shape::Ellipsoid { .. } => 4,
        Shape::Sphere { .. } => 3,
        Shape::Segment { .. } => 2,
        Shape::Cylinder(_) => 1,
        _ => 0,
    };
    contact(&s1, &s2, rank(&s1) >= rank(&s2), margin, epa)
}

/// Contact of the ellipsoid or cylinder `e` (shape 1) with the polytope `p` within `margin`.
pub(super) fn with_polytope<P: Polytope>(e: Shape, p: &P, margin: f64, epa: &mut Scratch) -> Option<Touch> {
    contact(&e, &Vertices(p), true, margin, epa)
}

/// Steps of Newton's method after GJK or EPA, at most.
const NEWTON: usize = 4;

/// The contact of shapes 1 and 2 within `margin`, placed at the support point of shape 1
/// (`on_first`) or 2.
fn contact<A: Convex, B: Convex>(a: &A, b: &B, on_first: bool, margin: f64, epa: &mut Scratch) -> Option<Touch> {
    let n = first_normal(a, b, margin, 0.0, epa)?;
    // the separation along n, and the support points
    let along = |n: DVec3| {
        let (s1, s2) = (a.support(-n), b.support(n));
        ((s1 - s2).dot(n), s1, s2)
    };
    // EPA's normal of a touching pair can be arbitrary: the line of the centres may separate more
    let centres = (a.centre() - b.centre()).try_normalize().unwrap_or(n);
    let (first, line) = (along(n), along(centres));
    let (mut n, (mut d, mut s1, mut s2)) = if line.0 > first.0 { (centres, line) } else { (n, first) };
    for _ in 0..NEWTON {
        // maximise d(n) on the unit sphere: gradient s₁ − s₂ (tangential part), Hessian
        // −(H₁ + H₂) − d I there; a step is kept only if it separates more
        let (t1, t2) = n.any_orthonormal_pair();
        let h = a.turn(-n) + b.turn(n);
        let g = s1 - s2;
        let (a11, a12, a22) = (t1.dot(h * t1) + d, t1.dot(h * t2), t2.dot(h * t2) + d);
        let det = a11 * a22 - a12 * a12;
        if !(a11 > 0.0 && det > 0.0) {
            break;
        }
        let (b1, b2) = (t1.dot(g), t2.dot(g));
        let step = t1 * ((b1 * a22 - b2 * a12) / det) + t2 * ((a11 * b2 - a12 * b1) / det);
        let next = (n + step).normalize();
        let (dn, n1, n2) = along(next);
        // (NaN, a degenerate step, ends it too)
        if dn.partial_cmp(&d) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        (n, d, s1, s2) = (next, dn, n1, n2);
    }
    // where a support point jumps (a capsule's side, a box's edge or face) the separation has a
    // kink Newton's steps across cannot climb: the normal is moved onto it, and along a ridge
    // (where it is smooth) Newton's steps go on
    let (ka, kb) = (a.kinks(-n), b.kinks(n));
    for kink in ka.into_iter().flatten().map(Kink::flip).chain(kb.into_iter().flatten()) {
        match kink {
            Kink::Face(f) => {
                let at = along(f);
                if at.0 > d {
                    (n, (d, s1, s2)) = (f, at);
                }
            }
            Kink::Ridge(e) => {
                let on = (n - e * n.dot(e)).normalize();
                let mut at = (on, along(on));
                for _ in 0..NEWTON {
                    let (on, (d0, r1, r2)) = at;
                    let t = e.cross(on);
                    let curve = t.dot((a.turn(-on) + b.turn(on)) * t) + d0;
                    let next = (on + t * (t.dot(r1 - r2) / curve)).normalize();
                    let step = along(next);
                    if !(curve > 0.0 && step.0 > d0) {
                        break;
                    }
                    at = (next, step);
                }
                if at.1.0 > d {
                    (n, (d, s1, s2)) = at;
                }
            }
        }
    }
    let pos = if on_first { s1 - n * (0.5 * d) } else { s2 + n * (0.5 * d) };
    (d <= margin).then_some((pos, n, d))
}

/// GJK's or EPA's normal (unit, from shape 2 to shape 1; neither a plane nor a height field)
/// of shapes 1 and 2 within `margin`, None when farther apart: where a hull pair of many edges
/// looks for its separating axis (`radius` bounds shape 1's points' distance from its centre).
pub(super) fn normal(a: Shape, b: Shape, margin: f64, radius: f64, epa: &mut Scratch) -> Option<DVec3> {
    // shrunk, shape 1's points come at most HINT_SHRINK × radius nearer shape 2
    first_normal(&a, &b, margin + HINT_SHRINK * radius, HINT_SHRINK, epa)
}

/// How much shape 1 is shrunk about its centre for [`normal`]'s GJK: shapes that touch or
/// overlap by less then lie apart, and GJK gives their normal in a few steps where EPA, at
/// parry's absolute tolerance, would spend its hundred iterations on a touching pair of
/// detailed meshes (the hint needs no more: the pair's test finds the exact features).
const HINT_SHRINK: f64 = 1e-3;

/// GJK's normal (from shape 2 to shape 1) of two shapes apart by at most `margin`, else EPA's;
/// the line of the centres if EPA finds none (a degenerate overlap); None when farther apart.
/// A separating axis kept in `epa.kept` (from shape 2 to shape 1) along which the shapes lie
/// farther apart than `margin` settles it without GJK, and GJK leaves its own axis there (none
/// when the shapes overlap). GJK's witnesses are never nearer than the shapes, so the kept axis
/// settles only what GJK would have rejected: the contacts do not depend on it.
fn first_normal<A: Convex, B: Convex>(a: &A, b: &B, margin: f64, shrink: f64, epa: &mut Scratch) -> Option<DVec3> {
    // a diverging world's poses are not finite: no contact (GJK asserts finite supports)
    let o = a.centre();
    if !(a.support(DVec3::X) - b.support(DVec3::Y)).is_finite() {
        epa.kept.sep = Separation::Unknown;
        return None;
    }
    let frame = Frame { o, k: 1.0 - shrink };
    if let Separation::Axis(n) = epa.kept.sep {
        let (sa, sb) = (o + (a.support(-n) - o) * frame.k, b.support(n));
        // round-off of the supports' dot products to spare
        if (sa - sb).dot(n) > margin + AXIS_SPARE * (sa.length() + sb.length()) {
            epa.kept.skips += 1;
            return None;
        }
    }
    let (pa, pb, pose) = (Parry(a, Cell::new(u32::MAX), frame), Parry(b, Cell::new(u32::MAX), Frame { o, k: 1.0 }), Pose::IDENTITY);
    let toward = (b.centre() - a.centre()).try_normalize().unwrap_or(DVec3::X);
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(&pose, &pa, &pb, to_parry(toward)));
    // parry's normals and axes point from shape 1 to shape 2
    let (n1, apart) = match gjk::closest_points(&pose, &pa, &pb, margin, true, &mut simplex) {
        GJKResult::ClosestPoints(p1, p2, n1) => (from_parry(n1), from_parry(p2 - p1).length() > margin),
        GJKResult::NoIntersection(n1) | GJKResult::Proximity(n1) => (from_parry(n1), true),
        GJKResult::Intersection => {
            epa.kept.sep = Separation::Unknown;
            let n1 = epa.epa.closest_points(&pose, &pa, &pb, &simplex).map_or(toward, |(_, _, n1)| from_parry(n1));
            return Some(-n1);
        }
    };
    epa.kept.sep = Separation::Axis(-n1);
    (!apart).then_some(-n1)
}

/// How much farther apart than the margin (relative to the support points' distances from the
/// origin) a kept axis must hold two shapes to settle their test.
const AXIS_SPARE: f64 = 1e-12;
