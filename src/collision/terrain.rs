//! Contacts with a height field: each triangle under the other shape's bounding square is the
//! top of a prism down to the field's base (MuJoCo's decomposition), collided as a convex
//! polytope; points repeated by neighbouring prisms (along a shared edge) are kept once, and more
//! than [`MAX_MANIFOLD`] are reduced as a face's are.

use arrayvec::ArrayVec;
use glam::{DMat3, DVec3};

use super::cylinder;
use super::convex::{point_polytope, polytopes, reduce, Manifold, Point, PosedBox, PosedHull, Segment, MAX_MANIFOLD};
use super::prism::Prism;
use super::data::{Kept, Scratch};
use super::ellipsoid::{half_width, with_polytope};
use super::shapes::Shape;
use crate::geometry::HField;

/// Most points gathered over the prisms before reduction.
const MAX_GATHER: usize = 64;

/// Contacts of `other` (within `margin`) with the height field `h` at pose (`p`, `rot`); normals
/// point from the field toward `other`.
pub(super) fn hfield_contacts(h: &HField, p: DVec3, rot: DMat3, other: Shape, margin: f64, scale: f64, epa: &mut Scratch) -> Manifold {
    let up = rot.col(2);
    // the shape's centre and its half-extents along the field's x and y
    let (x, y) = (rot.col(0), rot.col(1));
    let (centre, half) = match other {
        Shape::Sphere { c, r } => (c, [r, r]),
        Shape::Segment { a, b, r } => ((a + b) * 0.5, [0.5 * (b - a).dot(x).abs() + r, 0.5 * (b - a).dot(y).abs() + r]),
        Shape::Box { c, rot: br, half } => (c, [(br.transpose() * x).abs().dot(half), (br.transpose() * y).abs().dot(half)]),
        Shape::Hull { c, rot: hr, hull } => {
            let reach = |d: DVec3| 0.5 * (hull.support(hr.transpose() * d).1 + hull.support(hr.transpose() * -d).1);
            let mid = |d: DVec3| 0.5 * (hull.support(hr.transpose() * d).1 - hull.support(hr.transpose() * -d).1);
            (c + x * mid(x) + y * mid(y), [reach(x), reach(y)])
        }
        Shape::Ellipsoid { c, rot: er, radii } => (c, [half_width(er, radii, x), half_width(er, radii, y)]),
        Shape::Cylinder(cyl) => (cyl.c, [cyl.c.dot(x) - cyl.lowest_along(x), cyl.c.dot(y) - cyl.lowest_along(y)]),
        Shape::Plane { .. } | Shape::HField { .. } => return Manifold::new(),
    };
    let lowest = lowest_along(other, up);
    let local = rot.transpose() * (centre - p);
    // a cell whose highest corner lies below the shape's lowest point by more than the margin
    // cannot touch it
    let above = lowest - p.dot(up) - margin;
    let (rows, cols) = h.cells_under(local.x, local.y, [half[0] + margin, half[1] + margin]);
    let tol = 1e-9 * scale;
    let mut pts: ArrayVec<Point, MAX_GATHER> = ArrayVec::new();
    for row in rows {
        for col in cols.clone() {
            let top = [(row, col), (row, col + 1), (row + 1, col), (row + 1, col + 1)].map(|(r, c)| h.data[r * h.ncol + c]).into_iter().fold(0.0, f64::max);
            if top * h.size[2] < above {
                continue;
            }
            for (t, tri) in h.cell_triangles(row, col).into_iter().enumerate() {
                let top = tri.map(|v| p + rot * v);
                // the triangle's plane alone separates most prisms from a shape above them
                let n = (top[1] - top[0]).cross(top[2] - top[0]).normalize_or(up);
                if lowest_along(other, n) - n.dot(top[0]) > margin {
                    continue;
                }
                let prism = Prism::new(top, p, up, h.size[3]);
                let m = prism_contacts(&prism, other, margin, epa);
                let id = ((row * h.ncol + col) * 2 + t).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                for &(f, at, n, d) in m.iter() {
                    let repeat = pts.iter().any(|q: &Point| q.1.distance(at) <= tol && q.2.dot(n) > 1.0 - 1e-9);
                    if !repeat && !pts.is_full() {
                        // the low 53 bits: a feature stays exact as a float64 (a full state's history)
                        pts.push((f.wrapping_add(id) & ((1 << 53) - 1), at, n, d));
                    }
                }
            }
        }
    }
    if pts.len() <= MAX_MANIFOLD {
        return reduce(&pts, up);
    }
    let n = pts.iter().map(|q| q.2).sum::<DVec3>().normalize_or(up);
    reduce(&pts, n)
}

/// The least projection of a point of `shape` on unit `n`.
fn lowest_along(shape: Shape, n: DVec3) -> f64 {
    match shape {
        Shape::Sphere { c, r } => c.dot(n) - r,
        Shape::Segment { a, b, r } => a.dot(n).min(b.dot(n)) - r,
        Shape::Box { c, rot, half } => c.dot(n) - (rot.transpose() * n).abs().dot(half),
        Shape::Hull { c, rot, hull } => c.dot(n) - hull.support(rot.transpose() * -n).1,
        Shape::Ellipsoid { c, rot, radii } => c.dot(n) - half_width(rot, radii, n),
        Shape::Cylinder(cyl) => cyl.lowest_along(n),
        Shape::Plane { .. } | Shape::HField { .. } => f64::NEG_INFINITY,
    }
}

/// Contacts of `other` with one prism, normals from the prism toward `other`.
fn prism_contacts(prism: &Prism, other: Shape, margin: f64, epa: &mut Scratch) -> Manifold {
    let scale = prism.v[0].distance(prism.v[3]).max(prism.v[0].distance(prism.v[1]));
    let flip = |mut m: Manifold| {
        for q in m.iter_mut() {
            q.2 = -q.2;
        }
        m
    };
    match other {
        Shape::Sphere { c, r } => {
            let (n, d) = point_polytope(prism, c);
            let mut m = Manifold::new();
            if d - r <= margin {
                m.push((0, c - n * (r + 0.5 * (d - r)), n, d - r));
            }
            m
        }
        Shape::Segment { a, b, r } => {
            // normals from the segment to the prism: the capsule's surface is r nearer it
            let mut m = polytopes(prism, &Segment { a, b }, margin + r, scale, None, &mut Kept::default());
            for q in m.iter_mut() {
                q.1 += q.2 * (0.5 * r);
                q.3 -= r;
            }
            flip(m)
        }
        Shape::Box { c, rot, half } => polytopes(&PosedBox { c, rot, half }, prism, margin, scale, None, &mut Kept::default()),
        Shape::Hull { c, rot, hull } => polytopes(&PosedHull { hull, c, rot }, prism, margin, scale, None, &mut Kept::default()),
        Shape::Ellipsoid { .. } => with_polytope(other, prism, margin, epa).into_iter().map(|(at, n, d)| (0, at, n, d)).collect(),
        Shape::Cylinder(cyl) => cylinder::with_prism(&cyl, prism, margin, epa),
        Shape::Plane { .. } | Shape::HField { .. } => Manifold::new(),
    }
}
