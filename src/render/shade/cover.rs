//! Which solids each pixel of a row may see. A solid's bounding sphere covers the columns of a
//! row whose rays meet it, one interval found from a quadratic; the row is cut into runs of
//! columns that see the same solids, so that a pixel tests only the solids over it.

use glam::Vec3A;

/// A frame's geoms sorted by where they may show.
pub(super) struct Bins {
    /// Geoms that may cover any pixel (planes, geoms reaching behind the near plane).
    pub(super) everywhere: Vec<u32>,
    /// The bounding spheres of the others, wholly beyond the near plane.
    pub(super) spheres: Vec<Sphere>,
}

/// A geom's bounding sphere (relative to the eye) and the rows it may cover.
pub(super) struct Sphere {
    pub(super) g: u32,
    pub(super) centre: Vec3A,
    pub(super) r: f32,
    /// First and last row, rounded outwards.
    pub(super) rows: (usize, usize),
}

/// The solids each column of one row may see.
pub(super) struct RowCover {
    /// Each run's solids, one run after another.
    ids: Vec<u32>,
    /// Each run's range in `ids`.
    runs: Vec<(u32, u32)>,
    /// Each column's run.
    run_of: Vec<u32>,
    /// Scratch: where spheres start (true) and end covering, by column; the solids in cover.
    events: Vec<(usize, bool, u32)>,
    active: Vec<u32>,
}

impl RowCover {
    /// Empty, for rows of `width` columns.
    pub(super) fn new(width: usize) -> RowCover {
        RowCover { ids: vec![], runs: vec![], run_of: vec![0; width], events: vec![], active: vec![] }
    }

    /// The solids of `bins` whose bounding spheres the rays `d0 + x step` of row `y` (column x)
    /// meet. A ray meets the sphere (c, r) when r²|d|² ≥ |c × d|², a quadratic in x; as every
    /// ray looks forward and the sphere lies beyond the near plane, the columns are one interval
    /// (widened by a column for rounding).
    pub(super) fn build(&mut self, bins: &Bins, y: usize, d0: Vec3A, step: Vec3A) {
        let width = self.run_of.len();
        let (bb, bs, ss) = (d0.length_squared(), d0.dot(step), step.length_squared());
        self.events.clear();
        for s in bins.spheres.iter().filter(|s| s.rows.0 <= y && y <= s.rows.1) {
            let (cb, cs) = (s.centre.cross(d0), s.centre.cross(step));
            let r2 = s.r * s.r;
            // a x² + 2 b x + cc ≥ 0
            let (a, b, cc) = (r2 * ss - cs.length_squared(), r2 * bs - cb.dot(cs), r2 * bb - cb.length_squared());
            let disc = b * b - a * cc;
            let (x0, x1) = if a >= 0.0 {
                (0.0, width as f32) // not an ellipse in single precision: every column
            } else if disc < 0.0 {
                continue;
            } else {
                // a < 0: between the roots (−b ± √disc) / a
                ((-b + disc.sqrt()) / a - 1.0, (-b - disc.sqrt()) / a + 1.0)
            };
            if x1 < 0.0 || x0 >= width as f32 {
                continue;
            }
            let (x0, x1) = (x0.max(0.0) as usize, (x1 as usize).min(width - 1));
            self.events.push((x0, true, s.g));
            self.events.push((x1 + 1, false, s.g));
        }
        self.events.sort_unstable_by_key(|e| e.0);
        self.ids.clear();
        self.runs.clear();
        self.active.clear();
        let (mut x, mut e) = (0, 0);
        while x < width {
            while e < self.events.len() && self.events[e].0 <= x {
                let (_, starts, g) = self.events[e];
                if starts {
                    self.active.push(g);
                } else {
                    self.active.retain(|&a| a != g);
                }
                e += 1;
            }
            let next = self.events.get(e).map_or(width, |ev| ev.0.min(width));
            let start = self.ids.len() as u32;
            self.ids.extend_from_slice(&self.active);
            self.runs.push((start, self.ids.len() as u32));
            self.run_of[x..next].fill(self.runs.len() as u32 - 1);
            x = next;
        }
    }

    /// The solids column `x` may see.
    #[inline]
    pub(super) fn at(&self, x: usize) -> &[u32] {
        let (a, b) = self.runs[self.run_of[x] as usize];
        &self.ids[a as usize..b as usize]
    }
}
