//! Contacts of convex polytopes — mesh hulls, boxes and segments (a capsule's core) — by the
//! separating-axis test with Gauss-map pruning of edge pairs, then face clipping (Gregorius,
//! "The Separating Axis Test between Convex Polyhedra", GDC 2013; Ericson 2005, §5.2.1 and
//! §8.3.4 for Sutherland–Hodgman clipping). Face axes are preferred unless an edge axis is
//! clearly better, as in `box_box`. Each point keeps an identity made from the features that
//! made it (an incident vertex, or the incident edge and the reference side plane that cut it),
//! so a resting contact keeps its rows' warm start from step to step. A face touching a face
//! yields at most [`MAX_MANIFOLD`] points spanning the support polygon ([`reduce`]): more only
//! repeat what those rows hold and make the LCP degenerate.

use arrayvec::ArrayVec;
use glam::{DMat3, DVec3};

use super::data::{Kept, Separation};
use super::shapes::closest_segments;
use crate::geometry::Hull;

/// Edge pairs beyond which a hinted pair is collided [`along_normal`] (two hulls of 500 edges).
const HUGE_EDGE_PAIRS: usize = 250_000;

/// Edges of one polytope beyond which a hinted pair is collided [`along_normal`] whatever the
/// other (a detailed mesh against a box: the test would read thousands of its features).
const HUGE_EDGES: usize = 2048;

/// The cosine within which a face's normal counts as near a hinted separating axis (60°: every
/// direction lies within 54.7° of one of a box's faces).
const CONE: f64 = 0.5;

/// Most points a pair of polytopes (or a hull on a plane) contributes.
pub(super) const MAX_MANIFOLD: usize = 8;

/// Edges of the second polytope posed once per test when at most this many are read (more are
/// posed as the test reads them).
const MAX_POSED_EDGES: usize = 256;

/// Largest polygon a clip keeps (an incident face's vertices plus one per reference side).
pub(super) const MAX_POLY: usize = 128;

/// Feature offsets of a polytope pair's points: face contacts with A or B as reference, edge pairs.
const FACE_A: usize = 1 << 40;
const FACE_B: usize = 2 << 40;
const EDGE: usize = 3 << 40;
/// A clipped point's identity: the reference side `k` and the incident vertex its edge starts at.
const CUT: usize = 1 << 20;

/// A point of a manifold: (feature, point midway between the surfaces, unit normal from B to A,
/// signed distance).
pub(super) type Point = (usize, DVec3, DVec3, f64);

/// Up to [`MAX_MANIFOLD`] points.
pub(super) type Manifold = ArrayVec<Point, MAX_MANIFOLD>;

/// A convex polytope posed in world coordinates.
pub(super) trait Polytope {
    fn nvert(&self) -> usize;
    fn vert(&self, i: usize) -> DVec3;
    fn nface(&self) -> usize;
    /// Outward unit normal and offset (normal · x on the face).
    fn plane(&self, f: usize) -> (DVec3, f64);
    fn face_len(&self, f: usize) -> usize;
    /// The face's k-th vertex, counter-clockwise about its normal.
    fn face_vert(&self, f: usize, k: usize) -> usize;
    fn nedge(&self) -> usize;
    /// An edge's ends and the normals of its two faces (None for a segment, all of whose
    /// perpendiculars are normals).
    fn edge(&self, e: usize) -> ([usize; 2], Option<[DVec3; 2]>);
    fn centre(&self) -> DVec3;
    /// `q` in the frame of [`Polytope::local_plane`] (the world's unless overridden).
    fn to_local(&self, q: DVec3) -> DVec3 {
        q
    }
    /// Direction `d` in the frame of [`Polytope::local_plane`].
    fn to_local_dir(&self, d: DVec3) -> DVec3 {
        d
    }
    /// A face's plane in the polytope's own frame: its separation from a point is read there
    /// without posing each plane.
    fn local_plane(&self, f: usize) -> (DVec3, f64) {
        self.plane(f)
    }
    /// Largest projection of a vertex on `d`.
    fn support(&self, d: DVec3) -> f64 {
        (0..self.nvert()).map(|i| self.vert(i).dot(d)).fold(f64::NEG_INFINITY, f64::max)
    }
}

/// A mesh's hull at a pose.
pub(super) struct PosedHull<'a> {
    pub(super) hull: &'a Hull,
    pub(super) c: DVec3,
    pub(super) rot: DMat3,
}

impl Polytope for PosedHull<'_> {
    fn nvert(&self) -> usize {
        self.hull.vert.len()
    }
    fn vert(&self, i: usize) -> DVec3 {
        self.c + self.rot * self.hull.vert[i]
    }
    fn nface(&self) -> usize {
        self.hull.faces.len()
    }
    fn plane(&self, f: usize) -> (DVec3, f64) {
        let face = &self.hull.faces[f];
        let n = self.rot * face.normal;
        (n, face.offset + n.dot(self.c))
    }
    fn face_len(&self, f: usize) -> usize {
        self.hull.faces[f].verts.len()
    }
    fn face_vert(&self, f: usize, k: usize) -> usize {
        self.hull.faces[f].verts[k] as usize
    }
    fn nedge(&self) -> usize {
        self.hull.edges.len()
    }
    fn edge(&self, e: usize) -> ([usize; 2], Option<[DVec3; 2]>) {
        let edge = &self.hull.edges[e];
        let n = edge.faces.map(|f| self.rot * self.hull.faces[f as usize].normal);
        (edge.ends.map(|i| i as usize), Some(n))
    }
    fn centre(&self) -> DVec3 {
        self.c
    }
    fn to_local(&self, q: DVec3) -> DVec3 {
        self.rot.transpose() * (q - self.c)
    }
    fn to_local_dir(&self, d: DVec3) -> DVec3 {
        self.rot.transpose() * d
    }
    fn local_plane(&self, f: usize) -> (DVec3, f64) {
        let face = &self.hull.faces[f];
        (face.normal, face.offset)
    }
    fn support(&self, d: DVec3) -> f64 {
        self.hull.support(self.rot.transpose() * d).1 + d.dot(self.c)
    }
}

/// A box at a pose: vertex k has the signs of bits 0, 1, 2 of k; faces +x, −x, +y, −y, +z, −z.
pub(super) struct PosedBox {
    pub(super) c: DVec3,
    pub(super) rot: DMat3,
    pub(super) half: DVec3,
}

/// The box's faces, counter-clockwise about their outward normals.
const BOX_FACES: [[usize; 4]; 6] = [[1, 3, 7, 5], [0, 4, 6, 2], [2, 6, 7, 3], [0, 1, 5, 4], [4, 5, 7, 6], [0, 2, 3, 1]];

impl Polytope for PosedBox {
    fn nvert(&self) -> usize {
        8
    }
    fn vert(&self, i: usize) -> DVec3 {
        let s = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
        self.c + self.rot * DVec3::new(s(0) * self.half.x, s(1) * self.half.y, s(2) * self.half.z)
    }
    fn nface(&self) -> usize {
        6
    }
    fn plane(&self, f: usize) -> (DVec3, f64) {
        let sign = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
        let n = self.rot.col(f / 2) * sign;
        (n, self.half[f / 2] + n.dot(self.c))
    }
    fn face_len(&self, _: usize) -> usize {
        4
    }
    fn face_vert(&self, f: usize, k: usize) -> usize {
        BOX_FACES[f][k]
    }
    fn nedge(&self) -> usize {
        12
    }
    fn edge(&self, e: usize) -> ([usize; 2], Option<[DVec3; 2]>) {
        // four edges along each axis; the other two axes' bits pick the edge and its faces
        let (axis, k) = (e / 4, e % 4);
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let base = ((k & 1) << u) | ((k >> 1) << v);
        let face = |ax: usize, set: bool| {
            let (n, _) = self.plane(2 * ax + usize::from(!set));
            n
        };
        ([base, base | (1 << axis)], Some([face(u, k & 1 != 0), face(v, k >> 1 != 0)]))
    }
    fn centre(&self) -> DVec3 {
        self.c
    }
    fn support(&self, d: DVec3) -> f64 {
        let l = self.rot.transpose() * d;
        d.dot(self.c) + l.abs().dot(self.half)
    }
}

/// A segment (a capsule's core): two vertices, one edge, no faces.
pub(super) struct Segment {
    pub(super) a: DVec3,
    pub(super) b: DVec3,
}

impl Polytope for Segment {
    fn nvert(&self) -> usize {
        2
    }
    fn vert(&self, i: usize) -> DVec3 {
        if i == 0 { self.a } else { self.b }
    }
    fn nface(&self) -> usize {
        0
    }
    fn plane(&self, _: usize) -> (DVec3, f64) {
        // never asked: a segment has no faces
        (DVec3::ZERO, f64::NEG_INFINITY)
    }
    fn face_len(&self, _: usize) -> usize {
        2
    }
    fn face_vert(&self, _: usize, k: usize) -> usize {
        k
    }
    fn nedge(&self) -> usize {
        1
    }
    fn edge(&self, _: usize) -> ([usize; 2], Option<[DVec3; 2]>) {
        ([0, 1], None)
    }
    fn centre(&self) -> DVec3 {
        (self.a + self.b) * 0.5
    }
}

/// Whether the arcs of two edges' Gauss maps cross: edge A between faces of normals `na`, edge B
/// between faces of normals `nb` (None: a segment of direction `db`, whose map is the great
/// circle ⊥ db), so that their cross product is a face of the Minkowski difference.
fn minkowski_face(na: [DVec3; 2], nb: Option<[DVec3; 2]>, db: DVec3) -> bool {
    let (a, b) = (na[0], na[1]);
    let Some([c, d]) = nb else { return a.dot(db) * b.dot(db) < 0.0 };
    let (c, d) = (-c, -d);
    let (bxa, dxc) = (b.cross(a), d.cross(c));
    let (cba, dba, adc, bdc) = (c.dot(bxa), d.dot(bxa), a.dot(dxc), b.dot(dxc));
    cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
}

/// Contacts of polytopes A and B within `margin` (points midway, normals from B to A). With a
/// `hint` (GJK's or EPA's unit normal from B to A, for polytopes of many edges) the test reads
/// only the faces, and the edges next to faces, turned within 60° of it: the separating axis
/// lies near that normal, and the rest of the test's cost (every pair of edges) is spared (all
/// of them are read when a polytope has no face within the cone). Without a hint, a face that
/// held the pair apart is `kept`, and while it holds them farther apart than the margin (by the
/// tolerance the choice of the best face allows) it settles the test: the full test would find
/// a face at least as far apart, so the contacts do not depend on it.
pub(super) fn polytopes(a: &impl Polytope, b: &impl Polytope, margin: f64, scale: f64, hint: Option<DVec3>, kept: &mut Kept) -> Manifold {
    let tol = 1e-9 * scale;
    if let Some(n) = hint.filter(|_| a.nedge() * b.nedge() > HUGE_EDGE_PAIRS || a.nedge().max(b.nedge()) > HUGE_EDGES) {
        return along_normal(a, b, n, margin, tol);
    }
    if let (None, Separation::Face(of_b, f)) = (hint, kept.sep) {
        let f = f as usize;
        let s = match of_b {
            false if f < a.nface() => beyond(b, a.plane(f)),
            true if f < b.nface() => beyond(a, b.plane(f)),
            _ => f64::NEG_INFINITY,
        };
        if s > margin + tol {
            kept.skips += 1;
            return Manifold::new();
        }
    }
    let focus = Focus::new(a, b, hint, scale);
    let fa = best_face(a, b, tol, |f, n| focus.reads_face(a, f, n, -1.0));
    let fb = best_face(b, a, tol, |f, n| focus.reads_face(b, f, n, 1.0));
    if hint.is_some() && (fa.0 == f64::NEG_INFINITY || fb.0 == f64::NEG_INFINITY) {
        return polytopes(a, b, margin, scale, None, kept);
    }
    if fa.0 > margin || fb.0 > margin {
        if hint.is_none() {
            kept.sep = if fa.0 > margin { Separation::Face(false, fa.1 as u32) } else { Separation::Face(true, fb.1 as u32) };
        }
        return Manifold::new();
    }
    if hint.is_none() {
        kept.sep = Separation::Unknown;
    }
    let edge = best_edges(a, b, &focus);
    if edge.0 > margin {
        return Manifold::new();
    }
    // touching faces (separations near zero) keep their face contact: an edge pair must be
    // better by more than round-off, or the manifold would flip between one point and a face's
    let face = fa.0.max(fb.0);
    if edge.0 > face + 0.05 * face.abs() + 1e3 * tol {
        let (_, ea, eb, axis) = edge;
        let ([a0, a1], _) = a.edge(ea);
        let ([b0, b1], _) = b.edge(eb);
        let (q1, q2) = closest_segments(a.vert(a0), a.vert(a1), b.vert(b0), b.vert(b1));
        let mut out = Manifold::new();
        out.push((EDGE + ea * b.nedge() + eb, (q1 + q2) * 0.5, -axis, axis.dot(q2 - q1)));
        return out;
    }
    if fb.0 > fa.0 + tol {
        let mut m = clip(b, fb.1, a, margin, tol);
        for p in m.iter_mut() {
            p.0 += FACE_B;
        }
        m
    } else {
        let mut m = clip(a, fa.1, b, margin, tol);
        for p in m.iter_mut() {
            p.0 += FACE_A;
            p.2 = -p.2;
        }
        m
    }
}

/// What a hinted test reads: with a `hint` (unit, from B to A), A's faces look along −hint and
/// B's along +hint within [`CONE`], and the features that can meet have a vertex within the
/// overlap along it (and 2% of the pair's size) of their polytope's extreme toward the other.
struct Focus {
    hint: Option<DVec3>,
    /// A's extreme along −hint and B's along +hint.
    reach: [f64; 2],
    slack: f64,
}

impl Focus {
    fn new(a: &impl Polytope, b: &impl Polytope, hint: Option<DVec3>, scale: f64) -> Focus {
        let reach = hint.map_or([f64::NEG_INFINITY; 2], |h| [a.support(-h), b.support(h)]);
        Focus { hint, reach, slack: (reach[0] + reach[1]).abs() + 0.02 * scale }
    }

    /// Whether a face normal of A (`along` −1) or B (+1) turns toward the other.
    fn near(&self, normal: DVec3, along: f64) -> bool {
        self.hint.is_none_or(|h| along * normal.dot(h) > CONE)
    }

    /// Whether face `f` (normal `normal`) of `p`, A (`along` −1) or B (+1), is read: every face
    /// without a hint (no vertex is posed for it), else one turned toward the other polytope
    /// with a vertex near its extreme.
    fn reads_face(&self, p: &impl Polytope, f: usize, normal: DVec3, along: f64) -> bool {
        self.hint.is_none() || (self.near(normal, along) && (0..p.face_len(f)).any(|k| self.toward(along, p.vert(p.face_vert(f, k)))))
    }

    /// Whether point `p` of A (`along` −1) or B (+1) lies near its extreme toward the other.
    fn toward(&self, along: f64, p: DVec3) -> bool {
        let reach = self.reach[usize::from(along > 0.0)];
        self.hint.is_none_or(|h| along * p.dot(h) >= reach - self.slack)
    }
}

/// The edge pair of A and B whose axis (a face of their Minkowski difference) separates them
/// most: (separation, edge of A, edge of B, unit axis from A toward B), of the edges `focus` reads.
fn best_edges(a: &impl Polytope, b: &impl Polytope, focus: &Focus) -> (f64, usize, usize, DVec3) {
    // B's edges (those read) posed once: index, start, direction, face normals
    let wanted_b = |e: &(usize, DVec3, DVec3, Option<[DVec3; 2]>)| {
        e.3.is_none_or(|[n0, n1]| focus.near(n0, 1.0) || focus.near(n1, 1.0)) && (focus.toward(1.0, e.1) || focus.toward(1.0, e.1 + e.2))
    };
    let pose_b = |eb: usize| {
        let ([b0, b1], nb) = b.edge(eb);
        let pb = b.vert(b0);
        (eb, pb, b.vert(b1) - pb, nb)
    };
    let mut b_edges: ArrayVec<(usize, DVec3, DVec3, Option<[DVec3; 2]>), MAX_POSED_EDGES> = ArrayVec::new();
    let mut posed = true;
    for eb in 0..b.nedge() {
        let e = pose_b(eb);
        if wanted_b(&e) && b_edges.try_push(e).is_err() {
            posed = false;
            break;
        }
    }
    let a_centre = a.centre();
    let mut edge = (f64::NEG_INFINITY, 0, 0, DVec3::ZERO);
    for ea in 0..a.nedge() {
        let ([a0, a1], na) = a.edge(ea);
        let (pa, da) = (a.vert(a0), a.vert(a1) - a.vert(a0));
        let Some(na) = na else { continue };
        if !(focus.near(na[0], -1.0) || focus.near(na[1], -1.0)) || !(focus.toward(-1.0, pa) || focus.toward(-1.0, pa + da)) {
            continue;
        }
        let mut consider = |(eb, pb, db, nb): (usize, DVec3, DVec3, Option<[DVec3; 2]>)| {
            if !minkowski_face(na, nb, db) {
                return;
            }
            let axis = da.cross(db);
            let len = axis.length();
            if len < 1e-6 * da.length() * db.length() {
                return;
            }
            let axis = if axis.dot(pa - a_centre) < 0.0 { -axis / len } else { axis / len };
            let s = axis.dot(pb - pa);
            if s > edge.0 {
                edge = (s, ea, eb, axis);
            }
        };
        if posed {
            b_edges.iter().for_each(|&e| consider(e));
        } else {
            (0..b.nedge()).map(pose_b).filter(wanted_b).for_each(consider);
        }
    }
    edge
}

/// Contacts of polytopes of very many edges (detailed meshes' hulls) along GJK's or EPA's unit
/// normal `n` (from B to A), without the separating-axis test's pass over every pair of edges:
/// the gap along n; of the two faces turned most squarely against the other polytope, the one
/// nearer n clips the other's incident face (a face contact, as the test makes it); when
/// neither lies within 18° of n, one point midway between the deepest vertices along n.
fn along_normal(a: &impl Polytope, b: &impl Polytope, n: DVec3, margin: f64, tol: f64) -> Manifold {
    let gap = -a.support(-n) - b.support(n);
    if gap > margin {
        return Manifold::new();
    }
    // read in each polytope's own frame
    let facing = |p: &dyn Fn(usize) -> DVec3, faces: usize, dir: DVec3| {
        (0..faces).map(|f| (p(f).dot(dir), f)).fold((f64::NEG_INFINITY, 0), |x, y| if y.0 > x.0 { y } else { x })
    };
    let (ca, fa) = facing(&|f| a.local_plane(f).0, a.nface(), a.to_local_dir(-n));
    let (cb, fb) = facing(&|f| b.local_plane(f).0, b.nface(), b.to_local_dir(n));
    if ca.max(cb) > 0.95 {
        let mut m = if cb > ca { clip(b, fb, a, margin, tol) } else { clip(a, fa, b, margin, tol) };
        for p in m.iter_mut() {
            if cb > ca {
                p.0 += FACE_B;
            } else {
                p.0 += FACE_A;
                p.2 = -p.2;
            }
        }
        return m;
    }
    let deepest = |p: &dyn Fn(usize) -> DVec3, verts: usize, dir: DVec3| {
        (0..verts).map(p).fold(DVec3::splat(f64::NAN), |x, y| if x.is_nan() || y.dot(dir) > x.dot(dir) { y } else { x })
    };
    let (pa, pb) = (deepest(&|i| a.vert(i), a.nvert(), -n), deepest(&|i| b.vert(i), b.nvert(), n));
    let mut out = Manifold::new();
    out.push((EDGE, (pa + pb) * 0.5, n, gap));
    out
}

/// The face of `p` (of those `wanted`, by index and normal) that separates `q` most: (separation,
/// face); a later face must be better by more than `tol`, so that faces tied by round-off keep
/// the first.
fn best_face(p: &impl Polytope, q: &impl Polytope, tol: f64, wanted: impl Fn(usize, DVec3) -> bool) -> (f64, usize) {
    let mut best = (f64::NEG_INFINITY, 0);
    for f in 0..p.nface() {
        let plane = p.plane(f);
        if !wanted(f, plane.0) {
            continue;
        }
        let s = beyond(q, plane);
        if s > best.0 + tol {
            best = (s, f);
        }
    }
    best
}

/// How far q lies beyond the plane (n, d) of a face (n · x = d on it, n outward).
fn beyond(q: &impl Polytope, (n, d): (DVec3, f64)) -> f64 {
    -q.support(-n) - d
}

/// Face contact: the incident face of `inc` (the one most opposed to reference face `f` of `r`)
/// clipped by the side planes of `f`; points within `margin` of the face, normals along the
/// face's (from the reference toward the incident polytope).
fn clip(r: &impl Polytope, f: usize, inc: &impl Polytope, margin: f64, tol: f64) -> Manifold {
    let (n, d) = r.plane(f);
    let fi = (0..inc.nface()).min_by(|&x, &y| inc.plane(x).0.dot(n).total_cmp(&inc.plane(y).0.dot(n)));
    let mut poly: ArrayVec<(DVec3, usize), MAX_POLY> = ArrayVec::new();
    let verts = fi.map_or(2, |fi| inc.face_len(fi));
    for k in 0..verts.min(MAX_POLY) {
        let v = fi.map_or(k, |fi| inc.face_vert(fi, k));
        poly.push((inc.vert(v), v));
    }
    let mut next: ArrayVec<(DVec3, usize), MAX_POLY> = ArrayVec::new();
    let nr = r.face_len(f);
    for k in 0..nr {
        if poly.is_empty() {
            break;
        }
        let (v0, v1) = (r.vert(r.face_vert(f, k)), r.vert(r.face_vert(f, (k + 1) % nr)));
        let side = (v1 - v0).cross(n).normalize_or_zero();
        next.clear();
        let len = poly.len();
        // a two-vertex polygon (a segment) is one edge, not a closed loop
        let edges = if len == 2 { 1 } else { len };
        for i in 0..edges {
            let ((p, ip), (q, _)) = (poly[i], poly[(i + 1) % len]);
            let (sp, sq) = (side.dot(p - v0), side.dot(q - v0));
            if sp <= tol && !next.is_full() {
                next.push((p, ip));
            }
            if ((sp < -tol && sq > tol) || (sp > tol && sq < -tol)) && !next.is_full() {
                next.push((p + (q - p) * (sp / (sp - sq)), CUT + (k << 12) + (ip & 0xfff)));
            }
            if len == 2 && sq <= tol && !next.is_full() {
                next.push(poly[1]);
            }
        }
        std::mem::swap(&mut poly, &mut next);
    }
    let mut pts: ArrayVec<Point, MAX_POLY> = ArrayVec::new();
    for &(p, id) in &poly {
        let depth = n.dot(p) - d;
        let at = p - n * (0.5 * depth);
        if depth <= margin && !pts.iter().any(|o| o.1.distance(at) <= tol) {
            pts.push(((f << 24) + id, at, n, depth));
        }
    }
    reduce(&pts, n)
}

/// At most [`MAX_MANIFOLD`] of `pts` around normal `n`: all when few, else the deepest, the one
/// farthest from it, the one spanning the largest triangle with those two and the one adding the
/// most area on the other side (the classic reduction that keeps a face's support polygon).
pub(super) fn reduce(pts: &[Point], n: DVec3) -> Manifold {
    let mut out = Manifold::new();
    let push = |out: &mut Manifold, i: usize| {
        if !out.iter().any(|q| q.0 == pts[i].0) && !out.is_full() {
            out.push(pts[i]);
        }
    };
    if pts.len() <= MAX_MANIFOLD {
        (0..pts.len()).for_each(|i| push(&mut out, i));
        return out;
    }
    let best = |score: &dyn Fn(DVec3) -> f64| (0..pts.len()).max_by(|&i, &j| score(pts[i].1).total_cmp(&score(pts[j].1))).unwrap_or(0);
    let a = (0..pts.len()).min_by(|&i, &j| pts[i].3.total_cmp(&pts[j].3)).unwrap_or(0);
    let pa = pts[a].1;
    let b = best(&|p| p.distance_squared(pa));
    let pb = pts[b].1;
    let area = |p: DVec3| (pb - pa).cross(p - pa).dot(n);
    let c = best(&|p| area(p).abs());
    let side = area(pts[c].1).signum();
    // the fourth on the other side of ab from c
    let d = best(&|p| -side * area(p));
    for i in [a, b, c, d] {
        push(&mut out, i);
    }
    out
}

/// The vertices of `p` within `margin` of the plane through `o` with unit normal `n` (points on
/// the plane's side midway, normals `n`, features the vertex indices), at most [`MAX_MANIFOLD`].
pub(super) fn on_plane(p: &impl Polytope, o: DVec3, n: DVec3, margin: f64) -> Manifold {
    let mut pts: ArrayVec<Point, MAX_POLY> = ArrayVec::new();
    for i in 0..p.nvert() {
        let v = p.vert(i);
        let d = (v - o).dot(n);
        if d <= margin && !pts.is_full() {
            pts.push((i, v - n * (0.5 * d), n, d));
        }
    }
    reduce(&pts, n)
}

/// Signed distance of point `q` from a polytope and the unit normal from it toward `q`: the
/// closest point of the faces that see `q`, or, inside, the face of least penetration.
pub(super) fn point_polytope(p: &impl Polytope, q: DVec3) -> (DVec3, f64) {
    let ql = p.to_local(q);
    let separation = |f: usize| {
        let (n, d) = p.local_plane(f);
        n.dot(ql) - d
    };
    let (mut top, mut top_face) = (f64::NEG_INFINITY, 0);
    for f in 0..p.nface() {
        let s = separation(f);
        if s > top {
            (top, top_face) = (s, f);
        }
    }
    if top <= 0.0 {
        return (p.plane(top_face).0, top);
    }
    // a face's points are at least its plane's distance s away, and the polytope's at least the
    // largest s (top): the face of the largest s goes first (its own point at distance top ends
    // the search), and a face whose s is already beyond the nearest point found cannot hold a
    // nearer one
    let mut best = (f64::INFINITY, q);
    for f in std::iter::once(top_face).chain((0..p.nface()).filter(|&f| f != top_face)) {
        if best.0 <= top {
            break;
        }
        let s = separation(f);
        if s <= 0.0 || s >= best.0 {
            continue;
        }
        let (n, d) = p.plane(f);
        let s = n.dot(q) - d;
        let on = q - n * s;
        let k = p.face_len(f);
        let vert = |i: usize| p.vert(p.face_vert(f, i % k));
        let inside = (0..k).all(|i| (vert(i + 1) - vert(i)).cross(n).dot(on - vert(i)) <= 0.0);
        let closest = if inside {
            on
        } else {
            (0..k).map(|i| super::shapes::closest_on_segment(vert(i), vert(i + 1), q)).min_by(|a, b| a.distance_squared(q).total_cmp(&b.distance_squared(q))).unwrap_or(on)
        };
        let dist = closest.distance(q);
        if dist < best.0 {
            best = (dist, closest);
        }
    }
    ((q - best.1) / best.0.max(1e-300), best.0)
}

#[cfg(test)]
pub(super) mod tests;
