//! Triangle surfaces the renderer casts rays at (meshes and height fields): parry's
//! bounding-volume tree over a mesh's triangles, a walk over a height field's grid
//! (`hfield_grid.rs`), and each triangle's corner normals — the file's, or smooth vertex normals
//! made as MuJoCo makes them (area-weighted face normals, a face leaving a vertex's sum where it
//! meets the vertex normal at more than about 37°, so edges stay sharp) — interpolated across
//! each hit triangle.

use glam::{DVec3, Vec3A};
use parry3d_f64::math::Vector;
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;

use super::hfield_grid::Grid;
use super::raycast::Hit;
use crate::geometry::HField;

/// A face counts toward a vertex's normal when their cosine is at least this (MuJoCo's rule).
const SMOOTH_COS: f64 = 0.8;

/// Triangles and their vertex normals, in the geom's frame.
#[derive(Debug)]
pub struct Surface {
    index: Index,
    tris: Vec<[u32; 3]>,
    vert: Vec<Vec3A>,
    /// Each triangle's corner normals.
    corners: Vec<[Vec3A; 3]>,
}

/// What finds the first triangle a ray meets.
#[derive(Debug)]
enum Index {
    /// A mesh's: parry's tree.
    Tree(Box<TriMesh>),
    /// A height field's grid, whose triangles are `HField::triangles`.
    Grid(Grid),
}

impl Surface {
    /// The surface of triangles `face` over `vert`, with the file's corner normals when given
    /// (one triple per face); None if parry refuses the triangles (degenerate).
    pub fn new(vert: &[DVec3], face: &[[u32; 3]], given: &[[DVec3; 3]]) -> Option<Surface> {
        let tree = TriMesh::new(vert.iter().map(|p| Vector::new(p.x, p.y, p.z)).collect(), face.to_vec()).ok()?;
        Some(Surface::with_index(Index::Tree(Box::new(tree)), vert, face, given))
    }

    /// A height field's top surface (`HField::triangles` over its grid points).
    pub fn height_field(h: &HField) -> Surface {
        let vert: Vec<DVec3> = (0..h.nrow * h.ncol).map(|i| h.vertex(i / h.ncol, i % h.ncol)).collect();
        Surface::with_index(Index::Grid(Grid::new(h)), &vert, &h.triangles(), &[])
    }

    fn with_index(index: Index, vert: &[DVec3], face: &[[u32; 3]], given: &[[DVec3; 3]]) -> Surface {
        let area_normal = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| vert[i as usize]);
            (b - a).cross(c - a)
        };
        let mut sum = vec![DVec3::ZERO; vert.len()];
        for t in face {
            let n = area_normal(t);
            t.iter().for_each(|&i| sum[i as usize] += n);
        }
        let mut smooth = vec![DVec3::ZERO; vert.len()];
        for t in face {
            let n = area_normal(t);
            for &i in t {
                if n.normalize_or_zero().dot(sum[i as usize].normalize_or_zero()) >= SMOOTH_COS {
                    smooth[i as usize] += n;
                }
            }
        }
        let corners = if given.len() == face.len() {
            given.iter().map(|c| c.map(|n| n.as_vec3a())).collect()
        } else {
            face.iter().map(|t| t.map(|i| smooth[i as usize].normalize_or(DVec3::Z).as_vec3a())).collect()
        };
        Surface { index, tris: face.to_vec(), vert: vert.iter().map(|v| v.as_vec3a()).collect(), corners }
    }

    /// First hit of the ray `o + t d` in `[t0, t1)`, the normal interpolated from the hit
    /// triangle's vertex normals (the face's where they disagree with it) and facing the ray.
    pub fn hit(&self, o: Vec3A, d: Vec3A, t0: f32, t1: f32) -> Option<Hit> {
        let (t, k, face) = match &self.index {
            Index::Tree(tree) => {
                let v = |x: Vec3A| Vector::new(f64::from(x.x), f64::from(x.y), f64::from(x.z));
                let start = o + d * t0;
                let hit = tree.cast_local_ray_and_get_normal(&Ray::new(v(start), v(d)), f64::from(t1 - t0), false)?;
                let face = Vec3A::new(hit.normal.x as f32, hit.normal.y as f32, hit.normal.z as f32);
                (t0 + hit.time_of_impact as f32, hit.subshape as usize, face)
            }
            Index::Grid(grid) => grid.first_hit(o, d, t0, t1)?,
        };
        if t >= t1 {
            return None;
        }
        let n = self.tris.get(k).map_or(face, |tri| {
            let [a, b, c] = tri.map(|i| self.vert[i as usize]);
            let p = o + d * t;
            // barycentric weights of p by the sub-triangles' areas
            let full = (b - a).cross(c - a);
            let inv = 1.0 / full.length_squared().max(f32::MIN_POSITIVE);
            let wa = (b - p).cross(c - p).dot(full) * inv;
            let wb = (c - p).cross(a - p).dot(full) * inv;
            let wc = 1.0 - wa - wb;
            let [na, nb, nc] = self.corners[k];
            let s = (na * wa + nb * wb + nc * wc).normalize_or_zero();
            if s.dot(face).abs() > 0.2 { s * s.dot(face).signum() } else { face }
        });
        Some((t, if n.dot(d) > 0.0 { -n } else { n }))
    }
}
