//! Convex hulls as collision shapes: the hull's vertices, its triangles, its faces (coplanar
//! triangles merged into one polygon, so a box has six) and its edges with the two faces each
//! joins (the Gauss map the separating-axis test prunes edge pairs with). Quickhull from parry.

use glam::DVec3;

/// Triangles whose normals differ by less than this (1 − cos of the angle) are one face.
const COPLANAR: f64 = 1e-9;

/// A face of a hull: outward unit normal, plane offset (normal · x on the face) and its vertices
/// in counter-clockwise order about the normal.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// Outward unit normal.
    pub normal: DVec3,
    /// normal · x for the points x of the face.
    pub offset: f64,
    /// Vertex indices, counter-clockwise about `normal`.
    pub verts: Vec<u32>,
}

/// An edge of a hull between two faces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// End vertices.
    pub ends: [u32; 2],
    /// The faces on either side.
    pub faces: [u32; 2],
}

/// A convex polyhedron.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hull {
    /// Vertices.
    pub vert: Vec<DVec3>,
    /// Triangles, counter-clockwise seen from outside.
    pub tris: Vec<[u32; 3]>,
    /// Faces (merged coplanar triangles).
    pub faces: Vec<Face>,
    /// Edges between faces.
    pub edges: Vec<Edge>,
    /// Each vertex's neighbours along the triangles' edges: `neighbours[start[i]..start[i + 1]]`
    /// (a hull of more than [`CLIMB_FROM`] vertices finds its support by walking them).
    neighbours: Vec<u32>,
    start: Vec<u32>,
    /// The vertices farthest along ±x, ±y, ±z: the walk starts from the best of them.
    seeds: [u32; 6],
    /// The box of the vertices along the hull's axes: centre and half extents.
    pub bounds: (DVec3, DVec3),
}

/// Vertices beyond which [`Hull::support`] climbs the vertex graph instead of reading every vertex.
const CLIMB_FROM: usize = 64;

impl Hull {
    /// The convex hull of `points`; None when they span no volume.
    pub fn new(points: &[DVec3]) -> Option<Hull> {
        let pts: Vec<_> = points.iter().map(|p| parry3d_f64::math::Vector::new(p.x, p.y, p.z)).collect();
        let (v, tris) = parry3d_f64::transformation::try_convex_hull(&pts).ok()?;
        if tris.len() < 4 {
            return None;
        }
        let vert: Vec<DVec3> = v.iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect();
        let mut h = Hull { vert, tris, ..Hull::default() };
        h.link_vertices();
        h.merge_faces().then_some(h)
    }

    /// The hull moved into the frame whose origin is `origin` and whose rotation from the hull's
    /// present frame is `rot`ᵀ: each point x goes to `rot` (x − origin). Its faces' planes, support
    /// seeds and bounding box follow (the box is the oriented-box midphase's: one left in the
    /// old frame declared overlapping meshes apart).
    pub fn move_into(&mut self, rot: glam::DMat3, origin: DVec3) {
        for v in &mut self.vert {
            *v = rot * (*v - origin);
        }
        for f in &mut self.faces {
            f.offset -= f.normal.dot(origin);
            f.normal = rot * f.normal;
        }
        self.find_extremes();
    }

    /// Whether the hull finds its support by climbing its vertex graph ([`Hull::neighbours_of`]).
    pub fn climbs(&self) -> bool {
        self.vert.len() > CLIMB_FROM && !self.start.is_empty()
    }

    /// Vertex i's neighbours along the triangles' edges.
    pub fn neighbours_of(&self, i: usize) -> &[u32] {
        &self.neighbours[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The vertex farthest along `d` and its projection on `d`: on a hull of many vertices by
    /// climbing from a triangle's vertex to the best neighbour while one is farther (on a convex polytope a
    /// vertex no neighbour beats is a farthest one, as in the simplex method).
    pub fn support(&self, d: DVec3) -> (usize, f64) {
        self.support_from(d, None)
    }

    /// [`Hull::support`] climbing from vertex `start` (the last support point of a nearby
    /// direction: a few steps away) instead of the best of the axes' extremes.
    pub fn support_from(&self, d: DVec3, start: Option<usize>) -> (usize, f64) {
        if self.climbs() {
            let mut best = (0, f64::NEG_INFINITY);
            match start.filter(|&i| i < self.vert.len()) {
                Some(i) => best = (i, self.vert[i].dot(d)),
                None => {
                    for &i in &self.seeds {
                        let s = self.vert[i as usize].dot(d);
                        if s > best.1 {
                            best = (i as usize, s);
                        }
                    }
                }
            }
            loop {
                let (i, s) = best;
                for &j in self.neighbours_of(i) {
                    let t = self.vert[j as usize].dot(d);
                    if t > best.1 {
                        best = (j as usize, t);
                    }
                }
                if best.1 <= s || !best.1.is_finite() {
                    return best;
                }
            }
        }
        let mut best = (0, f64::NEG_INFINITY);
        for (i, v) in self.vert.iter().enumerate() {
            let s = v.dot(d);
            if s > best.1 {
                best = (i, s);
            }
        }
        best
    }

    /// Each vertex's neighbours along the triangles' edges ([`Hull::support`]'s walk).
    fn link_vertices(&mut self) {
        let mut lists: Vec<Vec<u32>> = vec![vec![]; self.vert.len()];
        for t in &self.tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if !lists[a as usize].contains(&b) {
                    lists[a as usize].push(b);
                }
                if !lists[b as usize].contains(&a) {
                    lists[b as usize].push(a);
                }
            }
        }
        self.start = std::iter::once(0).chain(lists.iter().scan(0, |n, l| {
            *n += l.len() as u32;
            Some(*n)
        })).collect();
        self.neighbours = lists.concat();
        self.find_extremes();
    }

    /// The vertices farthest along ±x, ±y, ±z (`seeds`) and the box they bound (`bounds`).
    fn find_extremes(&mut self) {
        let extreme = |d: DVec3| (0..self.vert.len()).max_by(|&a, &b| self.vert[a].dot(d).total_cmp(&self.vert[b].dot(d))).unwrap_or(0) as u32;
        self.seeds = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z].map(extreme);
        let [hx, lx, hy, ly, hz, lz] = self.seeds.map(|i| self.vert[i as usize]);
        let (lo, hi) = (DVec3::new(lx.x, ly.y, lz.z), DVec3::new(hx.x, hy.y, hz.z));
        self.bounds = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    }

    /// Groups adjacent triangles with one normal into faces; lists the edges between faces.
    /// False when a face has no boundary (a degenerate hull).
    fn merge_faces(&mut self) -> bool {
        let normal = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| self.vert[i as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        };
        let normals: Vec<DVec3> = self.tris.iter().map(normal).collect();
        // the triangle on the other side of each directed edge
        let mut twin = std::collections::HashMap::new();
        for (t, tri) in self.tris.iter().enumerate() {
            for k in 0..3 {
                twin.insert((tri[k], tri[(k + 1) % 3]), t);
            }
        }
        // union–find of coplanar neighbours
        let mut root: Vec<usize> = (0..self.tris.len()).collect();
        fn find(root: &mut [usize], mut i: usize) -> usize {
            while root[i] != i {
                root[i] = root[root[i]];
                i = root[i];
            }
            i
        }
        for (t, tri) in self.tris.iter().enumerate() {
            for k in 0..3 {
                if let Some(&u) = twin.get(&(tri[(k + 1) % 3], tri[k]))
                    && normals[t].dot(normals[u]) > 1.0 - COPLANAR
                {
                    let (a, b) = (find(&mut root, t), find(&mut root, u));
                    root[a.max(b)] = a.min(b);
                }
            }
        }
        let mut face_of = vec![usize::MAX; self.tris.len()];
        for t in 0..self.tris.len() {
            let r = find(&mut root, t);
            if face_of[r] == usize::MAX {
                face_of[r] = self.faces.len();
                self.faces.push(Face { normal: DVec3::ZERO, offset: 0.0, verts: vec![] });
            }
            face_of[t] = face_of[r];
        }
        // each face's boundary: its directed edges whose twin lies in another face, chained
        let mut next: Vec<std::collections::HashMap<u32, u32>> = vec![Default::default(); self.faces.len()];
        for (t, tri) in self.tris.iter().enumerate() {
            let [a, b, c] = tri.map(|i| self.vert[i as usize]);
            let f = face_of[t];
            self.faces[f].normal += (b - a).cross(c - a);
            for k in 0..3 {
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                let other = twin.get(&(j, i)).map_or(usize::MAX, |&u| face_of[u]);
                if other != f {
                    next[f].insert(i, j);
                    if i < j {
                        self.edges.push(Edge { ends: [i, j], faces: [f as u32, other as u32] });
                    }
                }
            }
        }
        for (f, face) in self.faces.iter_mut().enumerate() {
            face.normal = face.normal.normalize();
            let Some(&start) = next[f].keys().min() else { return false };
            let mut v = start;
            loop {
                face.verts.push(v);
                let Some(&to) = next[f].get(&v) else { return false };
                v = to;
                if v == start || face.verts.len() > next[f].len() {
                    break;
                }
            }
            face.offset = face.verts.iter().map(|&i| face.normal.dot(self.vert[i as usize])).sum::<f64>() / face.verts.len() as f64;
        }
        true
    }
}
