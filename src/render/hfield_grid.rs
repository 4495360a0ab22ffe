//! A ray's first hit on a height field's top surface by walking its grid
//! ([`crate::geometry::grid_walk`]): the ray's footprint crosses blocks of cells in order of
//! distance, a block whose highest point the ray passes above is skipped, and in the others the
//! cells are walked the same way, each cell's two triangles tested. The first cell with a hit holds the nearest. A tree over the
//! triangles (`surface.rs`) costs a log of the triangle count per ray and a rebuild whenever a
//! world draws new terrain; this costs the cells the ray passes near the surface.

use glam::Vec3A;

use crate::geometry::grid_walk::{clip, triangle, walk};
use crate::geometry::HField;

/// Cells per block side.
const BLOCK: usize = 4;

/// A height field's grid in its geom's frame.
#[derive(Debug)]
pub struct Grid {
    /// Grid points per row (x) and per column (y).
    ncol: usize,
    nrow: usize,
    /// The grid's corner (x, y) and cell size.
    x0: f32,
    y0: f32,
    dx: f32,
    dy: f32,
    /// Height of each grid point, row-major.
    z: Vec<f32>,
    /// Blocks per row and per column, and each block's highest point (row-major).
    bcol: usize,
    brow: usize,
    bmax: Vec<f32>,
    /// The lowest and highest point.
    zmin: f32,
    zmax: f32,
}

/// A hit: distance along the ray, triangle (`HField::triangles`' numbering) and its face normal.
pub type GridHit = (f32, usize, Vec3A);

impl Grid {
    /// The grid of `h` (at least 2 × 2 points).
    pub fn new(h: &HField) -> Grid {
        let (nrow, ncol) = (h.nrow, h.ncol);
        let z: Vec<f32> = (0..nrow * ncol).map(|i| h.vertex(i / ncol, i % ncol).z as f32).collect();
        let (bcol, brow) = ((ncol - 1).div_ceil(BLOCK), (nrow - 1).div_ceil(BLOCK));
        let mut bmax = vec![f32::NEG_INFINITY; bcol * brow];
        for r in 0..nrow {
            for c in 0..ncol {
                // a point bounds the cells on both sides of it
                for br in (r.saturating_sub(1) / BLOCK)..=((r.min(nrow - 2)) / BLOCK) {
                    for bc in (c.saturating_sub(1) / BLOCK)..=((c.min(ncol - 2)) / BLOCK) {
                        let m = &mut bmax[br * bcol + bc];
                        *m = m.max(z[r * ncol + c]);
                    }
                }
            }
        }
        let (zmin, zmax) = z.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let (x0, y0) = (-h.size[0] as f32, -h.size[1] as f32);
        let (dx, dy) = (2.0 * h.size[0] as f32 / (ncol - 1) as f32, 2.0 * h.size[1] as f32 / (nrow - 1) as f32);
        Grid { ncol, nrow, x0, y0, dx, dy, z, bcol, brow, bmax, zmin, zmax }
    }

    /// The first hit of the ray `o + t d` with t in [t0, t1), either side of the surface.
    pub fn first_hit(&self, o: Vec3A, d: Vec3A, t0: f32, t1: f32) -> Option<GridHit> {
        let (x1, y1) = (self.x0 + self.dx * (self.ncol - 1) as f32, self.y0 + self.dy * (self.nrow - 1) as f32);
        let (ta, tb) = clip(o, d, (t0, t1), [self.x0, self.y0, self.zmin], [x1, y1, self.zmax])?;
        let (bw, bh) = (self.dx * BLOCK as f32, self.dy * BLOCK as f32);
        walk((self.bcol, self.brow), (self.x0, self.y0), (bw, bh), o, d, (ta, tb), |bc, br, tin, tout| {
            // the ray is straight: over the block its lowest point is at an end
            if (o.z + d.z * tin).min(o.z + d.z * tout) > self.bmax[br * self.bcol + bc] {
                return None;
            }
            let corner = (self.x0 + bw * bc as f32, self.y0 + bh * br as f32);
            let cells = (BLOCK.min(self.ncol - 1 - bc * BLOCK), BLOCK.min(self.nrow - 1 - br * BLOCK));
            walk(cells, corner, (self.dx, self.dy), o, d, (tin, tout), |c, r, cin, cout| {
                self.cell_hit(bc * BLOCK + c, br * BLOCK + r, o, d, (t0, t1), (o.z + d.z * cin).min(o.z + d.z * cout))
            })
        })
    }

    /// The nearer hit of cell (c, r)'s two triangles, within [t0, t1); none if the ray's lowest
    /// point over the cell, `low`, is above its corners.
    fn cell_hit(&self, c: usize, r: usize, o: Vec3A, d: Vec3A, (t0, t1): (f32, f32), low: f32) -> Option<GridHit> {
        let z = |r: usize, c: usize| self.z[r * self.ncol + c];
        if low > z(r, c).max(z(r, c + 1)).max(z(r + 1, c + 1)).max(z(r + 1, c)) {
            return None;
        }
        let p = |r: usize, c: usize| Vec3A::new(self.x0 + self.dx * c as f32, self.y0 + self.dy * r as f32, z(r, c));
        let (a, b, cc, dd) = (p(r, c), p(r, c + 1), p(r + 1, c + 1), p(r + 1, c));
        let first = 2 * (r * (self.ncol - 1) + c);
        let mut best: Option<GridHit> = None;
        for (k, [u, v, w]) in [[a, b, cc], [a, cc, dd]].into_iter().enumerate() {
            if let Some(t) = triangle(o, d, [u, v, w]).filter(|&t| t >= t0 && t < t1 && best.is_none_or(|(tb, _, _)| t < tb)) {
                best = Some((t, first + k, (v - u).cross(w - u).normalize_or_zero()));
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Vector;
    use parry3d_f64::query::{Ray, RayCast};
    use parry3d_f64::shape::TriMesh;

    /// The walk finds the triangle and distance parry's tree finds, on a rough random field and
    /// rays from every direction (grazing ones included), and misses where it misses.
    #[test]
    fn walk_agrees_with_a_tree_over_the_triangles() {
        let (nrow, ncol) = (37, 29);
        let mut x = 7u64;
        let mut rand = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let data = (0..nrow * ncol).map(|_| rand()).collect();
        let h = HField { name: String::new(), nrow, ncol, size: [2.0, 3.0, 0.5, 0.1], data };
        let grid = Grid::new(&h);
        let vert = (0..nrow * ncol).map(|i| { let p = h.vertex(i / ncol, i % ncol); Vector::new(p.x, p.y, p.z) }).collect();
        let tree = TriMesh::new(vert, h.triangles()).unwrap();
        let (mut hits, mut same) = (0, 0);
        for _ in 0..20_000 {
            let o = Vec3A::new(6.0 * rand() as f32 - 3.0, 8.0 * rand() as f32 - 4.0, 2.0 * rand() as f32 - 0.5);
            let d = Vec3A::new(rand() as f32 - 0.5, rand() as f32 - 0.5, rand() as f32 - 0.7).normalize();
            let ours = grid.first_hit(o, d, 0.0, 20.0);
            let v = |a: Vec3A| Vector::new(f64::from(a.x), f64::from(a.y), f64::from(a.z));
            let theirs = tree.cast_local_ray_and_get_normal(&Ray::new(v(o), v(d)), 20.0, false);
            match (ours, theirs) {
                (Some((t, k, n)), Some(hit)) => {
                    hits += 1;
                    let toi = hit.time_of_impact as f32;
                    assert!((t - toi).abs() < 1e-4 * (1.0 + toi), "t {t} against {toi}");
                    if k == hit.subshape as usize {
                        same += 1;
                        let face = Vec3A::new(hit.normal.x as f32, hit.normal.y as f32, hit.normal.z as f32);
                        assert!(n.dot(face).abs() > 0.9999, "normal {n} against {face}");
                    }
                }
                (None, None) => {}
                // a ray grazing an edge may meet it in one and slip past it in the other
                (a, b) => {
                    let t = a.map(|h| h.0).or(b.map(|h| h.time_of_impact as f32)).unwrap();
                    let p = o + d * t;
                    let near_edge = (p.x.abs() - 2.0).abs() < 1e-3 || (p.y.abs() - 3.0).abs() < 1e-3;
                    assert!(near_edge, "{a:?} against {b:?} at {p}");
                }
            }
        }
        assert!(hits > 5_000 && same as f64 > 0.999 * hits as f64, "{hits} hits, {same} on the same triangle");
    }
}
