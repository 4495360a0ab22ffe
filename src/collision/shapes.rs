//! Each geom as a shape in world ([`Shape`]), and closest points and contacts of primitive pairs
//! in world coordinates: box–box by separating axes, a point or segment against a box, spheres,
//! segments.

use glam::{DMat3, DVec3};

use super::data::{CollisionData, Kept, Separation};
use crate::geometry::{HField, Hull};
use crate::model::{GeomType, Model};

/// A geom posed in world, as the narrowphase tests it.
#[derive(Clone, Copy)]
pub(super) enum Shape<'a> {
    Plane { p: DVec3, n: DVec3 },
    Sphere { c: DVec3, r: f64 },
    Segment { a: DVec3, b: DVec3, r: f64 },
    Cylinder(Cyl),
    Box { c: DVec3, rot: DMat3, half: DVec3 },
    Ellipsoid { c: DVec3, rot: DMat3, radii: DVec3 },
    Hull { c: DVec3, rot: DMat3, hull: &'a Hull },
    HField { p: DVec3, rot: DMat3, field: &'a HField },
}

impl Shape<'_> {
    /// A box that holds the shape (centre, rotation, half extents); None for a plane or height
    /// field.
    pub(super) fn oriented_box(&self) -> Option<(DVec3, DMat3, DVec3)> {
        let along = |axis: DVec3| {
            let (u, v) = axis.any_orthonormal_pair();
            DMat3::from_cols(u, v, axis)
        };
        match *self {
            Shape::Sphere { c, r } => Some((c, DMat3::IDENTITY, DVec3::splat(r))),
            Shape::Segment { a, b, r } => {
                let half = 0.5 * a.distance(b);
                let axis = (b - a).try_normalize().unwrap_or(DVec3::Z);
                Some(((a + b) * 0.5, along(axis), DVec3::new(r, r, half + r)))
            }
            Shape::Cylinder(Cyl { c, axis, half, r }) => Some((c, along(axis), DVec3::new(r, r, half))),
            Shape::Box { c, rot, half } => Some((c, rot, half)),
            Shape::Ellipsoid { c, rot, radii } => Some((c, rot, radii)),
            Shape::Hull { c, rot, hull } => Some((c + rot * hull.bounds.0, rot, hull.bounds.1)),
            Shape::Plane { .. } | Shape::HField { .. } => None,
        }
    }
}

/// Whether two shapes' boxes ([`Shape::oriented_box`]) lie farther apart than `margin`: the
/// midphase of a pair whose test starts with GJK on a hull (MuJoCo's oriented-box test), which
/// spares the support walks of limbs near each other but apart. Where they do, `parted` gets a
/// lower bound on the distance between the shapes
/// ([`boxes_separation`](super::broadphase::boxes_separation)): it spares the pair's next tests
/// while the joints' travel has not taken it up.
pub(super) fn boxes_part(s1: &Shape, s2: &Shape, margin: f64, parted: &mut f64) -> bool {
    match (s1.oriented_box(), s2.oriented_box()) {
        (Some(a), Some(b)) if super::broadphase::boxes_apart(a, b, margin) => {
            *parted = super::broadphase::boxes_separation(a, b);
            true
        }
        _ => false,
    }
}

/// A posed cylinder: centre, unit axis, half-length, radius (its geometry in `cylinder.rs`).
#[derive(Clone, Copy)]
pub(super) struct Cyl {
    pub(super) c: DVec3,
    pub(super) axis: DVec3,
    pub(super) half: f64,
    pub(super) r: f64,
}

/// Geom g as a shape at its pose in `cd` (a mesh or height-field geom always has its asset:
/// the compiler resolves them; the fallbacks only keep this total).
pub(super) fn shape<'a>(m: &'a Model, cd: &CollisionData, g: usize) -> Shape<'a> {
    let (p, r, s) = (cd.geom_xpos[g], cd.geom_xmat[g], m.geom_size[g]);
    match m.geom_type[g] {
        GeomType::Plane => Shape::Plane { p, n: r.col(2) },
        GeomType::Sphere => Shape::Sphere { c: p, r: s[0] },
        GeomType::Ellipsoid => Shape::Ellipsoid { c: p, rot: r, radii: DVec3::from_array(s) },
        GeomType::Capsule => {
            let h = r.col(2) * s[1];
            Shape::Segment { a: p - h, b: p + h, r: s[0] }
        }
        GeomType::Cylinder => Shape::Cylinder(Cyl { c: p, axis: r.col(2), half: s[1], r: s[0] }),
        GeomType::Box => Shape::Box { c: p, rot: r, half: DVec3::from_array(s) },
        GeomType::Mesh => match m.geom_mesh[g] {
            Some(k) => Shape::Hull { c: p, rot: r, hull: &m.meshes[k].hull },
            None => Shape::Box { c: p, rot: r, half: DVec3::from_array(s) },
        },
        GeomType::Hfield => match m.geom_hfield[g] {
            Some(k) => Shape::HField { p, rot: r, field: &m.hfields[k] },
            None => Shape::Plane { p, n: r.col(2) },
        },
    }
}


/// Features of box–box face contacts start here (edge contacts are 32–40).
const FACE_FEATURES: usize = 64;
/// |cos| of the angle between an edge axis and the best face axis above which [`box_box`] takes
/// the face (3°).
const EDGE_ON_FACE: f64 = 0.99863;

/// Box–box contacts by the separating-axis test (Gottschalk, Lin & Manocha, *OBBTree*, 1996), as
/// ODE's `dBoxBox`: of the 15 candidate axes, the one of least penetration (or widest gap) is the
/// normal, a face axis preferred unless an edge axis is clearly better and not within 3° of it.
/// Face axis: the other box's face most opposed to it is clipped against the reference face's
/// rectangle (Sutherland–Hodgman), up to 8 points. Edge axis: the closest points of the two
/// supporting edges, one point. Returns (feature, point, normal from box 2 to box 1, signed
/// distance) for points within `margin`.
#[allow(clippy::type_complexity)]
pub(super) fn box_box((c1, r1, h1): (DVec3, DMat3, DVec3), (c2, r2, h2): (DVec3, DMat3, DVec3), margin: f64, kept: &mut Kept) -> ([(usize, DVec3, DVec3, f64); 8], usize) {
    let mut out = [(0, DVec3::ZERO, DVec3::ZERO, 0.0); 8];
    let d = c1 - c2;
    let radius = |axis: DVec3, rot: DMat3, half: DVec3| (0..3).map(|k| half[k] * axis.dot(rot.col(k)).abs()).sum::<f64>();
    let gap = |axis: DVec3| axis.dot(d).abs() - radius(axis, r1, h1) - radius(axis, r2, h2);
    let scale = h1.max_element() + h2.max_element();
    // a face axis that held the boxes apart last time, still farther than the margin by the
    // tolerance of the best face's choice: the best face below is at least as far apart
    if let Separation::Face(of_2, k @ 0..3) = kept.sep
        && gap(if of_2 { r2 } else { r1 }.col(k as usize)) > margin + 1e-9 * scale
    {
        kept.skips += 1;
        return (out, 0);
    }
    // best face axis: (gap, reference box is box 1, axis index); a later axis must be better by
    // more than round-off, so that faces tied (equal boxes stacked) keep one reference box and
    // the contacts their features
    let mut face = (f64::NEG_INFINITY, false, 0);
    for (on1, rot) in [(true, r1), (false, r2)] {
        for k in 0..3 {
            let s = gap(rot.col(k));
            if s > face.0 + 1e-9 * scale {
                face = (s, on1, k);
            }
        }
    }
    let mut edge = (f64::NEG_INFINITY, 0, 0, DVec3::ZERO);
    for i in 0..3 {
        for j in 0..3 {
            let axis = r1.col(i).cross(r2.col(j));
            let len = axis.length();
            if len > 1e-6 {
                let s = gap(axis / len);
                if s > edge.0 {
                    edge = (s, i, j, axis / len);
                }
            }
        }
    }
    // an edge axis within a few degrees of the face axis is an edge lying on that face (a thin
    // box's edge across a cube's face): the face's clipping gives the segment's two ends, where
    // the edges' closest points give one, about which the box would rock
    let on_face = |axis: DVec3| axis.dot(if face.1 { r1.col(face.2) } else { r2.col(face.2) }).abs() > EDGE_ON_FACE;
    kept.sep = if face.0 > margin { Separation::Face(!face.1, face.2 as u32) } else { Separation::Unknown };
    if edge.0 > face.0 + 0.05 * face.0.abs() + 1e-9 * scale && !on_face(edge.3) {
        if edge.0 > margin {
            return (out, 0);
        }
        let (_, i, j, axis) = edge;
        out[0] = edge_contact((c1, r1, h1), (c2, r2, h2), i, j, axis);
        return (out, 1);
    }
    if face.0 > margin {
        return (out, 0);
    }
    // reference box R (whose face gives the normal) and other box O
    let (_, ref1, a) = face;
    let ((cr, rr, hr), (co, ro, ho)) = if ref1 { ((c1, r1, h1), (c2, r2, h2)) } else { ((c2, r2, h2), (c1, r1, h1)) };
    let toward = co - cr;
    let nf = if rr.col(a).dot(toward) >= 0.0 { rr.col(a) } else { -rr.col(a) };
    let face_centre = cr + nf * hr[a];
    // incident face of O: the one most opposed to nf, corners in cyclic order
    let k = (0..3).max_by(|&x, &y| nf.dot(ro.col(x)).abs().total_cmp(&nf.dot(ro.col(y)).abs())).unwrap();
    let ni = if ro.col(k).dot(nf) > 0.0 { -ro.col(k) } else { ro.col(k) };
    let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
    let (u, v) = (ro.col(k1) * ho[k1], ro.col(k2) * ho[k2]);
    let centre = co + ni * ho[k];
    let corners = [centre + u + v, centre - u + v, centre - u - v, centre + u - v];
    let (poly, len) = clip_to_face(&corners, (cr, rr, hr), a, scale);
    if len == 0 {
        return (out, 0);
    }
    // normal from box 2 to box 1: nf points from R to O
    let n = if ref1 { -nf } else { nf };
    let mut count = 0;
    // clipping through a vertex within round-off yields it twice, and a point this close to an
    // incident corner is that corner
    let tol = 1e-9 * scale;
    for &(p, id, _) in &poly[..len] {
        let depth = nf.dot(p - face_centre);
        let id = corners.iter().position(|c| c.distance(p) <= tol).unwrap_or(id);
        let at = p - nf * (0.5 * depth);
        let repeat = out[..count].iter().any(|o| o.1.distance(at) <= tol);
        if depth <= margin && !repeat {
            out[count] = (FACE_FEATURES + 64 * ref1 as usize + id, at, n, depth);
            count += 1;
        }
    }
    (out, count)
}

/// A box in world: centre, axes (columns), half-sizes.
type Cuboid = (DVec3, DMat3, DVec3);

/// [`box_box`]'s edge–edge contact on the axis r1ᵢ × r2ⱼ (unit `axis`): the closest points of the
/// two boxes' edges along it nearest each other, as (feature, point, normal from box 2 to box 1,
/// signed distance).
fn edge_contact((c1, r1, h1): Cuboid, (c2, r2, h2): Cuboid, i: usize, j: usize, axis: DVec3) -> (usize, DVec3, DVec3, f64) {
    let n = if axis.dot(c1 - c2) >= 0.0 { axis } else { -axis };
    // the edge of each box nearest the other
    let sgn = |x: f64| if x >= 0.0 { 1.0 } else { -1.0 };
    let mut p1 = c1;
    let mut p2 = c2;
    for k in 0..3 {
        if k != i {
            p1 -= r1.col(k) * (h1[k] * sgn(n.dot(r1.col(k))));
        }
        if k != j {
            p2 += r2.col(k) * (h2[k] * sgn(n.dot(r2.col(k))));
        }
    }
    let (e1, e2) = (r1.col(i) * h1[i], r2.col(j) * h2[j]);
    let (q1, q2) = closest_segments(p1 - e1, p1 + e1, p2 - e2, p2 + e2);
    (32 + 3 * i + j, (q1 + q2) * 0.5, n, n.dot(q1 - q2))
}

/// [`box_box`]'s incident face (`corners`, in cyclic order) clipped by the four side planes of
/// the reference box's face on axis `a` (Sutherland–Hodgman): the polygon's vertices with their
/// identities and the labels of the edges leaving them, and how many.
fn clip_to_face(corners: &[DVec3; 4], (cr, rr, hr): Cuboid, a: usize, scale: f64) -> ([(DVec3, usize, usize); 8], usize) {
    // each vertex with its identity and the label of the edge leaving it: an incident corner is
    // 0–3 and its edge to the next corner 0–3; a clip on reference plane pl makes the vertex
    // 8 + 8 pl + (the label of the edge it cut) and the edge along the plane 4 + pl. Identities
    // so made persist while the boxes shift by round-off, and so do the rows' (warm start,
    // friction tangents)
    let mut poly = [(DVec3::ZERO, 0usize, 0usize); 8];
    let mut len = 4;
    for (c, p) in corners.iter().enumerate() {
        poly[c] = (*p, c, c);
    }
    // clip by the reference face's four side planes: (p − c_R)·e ≤ h, a vertex within round-off
    // of a plane counting as on it (equal faces stacked put the incident corners on the planes:
    // an edge along a plane cut by round-off would give a point anywhere along it, another each
    // step)
    let on = 1e-9 * scale;
    let (a1, a2) = ((a + 1) % 3, (a + 2) % 3);
    for (pl, (e, h)) in [(rr.col(a1), hr[a1]), (-rr.col(a1), hr[a1]), (rr.col(a2), hr[a2]), (-rr.col(a2), hr[a2])].into_iter().enumerate() {
        let mut next = [(DVec3::ZERO, 0usize, 0usize); 8];
        let mut n_next = 0;
        for idx in 0..len {
            let ((p, id_p, edge), (q, _, _)) = (poly[idx], poly[(idx + 1) % len]);
            let (sp, sq) = ((p - cr).dot(e) - h, (q - cr).dot(e) - h);
            if sp <= on && n_next < 8 {
                // kept; if its edge leaves the face, the rest of it runs along this plane
                next[n_next] = (p, id_p, if sq > on { 4 + pl } else { edge });
                n_next += 1;
            }
            if ((sp < -on && sq > on) || (sp > on && sq < -on)) && n_next < 8 {
                let cut = p + (q - p) * (sp / (sp - sq));
                // entering the face: the cut point's edge is the rest of p's; leaving it: the plane's
                next[n_next] = (cut, 8 + 8 * pl + edge, if sp > 0.0 { edge } else { 4 + pl });
                n_next += 1;
            }
        }
        poly = next;
        len = n_next;
        if len == 0 {
            break;
        }
    }
    (poly, len)
}

/// Signed distance of point `p` from a box and the unit normal pointing from the box toward `p`.
/// Inside (or on) the box it leaves through the face of least penetration; faces tied within
/// round-off (a corner resting exactly on an edge) are decided by `hint`, a world direction from
/// the box toward whatever `p` belongs to.
pub(super) fn point_box(p: DVec3, c: DVec3, rot: DMat3, half: DVec3, hint: DVec3) -> (DVec3, f64) {
    let local = rot.transpose() * (p - c);
    let q = local.abs() - half;
    let tol = 1e-9 * half.max_element();
    if q.max_element() > tol {
        let closest = local.clamp(-half, half);
        let d = local - closest;
        let len = d.length();
        return (rot * (d / len), len);
    }
    let h = rot.transpose() * hint;
    let top = q.max_element();
    let mut axis = 0;
    let mut best = f64::NEG_INFINITY;
    for k in 0..3 {
        let score = h[k].abs() / half[k];
        if q[k] >= top - tol && score > best {
            best = score;
            axis = k;
        }
    }
    let mut n = DVec3::ZERO;
    n[axis] = if local[axis] >= 0.0 { 1.0 } else { -1.0 };
    (rot * n, q[axis].min(0.0))
}

/// Points of segment [a, b] to test against a box as sphere centres: both ends and the segment
/// point nearest the box (alternating projections between segment and box).
pub(super) fn segment_box_points(a: DVec3, b: DVec3, c: DVec3, rot: DMat3, half: DVec3) -> [DVec3; 3] {
    let mut p = closest_on_segment(a, b, c);
    for _ in 0..8 {
        let local = rot.transpose() * (p - c);
        let on_box = c + rot * local.clamp(-half, half);
        p = closest_on_segment(a, b, on_box);
    }
    [a, b, p]
}

/// Contact between two spheres: (point, normal from 2 to 1, signed distance).
pub(super) fn spheres(c1: DVec3, r1: f64, c2: DVec3, r2: f64) -> (DVec3, DVec3, f64) {
    let d = c1 - c2;
    let len = d.length();
    let n = if len > 1e-12 { d / len } else { DVec3::Z };
    let dist = len - r1 - r2;
    (c2 + n * (r2 + 0.5 * dist), n, dist)
}

pub(super) fn closest_on_segment(a: DVec3, b: DVec3, p: DVec3) -> DVec3 {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 < 1e-24 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
}

/// Closest points between segments [a1, b1] and [a2, b2] (Ericson, *Real-Time Collision
/// Detection*, 2005, §5.1.9).
pub(super) fn closest_segments(a1: DVec3, b1: DVec3, a2: DVec3, b2: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (b1 - a1, b2 - a2, a1 - a2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (s, t);
    if a <= 1e-24 && e <= 1e-24 {
        return (a1, a2);
    }
    if a <= 1e-24 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= 1e-24 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > 1e-24 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    (a1 + d1 * s, a2 + d2 * t)
}

#[cfg(test)]
mod tests {
    use super::{box_box, Kept};
    use glam::{DMat3, DVec3};

    /// Equal boxes stacked face to face touch at the four corners, whatever round-off turns or
    /// shifts them, with the same features every time (the rows' identities across steps).
    #[test]
    fn equal_stacked_boxes_touch_at_their_four_corners() {
        let h = DVec3::splat(0.1);
        let mut first: Option<Vec<usize>> = None;
        for k in 0..200 {
            // rotations by a and back: the identity up to round-off, different each time
            let a = 0.37 * k as f64;
            let top = DMat3::from_rotation_z(a) * DMat3::from_rotation_y(0.5 * a) * DMat3::from_rotation_y(-0.5 * a) * DMat3::from_rotation_z(-a);
            let bottom = DMat3::from_rotation_x(a) * DMat3::from_rotation_x(-a);
            let eps = 1e-16 * (k as f64 - 100.0);
            let (pts, n) = box_box((DVec3::new(eps, -eps, 0.2 + 1e-12), top, h), (DVec3::new(0.0, 7.0 * eps, 0.0), bottom, h), 1e-3, &mut Kept::default());
            assert_eq!(n, 4, "round-off {eps}: {:?}", &pts[..n]);
            for p in &pts[..n] {
                assert!((p.1.x.abs() - 0.1).abs() < 1e-9 && (p.1.y.abs() - 0.1).abs() < 1e-9, "not a corner: {:?}", p.1);
            }
            let mut features: Vec<usize> = pts[..n].iter().map(|p| p.0).collect();
            features.sort_unstable();
            match &first {
                Some(f) => assert_eq!(&features, f, "round-off {eps}"),
                None => first = Some(features),
            }
        }
    }

    /// A thin bar lying across a cube's top face along one edge (turned 45° about that edge, so
    /// that its edge, not a face, touches), tilted within the face by up to 2° with one end
    /// lifted by up to 0.5 mm: an edge axis then beats the face axis by round-off or by the lift,
    /// yet the contact is the edge's stretch over the face, two points at its ends within the
    /// margin (one point would be a pivot the cube rocks about, as Playground's Aero hand did).
    #[test]
    fn a_bar_edge_across_a_face_touches_at_both_ends() {
        let (cube, bar) = (DVec3::splat(0.025), DVec3::new(0.007, 0.042, 0.013));
        for k in 0..40 {
            let (turn, lift) = ((k as f64 / 40.0 - 0.5) * 0.07, (k % 5) as f64 * 1e-4);
            // the bar's x and z faces turned 45° about its length (y): its lowest edge along y
            let rot = DMat3::from_rotation_z(turn) * DMat3::from_rotation_x(lift / 0.05) * DMat3::from_rotation_y(std::f64::consts::FRAC_PI_4);
            let low = (0.007f64.powi(2) + 0.013f64.powi(2)).sqrt() * (std::f64::consts::FRAC_PI_4 - (0.007f64 / 0.013).atan()).cos();
            let (pts, n) = box_box((DVec3::new(0.0, 0.0, 0.025 + low), rot, bar), (DVec3::ZERO, DMat3::IDENTITY, cube), 2e-3, &mut Kept::default());
            assert_eq!(n, 2, "turn {turn}, lift {lift}: {:?}", &pts[..n]);
            let ys: Vec<f64> = pts[..n].iter().map(|p| p.1.y).collect();
            assert!(ys.iter().any(|&y| y > 0.02) && ys.iter().any(|&y| y < -0.02), "turn {turn}, lift {lift}: {:?}", &pts[..n]);
        }
    }
}
