//! Height fields as MuJoCo defines them: an `nrow × ncol` grid of elevations in [0, 1] spanning
//! x ∈ [−size₀, size₀] (columns) and y ∈ [−size₁, size₁] (rows, row 0 at −y), the surface at
//! z = elevation · size₂ over a base down to z = −size₃. Each grid cell is two triangles, each
//! the top of a prism down to the base: the convex pieces collision tests (MuJoCo's method).

use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};

/// A height field.
#[derive(Clone, Debug, PartialEq)]
pub struct HField {
    /// Name.
    pub name: String,
    /// Rows (along y).
    pub nrow: usize,
    /// Columns (along x).
    pub ncol: usize,
    /// Half-extent in x and y, height of elevation 1, depth of the base.
    pub size: [f64; 4],
    /// Elevations in [0, 1], row-major.
    pub data: Vec<f64>,
}

impl HField {
    /// Grid point (r, c) in the height field's frame.
    #[inline]
    pub fn vertex(&self, r: usize, c: usize) -> DVec3 {
        let x = self.size[0] * (2.0 * c as f64 / (self.ncol - 1) as f64 - 1.0);
        let y = self.size[1] * (2.0 * r as f64 / (self.nrow - 1) as f64 - 1.0);
        DVec3::new(x, y, self.data[r * self.ncol + c] * self.size[2])
    }

    /// The two triangles of cell (r, c), counter-clockwise seen from above.
    #[inline]
    pub fn cell_triangles(&self, r: usize, c: usize) -> [[DVec3; 3]; 2] {
        let (a, b, cc, d) = (self.vertex(r, c), self.vertex(r, c + 1), self.vertex(r + 1, c + 1), self.vertex(r + 1, c));
        [[a, b, cc], [a, cc, d]]
    }

    /// The cells (rows, columns) under the rectangle about (x, y) of half-sides `half` (frame
    /// coordinates), clamped to the grid; empty when it lies outside.
    pub fn cells_under(&self, x: f64, y: f64, half: [f64; 2]) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let span = |v: f64, half: f64, size: f64, n: usize| {
            let cell = 2.0 * size / (n - 1) as f64;
            let lo = ((v - half + size) / cell).floor().max(0.0);
            let hi = ((v + half + size) / cell).floor() + 1.0;
            let hi = hi.min((n - 1) as f64);
            if lo >= hi || !lo.is_finite() || !hi.is_finite() { 0..0 } else { lo as usize..hi as usize }
        };
        (span(y, half[1], self.size[1], self.nrow), span(x, half[0], self.size[0], self.ncol))
    }

    /// Every cell's two triangles as vertex indices into the grid (r · ncol + c): the surface.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let mut t = Vec::with_capacity(2 * (self.nrow - 1) * (self.ncol - 1));
        for r in 0..self.nrow - 1 {
            for c in 0..self.ncol - 1 {
                let i = |r: usize, c: usize| (r * self.ncol + c) as u32;
                t.push([i(r, c), i(r, c + 1), i(r + 1, c + 1)]);
                t.push([i(r, c), i(r + 1, c + 1), i(r + 1, c)]);
            }
        }
        t
    }

    /// Largest distance of a point of the field (surface or base) from its origin.
    pub fn rbound(&self) -> f64 {
        DVec3::new(self.size[0], self.size[1], self.size[2].max(self.size[3])).length()
    }
}

/// Elevations scaled to [0, 1] as MuJoCo does (all equal: all zero after the shift).
pub fn normalize(data: &mut [f64]) {
    let (lo, hi) = data.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
    for x in data.iter_mut() {
        *x -= lo;
        if hi - lo > 1e-15 {
            *x /= hi - lo;
        }
    }
}

/// Reads a height-field file: a PNG image (grey levels; colour averaged; the image's top row at
/// +y) or MuJoCo's binary format (int32 nrow, ncol, then nrow × ncol float32). Returns (nrow,
/// ncol, elevations, not yet normalized).
pub fn read_hfield(path: &Path) -> Result<(usize, usize, Vec<f64>)> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| Error::io(format!("cannot read height-field file '{name}'"), &e))?;
    let is_png = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let out = if is_png { png_grid(&bytes) } else { binary_grid(&bytes) };
    out.map_err(|m| Error::Compile(format!("height-field file '{name}': {m}")))
}

fn png_grid(bytes: &[u8]) -> std::result::Result<(usize, usize, Vec<f64>), String> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| format!("not a valid PNG: {e}"))?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("image too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| format!("not a valid PNG: {e}"))?;
    let (w, h) = (info.width as usize, info.height as usize);
    let channels = info.color_type.samples();
    if w < 2 || h < 2 {
        return Err(format!("{w} × {h} pixels; at least 2 × 2 are needed"));
    }
    // grey (with alpha): the first sample; colour: the mean of red, green and blue
    let grey = |p: &[u8]| if channels >= 3 { (f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0 } else { f64::from(p[0]) };
    let mut data = vec![0.0; w * h];
    for r in 0..h {
        for c in 0..w {
            let at = (r * w + c) * channels;
            data[(h - 1 - r) * w + c] = grey(&buf[at..at + channels]);
        }
    }
    Ok((h, w, data))
}

fn binary_grid(bytes: &[u8]) -> std::result::Result<(usize, usize, Vec<f64>), String> {
    let int = |k: usize| bytes.get(4 * k..4 * k + 4).map(|w| i32::from_le_bytes([w[0], w[1], w[2], w[3]]));
    let (Some(nrow), Some(ncol)) = (int(0), int(1)) else { return Err("file too short".into()) };
    if nrow < 2 || ncol < 2 {
        return Err(format!("grid {nrow} × {ncol}; at least 2 × 2 is needed"));
    }
    let (nrow, ncol) = (nrow as usize, ncol as usize);
    if bytes.len() != 8 + 4 * nrow * ncol {
        return Err(format!("size {} bytes, expected {} for a {nrow} × {ncol} grid", bytes.len(), 8 + 4 * nrow * ncol));
    }
    let data: Vec<f64> = bytes[8..].chunks_exact(4).map(|w| f64::from(f32::from_le_bytes([w[0], w[1], w[2], w[3]]))).collect();
    if data.iter().any(|x| !x.is_finite()) {
        return Err("an elevation is not finite".into());
    }
    Ok((nrow, ncol, data))
}
