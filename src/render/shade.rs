//! One frame's scene and its pixels: primary rays binned by screen tile, shadow and reflection
//! rays, and MuJoCo's lighting (OpenGL's fixed-function model: per light ambient + diffuse
//! max(n·l, 0) + specular max(n·h, 0)^(128 · shininess), times attenuation and the spot factor).

use glam::{DMat3, DVec3};

use super::raycast::{intersect, meets_sphere};
use super::{Frame, Poses, View, TILE};
use crate::model::visual::{Builtin, TextureKind};
use crate::model::{GeomType, Model};

/// A geom as one frame sees it.
struct Geom {
    kind: GeomType,
    size: [f64; 3],
    pos: DVec3,
    /// World axes, transposed: world → geom frame.
    rot_t: DMat3,
    /// Bounding radius (∞ for planes).
    rbound: f64,
    /// The eye in the geom frame.
    eye: DVec3,
    rgb: DVec3,
    emission: f64,
    specular: f64,
    /// Phong exponent.
    exponent: f64,
    reflectance: f64,
    /// Texture colours and the repeat scale of local coordinates, when textured.
    texture: Option<Tex>,
}

#[derive(Clone, Copy)]
struct Tex {
    kind: TextureKind,
    builtin: Builtin,
    rgb1: DVec3,
    rgb2: DVec3,
    /// Repeats per metre along the texture's two axes.
    scale: [f64; 2],
}

/// A light in world.
struct Light {
    directional: bool,
    pos: DVec3,
    dir: DVec3,
    ambient: DVec3,
    diffuse: DVec3,
    specular: DVec3,
    attenuation: [f64; 3],
    cos_cutoff: f64,
    exponent: f64,
    castshadow: bool,
}

/// Everything one frame's pixels read.
pub(super) struct Scene {
    view: View,
    width: usize,
    height: usize,
    /// tan(fovy / 2).
    tan_half: f64,
    near: f64,
    far: f64,
    geoms: Vec<Geom>,
    /// Geoms that may cover any pixel (planes, geoms reaching behind the near plane).
    everywhere: Vec<u32>,
    /// Geoms whose projected bounding sphere meets each tile (row-major tiles).
    tiles: Vec<Vec<u32>>,
    tiles_x: usize,
    /// Geoms that can block light or be reflected (all but planes).
    solids: Vec<u32>,
    lights: Vec<Light>,
    /// Sky colour below (rgb2) and above (rgb1), or black.
    sky: Option<(Builtin, DVec3, DVec3)>,
    /// Offset of shadow and reflection rays off the surface.
    eps: f64,
}

impl Scene {
    pub(super) fn new(m: &Model, poses: &Poses, view: &View, lights: &[(usize, DVec3, DVec3)], extent: f64, width: usize, height: usize) -> Scene {
        let v = &m.vis;
        let mut geoms = Vec::with_capacity(m.ngeom);
        for g in 0..m.ngeom {
            let b = m.geom_body[g];
            let rot = poses.xmat(b) * m.geom_mat[g];
            let pos = poses.geom_xpos(m, g);
            let rot_t = rot.transpose();
            let rgba = v.geom_rgba[g];
            let mat = v.geom_material[g].map(|i| &v.materials[i]);
            let texture = mat.and_then(|mt| {
                let t = &v.textures[mt.texture?];
                // MuJoCo: a 2D texture spans a plane's extent texrepeat times (per metre when
                // texuniform); a cube texture wraps the geom once (per metre when texuniform)
                let size = m.geom_size[g];
                let span = |k: usize| if mt.texuniform || size[k] <= 0.0 { 1.0 } else { 2.0 * size[k] };
                let scale = match t.kind {
                    TextureKind::TwoD => [mt.texrepeat[0] / span(0), mt.texrepeat[1] / span(1)],
                    _ => [mt.texrepeat[0], mt.texrepeat[1]],
                };
                Some(Tex { kind: t.kind, builtin: t.builtin, rgb1: t.rgb1, rgb2: t.rgb2, scale })
            });
            geoms.push(Geom {
                kind: m.geom_type[g],
                size: m.geom_size[g],
                pos,
                rot_t,
                rbound: m.geom_rbound[g],
                eye: rot_t * (view.pos - pos),
                rgb: DVec3::new(rgba[0], rgba[1], rgba[2]),
                emission: mat.map_or(0.0, |mt| mt.emission),
                specular: mat.map_or(0.5, |mt| mt.specular),
                exponent: 128.0 * mat.map_or(0.5, |mt| mt.shininess),
                reflectance: mat.map_or(0.0, |mt| mt.reflectance),
                texture,
            });
        }
        let mut all_lights = Vec::with_capacity(lights.len() + 1);
        if v.head_active {
            all_lights.push(Light {
                directional: true,
                pos: view.pos,
                dir: view.forward,
                ambient: v.head_ambient,
                diffuse: v.head_diffuse,
                specular: v.head_specular,
                attenuation: [1.0, 0.0, 0.0],
                cos_cutoff: -1.0,
                exponent: 0.0,
                castshadow: false,
            });
        }
        for &(i, pos, dir) in lights {
            let l = &v.lights[i];
            all_lights.push(Light {
                directional: l.directional,
                pos,
                dir,
                ambient: l.ambient,
                diffuse: l.diffuse,
                specular: l.specular,
                attenuation: l.attenuation,
                cos_cutoff: l.cos_cutoff,
                exponent: l.exponent,
                castshadow: l.castshadow,
            });
        }
        let sky = v.skybox.map(|i| {
            let t = &v.textures[i];
            (t.builtin, t.rgb1, t.rgb2)
        });
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let mut s = Scene {
            view: *view,
            width,
            height,
            tan_half: (0.5 * view.fovy.to_radians()).tan(),
            near: v.znear * extent,
            far: v.zfar * extent,
            solids: (0..m.ngeom as u32).filter(|&g| m.geom_type[g as usize] != GeomType::Plane).collect(),
            geoms,
            everywhere: vec![],
            tiles: vec![vec![]; tiles_x * tiles_y],
            tiles_x,
            lights: all_lights,
            sky,
            eps: 1e-6 * extent,
        };
        s.bin();
        s
    }

    /// Puts each geom in the tiles its projected bounding sphere can cover.
    fn bin(&mut self) {
        let aspect = self.width as f64 / self.height as f64;
        let (sx, sy) = (self.tan_half * aspect, self.tan_half);
        let tiles_y = self.height.div_ceil(TILE);
        for (g, geom) in self.geoms.iter().enumerate() {
            let g = g as u32;
            if !geom.rbound.is_finite() {
                self.everywhere.push(g);
                continue;
            }
            let c = geom.pos - self.view.pos;
            let (x, y, z) = (c.dot(self.view.right), c.dot(self.view.up), c.dot(self.view.forward));
            let r = geom.rbound;
            if z + r < self.near {
                continue; // wholly behind the near plane
            }
            if z - r <= self.near.max(1e-9) {
                self.everywhere.push(g);
                continue;
            }
            // bounds of x/z and y/z over the sphere, conservative
            let span = |a: f64| {
                let lo = if a - r <= 0.0 { (a - r) / (z - r) } else { (a - r) / (z + r) };
                let hi = if a + r >= 0.0 { (a + r) / (z - r) } else { (a + r) / (z + r) };
                (lo, hi)
            };
            let ((x0, x1), (y0, y1)) = (span(x), span(y));
            // screen: column = (x/z / sx + 1) W / 2, row = (1 − y/z / sy) H / 2
            let col = |u: f64| (u / sx + 1.0) * 0.5 * self.width as f64;
            let row = |u: f64| (1.0 - u / sy) * 0.5 * self.height as f64;
            let (c0, c1, r0, r1) = (col(x0), col(x1), row(y1), row(y0));
            if c1 < 0.0 || r1 < 0.0 || c0 > self.width as f64 || r0 > self.height as f64 {
                continue;
            }
            let clamp = |v: f64, n: usize| ((v.max(0.0) as usize) / TILE).min(n - 1);
            let (tx0, tx1) = (clamp(c0, self.tiles_x), clamp(c1, self.tiles_x));
            let (ty0, ty1) = (clamp(r0, tiles_y), clamp(r1, tiles_y));
            for ty in ty0..=ty1 {
                for tx in tx0..=tx1 {
                    self.tiles[ty * self.tiles_x + tx].push(g);
                }
            }
        }
    }

    /// Draws rows `y0..y1` into the band `out` (its rows start at `y0`).
    pub(super) fn draw_rows(&self, m: &Model, y0: usize, y1: usize, out: Frame<'_>) {
        let _ = m;
        let (w, h) = (self.width as f64, self.height as f64);
        let aspect = w / h;
        let zbuf = |z: f64| (self.far * (z - self.near) / ((self.far - self.near) * z)) as f32;
        for y in y0..y1 {
            let sy = (1.0 - 2.0 * (y as f64 + 0.5) / h) * self.tan_half;
            for x in 0..self.width {
                let sx = (2.0 * (x as f64 + 0.5) / w - 1.0) * self.tan_half * aspect;
                let d = (self.view.forward + sx * self.view.right + sy * self.view.up).normalize();
                let cos = d.dot(self.view.forward);
                let tile = &self.tiles[(y / TILE) * self.tiles_x + x / TILE];
                let hit = self.first_hit(self.everywhere.iter().chain(tile), self.view.pos, d, self.near / cos, self.far / cos, true);
                let k = (y - y0) * self.width + x;
                let (rgb, z) = match hit {
                    Some((g, t, n)) => (self.shade(g, self.view.pos, d, t, n, true), zbuf(t * cos)),
                    None => (self.sky(d), 1.0),
                };
                if !out.rgb.is_empty() {
                    for c in 0..3 {
                        out.rgb[3 * k + c] = (rgb[c].clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
                    }
                }
                if !out.depth.is_empty() {
                    out.depth[k] = z;
                }
            }
        }
    }

    /// The nearest hit among `candidates` in `[t0, t1)`: geom, ray parameter and world normal.
    /// From the eye (`primary`) the geoms' eye positions are precomputed.
    fn first_hit<'a>(&self, candidates: impl Iterator<Item = &'a u32>, o: DVec3, d: DVec3, t0: f64, mut t1: f64, primary: bool) -> Option<(usize, f64, DVec3)> {
        let mut best = None;
        for &g in candidates {
            let geom = &self.geoms[g as usize];
            if !primary && !meets_sphere(geom.pos, geom.rbound, o, d, t0, t1) {
                continue;
            }
            let ol = if primary { geom.eye } else { geom.rot_t * (o - geom.pos) };
            if let Some((t, n)) = intersect(geom.kind, &geom.size, ol, geom.rot_t * d, t0, t1) {
                t1 = t;
                best = Some((g as usize, t, n));
            }
        }
        best.map(|(g, t, n)| (g, t, self.geoms[g].rot_t.transpose() * n))
    }

    /// Whether anything solid lies on the segment from `p` along unit `l` up to `t1`.
    fn blocked(&self, p: DVec3, l: DVec3, t1: f64) -> bool {
        self.solids.iter().any(|&g| {
            let geom = &self.geoms[g as usize];
            meets_sphere(geom.pos, geom.rbound, p, l, 0.0, t1)
                && intersect(geom.kind, &geom.size, geom.rot_t * (p - geom.pos), geom.rot_t * l, 0.0, t1).is_some()
        })
    }

    /// Colour of geom `g` hit at `o + t d` with world normal `n`; `direct` adds shadows and
    /// reflections (off for what a mirror shows).
    fn shade(&self, g: usize, o: DVec3, d: DVec3, t: f64, n: DVec3, direct: bool) -> DVec3 {
        let geom = &self.geoms[g];
        let p = o + t * d;
        let n = if n.dot(d) > 0.0 { -n } else { n };
        let base = geom.rgb * geom.texture.map_or(DVec3::ONE, |tex| texel(&tex, geom.rot_t * (p - geom.pos), geom.rot_t * n));
        let view = -d;
        let mut c = geom.emission * base;
        let lifted = p + self.eps * n;
        for l in &self.lights {
            let (to_light, dist) = if l.directional { (-l.dir, f64::INFINITY) } else {
                let v = l.pos - p;
                let dist = v.length();
                (v / dist, dist)
            };
            let mut k = 1.0;
            if !l.directional {
                let [a0, a1, a2] = l.attenuation;
                k /= (a0 + a1 * dist + a2 * dist * dist).max(1e-12);
                let cos = -to_light.dot(l.dir);
                k *= if cos < l.cos_cutoff { 0.0 } else { cos.max(0.0).powf(l.exponent) };
            }
            if k == 0.0 {
                continue;
            }
            c += k * l.ambient * base;
            let ndl = n.dot(to_light);
            if ndl <= 0.0 || (direct && l.castshadow && self.blocked(lifted, to_light, dist)) {
                continue;
            }
            c += k * ndl * l.diffuse * base;
            let ndh = n.dot((to_light + view).normalize());
            if ndh > 0.0 && geom.specular > 0.0 {
                c += k * geom.specular * ndh.powf(geom.exponent) * l.specular;
            }
        }
        if direct && geom.reflectance > 0.0 {
            let r = d - 2.0 * d.dot(n) * n;
            if let Some((h, tr, nr)) = self.first_hit(self.solids.iter(), lifted, r, 0.0, self.far, false) {
                c += geom.reflectance * self.shade(h, lifted, r, tr, nr, false);
            }
        }
        c
    }

    /// The skybox in direction `d`: a gradient from rgb2 straight down to rgb1 straight up.
    fn sky(&self, d: DVec3) -> DVec3 {
        match self.sky {
            None => DVec3::ZERO,
            Some((Builtin::Gradient, top, bottom)) => bottom + (top - bottom) * (0.5 * (1.0 + d.z)),
            Some((_, rgb1, _)) => rgb1,
        }
    }
}

/// Texture colour at local point `p` with local normal `n`: 2D textures tile the geom's xy plane,
/// cube textures are projected along the normal's dominant axis.
fn texel(t: &Tex, p: DVec3, n: DVec3) -> DVec3 {
    let (u, v) = match t.kind {
        TextureKind::TwoD => (p.x * t.scale[0], p.y * t.scale[1]),
        _ => {
            let a = n.abs();
            let (u, v) = if a.x >= a.y && a.x >= a.z { (p.y, p.z) } else if a.y >= a.z { (p.x, p.z) } else { (p.x, p.y) };
            (u * t.scale[0], v * t.scale[1])
        }
    };
    match t.builtin {
        Builtin::None => DVec3::ONE,
        Builtin::Flat => t.rgb1,
        Builtin::Checker => {
            // one repeat holds 2 × 2 checks, rgb2 on the diagonal through the origin
            let odd = ((2.0 * u).floor() as i64 + (2.0 * v).floor() as i64) & 1 == 1;
            if odd { t.rgb1 } else { t.rgb2 }
        }
        Builtin::Gradient => t.rgb2 + (t.rgb1 - t.rgb2) * (v - v.floor()),
    }
}
