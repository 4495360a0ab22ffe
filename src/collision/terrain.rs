//! Contacts with a height field: each triangle under the other shape's bounding square is the
//! top of a prism down to the field's base (MuJoCo's decomposition), collided as a convex
//! polytope; points repeated by neighbouring prisms (along a shared edge) are kept once, and more
//! than [`MAX_MANIFOLD`] are reduced as a face's are.

use glam::{DMat3, DVec3};

use super::convex::{point_polytope, polytopes, reduce, Manifold, Point, PosedBox, PosedHull, Prism, Segment, MAX_MANIFOLD};
use super::shapes::Shape;
use crate::geometry::HField;

/// Most points gathered over the prisms before reduction.
const MAX_GATHER: usize = 64;

/// Contacts of `other` (within `margin`) with the height field `h` at pose (`p`, `rot`); normals
/// point from the field toward `other`.
pub(super) fn hfield_contacts(h: &HField, p: DVec3, rot: DMat3, other: Shape, margin: f64, scale: f64) -> Manifold {
    let up = rot.col(2);
    // the shape's bounding radius about its centre and its lowest point along the field's up
    let (centre, r, lowest) = match other {
        Shape::Sphere { c, r } => (c, r, c.dot(up) - r),
        Shape::Segment { a, b, r } => ((a + b) * 0.5, 0.5 * a.distance(b) + r, a.dot(up).min(b.dot(up)) - r),
        Shape::Box { c, rot: br, half } => (c, half.length(), c.dot(up) - (br.transpose() * up).abs().dot(half)),
        Shape::Hull { c, rot: hr, hull } => {
            (c, hull.vert.iter().map(|v| v.length()).fold(0.0, f64::max), c.dot(up) - hull.support(hr.transpose() * -up).1)
        }
        Shape::Plane { .. } | Shape::HField { .. } => return Manifold::EMPTY,
    };
    let local = rot.transpose() * (centre - p);
    // a cell whose highest corner lies below the shape's lowest point by more than the margin
    // cannot touch it
    let above = lowest - p.dot(up) - margin;
    let (rows, cols) = h.cells_under(local.x, local.y, r + margin);
    let tol = 1e-9 * scale;
    let mut pts = [(0usize, DVec3::ZERO, DVec3::Z, 0.0); MAX_GATHER];
    let mut count = 0;
    for row in rows {
        for col in cols.clone() {
            let top = [(row, col), (row, col + 1), (row + 1, col), (row + 1, col + 1)].map(|(r, c)| h.data[r * h.ncol + c]).into_iter().fold(0.0, f64::max);
            if top * h.size[2] < above {
                continue;
            }
            for (t, tri) in h.cell_triangles(row, col).into_iter().enumerate() {
                let top = tri.map(|v| p + rot * v);
                let prism = Prism::new(top, p, up, h.size[3]);
                let m = prism_contacts(&prism, other, margin);
                let id = ((row * h.ncol + col) * 2 + t).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                for &(f, at, n, d) in m.iter() {
                    let repeat = pts[..count].iter().any(|q: &Point| q.1.distance(at) <= tol && q.2.dot(n) > 1.0 - 1e-9);
                    if !repeat && count < MAX_GATHER {
                        pts[count] = (f.wrapping_add(id), at, n, d);
                        count += 1;
                    }
                }
            }
        }
    }
    if count <= MAX_MANIFOLD {
        return reduce(&pts[..count], up);
    }
    let n = pts[..count].iter().map(|q| q.2).sum::<DVec3>().normalize_or(up);
    reduce(&pts[..count], n)
}

/// Contacts of `other` with one prism, normals from the prism toward `other`.
fn prism_contacts(prism: &Prism, other: Shape, margin: f64) -> Manifold {
    let scale = prism.v[0].distance(prism.v[3]).max(prism.v[0].distance(prism.v[1]));
    let flip = |mut m: Manifold| {
        for q in &mut m.points[..m.len] {
            q.2 = -q.2;
        }
        m
    };
    match other {
        Shape::Sphere { c, r } => {
            let (n, d) = point_polytope(prism, c);
            let mut m = Manifold::EMPTY;
            if d - r <= margin {
                m.points[0] = (0, c - n * (r + 0.5 * (d - r)), n, d - r);
                m.len = 1;
            }
            m
        }
        Shape::Segment { a, b, r } => {
            // normals from the segment to the prism: the capsule's surface is r nearer it
            let mut m = polytopes(prism, &Segment { a, b }, margin + r, scale);
            for q in &mut m.points[..m.len] {
                q.1 += q.2 * (0.5 * r);
                q.3 -= r;
            }
            flip(m)
        }
        Shape::Box { c, rot, half } => polytopes(&PosedBox { c, rot, half }, prism, margin, scale),
        Shape::Hull { c, rot, hull } => polytopes(&PosedHull { hull, c, rot }, prism, margin, scale),
        Shape::Plane { .. } | Shape::HField { .. } => Manifold::EMPTY,
    }
}
