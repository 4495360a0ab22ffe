//! Shadows of directional lights: the solids' outlines seen along the light, binned in a grid,
//! so that a point's shadow ray is tested only against the solids whose outline holds it.

use glam::Vec3A;

use super::{Geom, Scene};
use crate::model::GeomType;

/// A solid's outline seen along a light, in the plane ⊥ the light: the points within `r` of the
/// segment `centre ± axis`. A capsule's or cylinder's outline lies within its axis's stadium;
/// any other solid's within its bounding sphere's disc (a zero axis).
#[derive(Clone, Copy)]
pub(super) struct Outline {
    centre: (f32, f32),
    axis: (f32, f32),
    /// 1 / |axis|², or 0 for a disc.
    inv_len2: f32,
    r2: f32,
    geom: u32,
}

impl Outline {
    fn new(geom: &Geom, g: u32, (e1, e2): (Vec3A, Vec3A)) -> (Outline, f32) {
        let centre = (geom.pos.dot(e1), geom.pos.dot(e2));
        let (axis, r) = match geom.kind {
            GeomType::Capsule | GeomType::Cylinder => {
                let a = geom.rot.z_axis * geom.size[1];
                ((a.dot(e1), a.dot(e2)), geom.size[0])
            }
            _ => ((0.0, 0.0), geom.rbound),
        };
        let len2 = axis.0 * axis.0 + axis.1 * axis.1;
        let inv_len2 = if len2 > 0.0 { 1.0 / len2 } else { 0.0 };
        (Outline { centre, axis, inv_len2, r2: r * r, geom: g }, r + len2.sqrt())
    }

    /// Whether (u, v) lies in the outline.
    #[inline]
    fn holds(&self, u: f32, v: f32) -> bool {
        let (du, dv) = (u - self.centre.0, v - self.centre.1);
        let s = ((du * self.axis.0 + dv * self.axis.1) * self.inv_len2).clamp(-1.0, 1.0);
        let (eu, ev) = (du - s * self.axis.0, dv - s * self.axis.1);
        eu * eu + ev * ev <= self.r2
    }
}

/// The solids seen along a directional light: a shadow ray from p can meet a solid only if p's
/// projection lies in its outline. The outlines are binned in a uniform grid over the plane ⊥
/// the light.
pub(super) struct ShadowGrid {
    /// The plane's axes.
    axes: (Vec3A, Vec3A),
    /// Lower corner (u, v) of the grid and the inverse of its cell size.
    lo: (f32, f32),
    inv_cell: f32,
    nu: usize,
    nv: usize,
    /// Each cell's outlines.
    cells: Vec<Vec<Outline>>,
}

impl ShadowGrid {
    pub(super) fn new(dir: Vec3A, geoms: &[Geom], solids: &[u32]) -> Option<ShadowGrid> {
        if solids.is_empty() {
            return None;
        }
        let e1 = dir.any_orthonormal_vector();
        let e2 = dir.cross(e1);
        // each outline and the radius of a disc holding it
        let outlines: Vec<(Outline, f32)> = solids.iter().map(|&g| Outline::new(&geoms[g as usize], g, (e1, e2))).collect();
        let (mut lo, mut hi) = ((f32::INFINITY, f32::INFINITY), (f32::NEG_INFINITY, f32::NEG_INFINITY));
        for &(o, r) in &outlines {
            let (u, v) = o.centre;
            lo = (lo.0.min(u - r), lo.1.min(v - r));
            hi = (hi.0.max(u + r), hi.1.max(v + r));
        }
        // about 32 cells along the longer side
        let cell = ((hi.0 - lo.0).max(hi.1 - lo.1) / 32.0).max(1e-9);
        let (nu, nv) = ((((hi.0 - lo.0) / cell) as usize + 1).min(64), (((hi.1 - lo.1) / cell) as usize + 1).min(64));
        let cell = cell.max((hi.0 - lo.0) / nu as f32).max((hi.1 - lo.1) / nv as f32);
        let inv_cell = 1.0 / cell;
        let mut cells = vec![vec![]; nu * nv];
        for &(o, r) in &outlines {
            let (u, v) = o.centre;
            let i0 = (((u - r - lo.0) * inv_cell) as usize).min(nu - 1);
            let i1 = (((u + r - lo.0) * inv_cell) as usize).min(nu - 1);
            let j0 = (((v - r - lo.1) * inv_cell) as usize).min(nv - 1);
            let j1 = (((v + r - lo.1) * inv_cell) as usize).min(nv - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    cells[j * nu + i].push(o);
                }
            }
        }
        Some(ShadowGrid { axes: (e1, e2), lo, inv_cell, nu, nv, cells })
    }

    /// p's projection and the outlines that may hold it.
    #[inline]
    fn at(&self, p: Vec3A) -> (f32, f32, &[Outline]) {
        let (u, v) = (p.dot(self.axes.0), p.dot(self.axes.1));
        let (fu, fv) = ((u - self.lo.0) * self.inv_cell, (v - self.lo.1) * self.inv_cell);
        if !(fu >= 0.0 && fv >= 0.0 && fu < self.nu as f32 && fv < self.nv as f32) {
            return (u, v, &[]);
        }
        (u, v, &self.cells[fv as usize * self.nu + fu as usize])
    }
}


impl Scene {
    /// Whether a solid other than `own` lies between `p` and a directional light whose solids
    /// `grid` holds (a convex geom does not shadow its own lit side).
    pub(super) fn shadowed(&self, grid: &ShadowGrid, own: usize, p: Vec3A, to_light: Vec3A) -> bool {
        let (u, v, outlines) = grid.at(p);
        outlines.iter().any(|o| o.geom as usize != own && o.holds(u, v) && self.meets(o.geom, p, to_light, f32::INFINITY))
    }
}
