//! A ray's first hit on a height field's top surface by walking its grid: the ray's footprint
//! crosses blocks of cells in order of distance (Amanatides & Woo 1987, *A Fast Voxel Traversal
//! Algorithm for Ray Tracing*), a block whose highest point the ray passes above is skipped, and
//! in the others the cells are walked the same way, each cell's two triangles tested
//! (Möller & Trumbore 1997). The first cell with a hit holds the nearest. A tree over the
//! triangles (`surface.rs`) costs a log of the triangle count per ray and a rebuild whenever a
//! world draws new terrain; this costs the cells the ray passes near the surface.

use glam::Vec3A;

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
        let (ta, tb) = clip(o, d, t0, t1, [self.x0, self.y0, self.zmin], [x1, y1, self.zmax])?;
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
            if let Some(t) = triangle(o, d, u, v, w).filter(|&t| t >= t0 && t < t1 && best.is_none_or(|(tb, _, _)| t < tb)) {
                best = Some((t, first + k, (v - u).cross(w - u).normalize_or_zero()));
            }
        }
        best
    }
}

/// The part of [t0, t1) in which `o + t d` is inside the box [lo, hi] (slabs), if any.
fn clip(o: Vec3A, d: Vec3A, t0: f32, t1: f32, lo: [f32; 3], hi: [f32; 3]) -> Option<(f32, f32)> {
    let (mut ta, mut tb) = (t0, t1);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        ta = ta.max(u.min(v));
        tb = tb.min(u.max(v));
    }
    (ta <= tb).then_some((ta, tb))
}

/// Visits the cells of an n.0 × n.1 grid (corner `origin`, cell size `size`) that the ray's
/// footprint crosses for t in [ta, tb], nearest first, each with the t it enters and leaves
/// by, until `visit` returns a value.
fn walk<R>(n: (usize, usize), origin: (f32, f32), size: (f32, f32), o: Vec3A, d: Vec3A, (ta, tb): (f32, f32), mut visit: impl FnMut(usize, usize, f32, f32) -> Option<R>) -> Option<R> {
    let start = |k: usize, n: usize, origin: f32, size: f32| (((o[k] + d[k] * ta - origin) / size).floor().max(0.0) as usize).min(n - 1);
    let (mut i, mut j) = (start(0, n.0, origin.0, size.0), start(1, n.1, origin.1, size.1));
    // the t at which the footprint crosses the next line of each axis, and between lines
    let next = |k: usize, cell: usize, origin: f32, size: f32| match d[k] {
        v if v > 0.0 => (origin + size * (cell + 1) as f32 - o[k]) / v,
        v if v < 0.0 => (origin + size * cell as f32 - o[k]) / v,
        _ => f32::INFINITY,
    };
    let (mut nx, mut ny) = (next(0, i, origin.0, size.0), next(1, j, origin.1, size.1));
    let (sx, sy) = (size.0 / d.x.abs(), size.1 / d.y.abs());
    let mut t = ta;
    loop {
        let out = nx.min(ny).min(tb);
        if let Some(r) = visit(i, j, t, out) {
            return Some(r);
        }
        if out >= tb {
            return None;
        }
        t = out;
        if nx <= ny {
            i = match (d.x > 0.0, i) {
                (true, i) if i + 1 < n.0 => i + 1,
                (false, i) if i > 0 => i - 1,
                _ => return None,
            };
            nx += sx;
        } else {
            j = match (d.y > 0.0, j) {
                (true, j) if j + 1 < n.1 => j + 1,
                (false, j) if j > 0 => j - 1,
                _ => return None,
            };
            ny += sy;
        }
    }
}

/// The distance along `o + t d` to triangle (a, b, c), from either side (Möller & Trumbore 1997).
#[inline]
fn triangle(o: Vec3A, d: Vec3A, a: Vec3A, b: Vec3A, c: Vec3A) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    // parallel to the plane (to rounding)
    if det * det <= f32::EPSILON * f32::EPSILON * e1.length_squared() * e2.length_squared() * d.length_squared() {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
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
