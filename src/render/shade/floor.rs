//! The floor drawn a row at a time. When a plane is the only geom every pixel may see (MuJoCo's
//! scenes: a floor), its hits along a row are a ray parameter per column from one linear form,
//! and so are its checker, its Phong terms and its depth: loops over the row's columns that the
//! compiler vectorises. What differs pixel by pixel (solids in front, shadows, reflections) is
//! then added per pixel as for any geom.

use glam::Vec3A;

use super::{Direct, Geom, Scene, phong};
use crate::model::GeomType;
use crate::model::visual::Builtin;

/// A floor plane and what its pixels share.
pub(in crate::render) struct Floor {
    g: usize,
    /// The colour (rgba × texture) of even and odd checks (the same twice when not checkered).
    colours: [Vec3A; 2],
    /// Checks per metre along the plane's x and y (twice its repeats), or 0 when not checkered.
    checks: [f32; 2],
    /// The world normal.
    normal: Vec3A,
}

impl Floor {
    /// Geom `g` drawn by rows when it is a plane whose texture is flat or checkered (or none).
    pub(super) fn new(geoms: &[Geom], g: usize) -> Option<Floor> {
        let geom = &geoms[g];
        if geom.kind != GeomType::Plane {
            return None;
        }
        let (colours, checks) = match &geom.texture {
            None => ([geom.rgb; 2], [0.0; 2]),
            Some(t) => match t.builtin {
                Builtin::None => ([geom.rgb; 2], [0.0; 2]),
                Builtin::Flat => ([geom.rgb * t.rgb1; 2], [0.0; 2]),
                // one repeat holds 2 × 2 checks, rgb2 on the diagonal through the origin
                Builtin::Checker => ([geom.rgb * t.rgb2, geom.rgb * t.rgb1], [2.0 * t.scale[0], 2.0 * t.scale[1]]),
                Builtin::Gradient => return None,
            },
        };
        Some(Floor { g, colours, checks, normal: geom.rot.z_axis })
    }

    /// The geom.
    pub(super) fn geom(&self) -> usize {
        self.g
    }
}

/// One row of the floor, by column.
pub(in crate::render) struct FloorRow {
    /// Ray parameter of the hit (∞ where the ray misses the floor).
    pub(super) t: Vec<f32>,
    /// The share of odd checks in the pixel's footprint (0 to 1).
    odd: Vec<f32>,
    /// Per directional light, the cosine between the normal and the half vector where the
    /// specular term shows, else 0.
    half: Vec<Vec<f32>>,
    /// The column numbers.
    xs: Vec<f32>,
}

impl FloorRow {
    pub(super) fn new(width: usize, lights: usize) -> FloorRow {
        FloorRow { t: vec![0.0; width], odd: vec![0.0; width], half: vec![vec![0.0; width]; lights], xs: (0..width).map(|x| x as f32).collect() }
    }
}

impl Scene {
    /// Fills `row` for the rays `d0 + x step` of columns x, whose 1 / |d| `inv_len` holds;
    /// `down` is the step to the next row's rays.
    pub(super) fn floor_row(&self, f: &Floor, d0: Vec3A, step: Vec3A, down: Vec3A, inv_len: &[f32], row: &mut FloorRow) {
        let geom = &self.geoms[f.g];
        let o = self.eyes[f.g];
        // the rays in the plane's frame: a + x s; the next row's, a + x s + r
        let (a, s, r) = (geom.rot_t * d0, geom.rot_t * step, geom.rot_t * down);
        let (near, far) = (self.near, self.far);
        let (sx, sy) = (geom.size[0], geom.size[1]);
        let [cx, cy] = f.checks;
        // branch-free bodies over equal slices (`&`, not `&&`; float floors), so that the loops
        // vectorise
        for ((t_out, odd), &xf) in row.t.iter_mut().zip(row.odd.iter_mut()).zip(&row.xs) {
            let (dx, dy, dz) = (a.x + xf * s.x, a.y + xf * s.y, a.z + xf * s.z);
            // seen from its front only, within its half-sizes where they are positive
            let t = -o.z / dz;
            let (px, py) = (o.x + t * dx, o.y + t * dy);
            let inside = (o.z > 0.0) & (dz < 0.0) & (t >= near) & (t < far) & ((sx <= 0.0) | (px.abs() <= sx)) & ((sy <= 0.0) | (py.abs() <= sy));
            *t_out = if inside { t } else { f32::INFINITY };
            // the footprint: how far the hit moves a column right and a row down, in checks
            let (sz, rz) = (s.z / dz, r.z / dz);
            let wx = cx * (t * (s.x - dx * sz)).abs() + cx * (t * (r.x - dx * rz)).abs();
            let wy = cy * (t * (s.y - dy * sz)).abs() + cy * (t * (r.y - dy * rz)).abs();
            *odd = odd_share(px * cx, py * cy, wx, wy);
        }
        // Phong: n·h and |h|² of h = l + v, v = −d / |d|, are linear in d times 1 / |d|
        let n = f.normal;
        let (nd0, nds) = (n.dot(d0), n.dot(step));
        for (l, half) in self.directional.iter().zip(row.half.iter_mut()) {
            if geom.specular <= 0.0 {
                half.fill(0.0);
                continue;
            }
            let (nl, ld0, lds) = (n.dot(l.to_light), l.to_light.dot(d0), l.to_light.dot(step));
            let cut2 = geom.spec_cut * geom.spec_cut;
            for ((h, &inv), &xf) in half.iter_mut().zip(inv_len).zip(&row.xs) {
                let nh = nl - (nd0 + xf * nds) * inv;
                let h2 = 2.0 - 2.0 * (ld0 + xf * lds) * inv;
                let cos = nh / h2.sqrt();
                *h = if (nh > 0.0) & (nh * nh > cut2 * h2) { cos } else { 0.0 };
            }
        }
    }

    /// The colour of the floor hit in column `x` of `row`, along `d` (unit `view` back to the eye).
    pub(super) fn floor_colour(&self, f: &Floor, row: &FloorRow, x: usize, d: Vec3A, view: Vec3A, at: Direct<'_>) -> Vec3A {
        let (g, n) = (f.g, f.normal);
        let geom = &self.geoms[g];
        let t = row.t[x];
        let base = f.colours[0] * (1.0 - row.odd[x]) + f.colours[1] * row.odd[x];
        let p = t * d;
        let lifted = p + self.eps * n;
        let mut c = geom.emission * base + self.ambient * base;
        for (l, half) in self.directional.iter().zip(&row.half) {
            let ndl = n.dot(l.to_light);
            if ndl <= 0.0 || l.shadows.as_ref().is_some_and(|grid| self.shadowed(grid, g, lifted, l.to_light)) {
                continue;
            }
            c += ndl * l.diffuse * base;
            if half[x] > 0.0 {
                c += geom.specular * phong(half[x], geom.exponent, geom.exponent_int) * l.specular;
            }
        }
        if !self.spots.is_empty() {
            c += self.spot_lights(g, p, n, view, base, true);
        }
        c + self.reflection(g, d, view, t, Some(at))
    }
}

/// The share of odd checks (⌊u⌋ + ⌊v⌋ odd) in a `wu` × `wv` box about (u, v), in checks: the
/// box filter of the checker, exact for a box (the ±1 square wave's mean over an interval is the
/// difference of its triangle-wave primitive), so that checks smaller than a pixel blend
/// instead of aliasing into moiré. Below a thousandth of a check the sharp checker.
#[inline]
pub(super) fn odd_share(u: f32, v: f32, wu: f32, wv: f32) -> f32 {
    // the square wave, +1 on even checks; its primitive, 1 − |2 frac(x / 2) − 1|
    let sharp = |x: f32| 1.0 - 2.0 * (floor(x) - 2.0 * floor(0.5 * floor(x)));
    let tri = |x: f32| 1.0 - (2.0 * (0.5 * x - floor(0.5 * x)) - 1.0).abs();
    let mean = |x: f32, w: f32| if w < 1e-3 { sharp(x) } else { (tri(x + 0.5 * w) - tri(x - 0.5 * w)) / w };
    0.5 - 0.5 * mean(u, wu) * mean(v, wv)
}

/// ⌊x⌋ for |x| < 2²², in float operations the compiler vectorises (adding and subtracting
/// 1.5 · 2²³ rounds to the nearest integer).
#[inline]
fn floor(x: f32) -> f32 {
    const ROUND: f32 = 12_582_912.0;
    let r = (x + ROUND) - ROUND;
    if r > x { r - 1.0 } else { r }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::model::Model;
    use crate::render::{CameraChoice, Frame, FreeCamera, Poses, Renderer};

    /// A tilted checker floor that mirrors, a light casting shadows, a headlight with specular, and
    /// solids of each kind standing on it, some reflected, some in front of the camera's near
    /// plane.
    const SCENE: &str = r#"<mujoco>
      <asset>
        <texture name="checks" type="2d" builtin="checker" rgb1="0 0 0" rgb2="0.8 0.8 0.8" width="64" height="64"/>
        <material name="floor" texture="checks" texrepeat="5 5" reflectance="0.3" shininess="0.8" specular="1"/>
      </asset>
      <worldbody>
        <light directional="true" dir="0.3 0.2 -1" pos="0 0 3" castshadow="true"/>
        <geom type="plane" size="6 6 0.1" euler="4 -3 20" material="floor"/>
        <geom type="sphere" pos="0 0 0.3" size="0.3" rgba="1 0 0 1"/>
        <geom type="capsule" fromto="0.8 0.2 0.1 1.2 0.9 0.6" size="0.1" rgba="0 1 0 1"/>
        <geom type="box" pos="-0.9 0.4 0.25" size="0.2 0.3 0.25" euler="0 0 30" rgba="0 0 1 1"/>
        <geom type="cylinder" pos="0.2 -0.9 0.2" size="0.15 0.2" rgba="1 1 0 1"/>
        <geom type="ellipsoid" pos="-0.5 -0.8 0.2" size="0.3 0.15 0.2" rgba="0 1 1 1"/>
      </worldbody>
    </mujoco>"#;

    /// The floor drawn by rows gives the general path's picture: depth to single precision,
    /// colours within a grey level but on a few pixels where a check's edge or a shadow's edge
    /// falls between the two paths' roundings.
    #[test]
    fn the_floor_by_rows_draws_what_the_general_path_draws() {
        let m = Model::from_mjcf(SCENE).unwrap();
        let r = Renderer::new(&m);
        let poses = Poses::new(&m, &m.qpos0);
        let (w, h) = (160, 120);
        for (azimuth, elevation) in [(90.0, -30.0), (10.0, -60.0), (200.0, -15.0)] {
            let cam = CameraChoice::Free(FreeCamera { lookat: DVec3::new(0.0, 0.0, 0.3), distance: 3.0, azimuth, elevation, track_body: None });
            let mut scene = r.scene(&m, &poses, &r.view(&m, &poses, &cam), w, h);
            assert!(scene.floor.is_some(), "the plane is drawn by rows");
            let (mut rgb, mut depth) = (vec![0u8; 3 * w * h], vec![0f32; w * h]);
            scene.draw_rows(0, h, Frame { rgb: &mut rgb, depth: &mut depth });
            scene.floor = None;
            let (mut rgb_g, mut depth_g) = (vec![0u8; 3 * w * h], vec![0f32; w * h]);
            scene.draw_rows(0, h, Frame { rgb: &mut rgb_g, depth: &mut depth_g });
            let depth_err = depth.iter().zip(&depth_g).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
            assert!(depth_err < 1e-6, "depth differs by {depth_err}");
            let off = rgb.iter().zip(&rgb_g).filter(|(a, b)| a.abs_diff(**b) > 1).count();
            assert!(off * 500 < rgb.len(), "{off} of {} colour values differ by more than a grey level", rgb.len());
            assert!(rgb.iter().zip(&rgb_g).filter(|(a, b)| a != b).count() * 20 < rgb.len());
        }
    }
}
