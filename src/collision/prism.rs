//! A height field's convex piece: the prism under one of its triangles down to the field's base
//! (MuJoCo's decomposition), as a polytope the convex tests read.

use glam::DVec3;

use super::convex::Polytope;

/// A triangle of a height field (world vertices, counter-clockwise seen from above the field)
/// and the prism under it down to the field's base: MuJoCo's convex piece of a height field.
pub(super) struct Prism {
    /// Top vertices 0–2, then the base vertices below them 3–5.
    pub(super) v: [DVec3; 6],
    /// Faces: top, base, then the sides over edges 0–1, 1–2, 2–0.
    pub(super) planes: [(DVec3, f64); 5],
}

const PRISM_FACES: [&[usize]; 5] = [&[0, 1, 2], &[3, 5, 4], &[0, 3, 4, 1], &[1, 4, 5, 2], &[2, 5, 3, 0]];
/// Edges: ends and faces.
const PRISM_EDGES: [([usize; 2], [usize; 2]); 9] =
    [([0, 1], [0, 2]), ([1, 2], [0, 3]), ([2, 0], [0, 4]), ([3, 4], [1, 2]), ([4, 5], [1, 3]), ([5, 3], [1, 4]), ([0, 3], [4, 2]), ([1, 4], [2, 3]), ([2, 5], [3, 4])];

impl Prism {
    /// The prism under triangle `top` (world) whose base lies `depth` below the field's plane
    /// (origin `o`, up `up`).
    pub(super) fn new(top: [DVec3; 3], o: DVec3, up: DVec3, depth: f64) -> Prism {
        let base = |p: DVec3| p - up * (up.dot(p - o) + depth);
        let v = [top[0], top[1], top[2], base(top[0]), base(top[1]), base(top[2])];
        let plane = |f: &[usize]| {
            let n = (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).normalize_or_zero();
            (n, n.dot(v[f[0]]))
        };
        Prism { v, planes: PRISM_FACES.map(plane) }
    }
}

impl Polytope for Prism {
    fn nvert(&self) -> usize {
        6
    }
    fn vert(&self, i: usize) -> DVec3 {
        self.v[i]
    }
    fn nface(&self) -> usize {
        5
    }
    fn plane(&self, f: usize) -> (DVec3, f64) {
        self.planes[f]
    }
    fn face_len(&self, f: usize) -> usize {
        PRISM_FACES[f].len()
    }
    fn face_vert(&self, f: usize, k: usize) -> usize {
        PRISM_FACES[f][k]
    }
    fn nedge(&self) -> usize {
        9
    }
    fn edge(&self, e: usize) -> ([usize; 2], Option<[DVec3; 2]>) {
        let (ends, faces) = PRISM_EDGES[e];
        (ends, Some(faces.map(|f| self.planes[f].0)))
    }
    fn centre(&self) -> DVec3 {
        self.v.iter().copied().sum::<DVec3>() / 6.0
    }
}
