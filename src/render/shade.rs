//! One frame's scene and its pixels: primary rays binned by screen tile, shadow and reflection
//! rays, and MuJoCo's lighting (OpenGL's fixed-function model: per light ambient + diffuse
//! max(n·l, 0) + specular max(n·h, 0)^(128 · shininess), times attenuation and the spot factor).

use glam::{DMat3, DVec3};

use super::raycast::{intersect, meets_sphere, plane};
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
    /// World axes: geom frame → world.
    rot: DMat3,
    /// Bounding radius (∞ for planes).
    rbound: f64,
    rgb: DVec3,
    emission: f64,
    specular: f64,
    /// Phong exponent.
    exponent: f64,
    /// The exponent when it is a small integer (the usual case): powers by squaring.
    exponent_int: Option<u32>,
    /// Below this n·h the specular term is under half a grey level: skipped.
    spec_cut: f64,
    reflectance: f64,
    /// Index into `Scene::mirrors` of a plane that reflects.
    mirror: Option<usize>,
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
    /// A 2D texture's axes in world, times `scale`: its coordinates are (p − pos)·axes.
    axes: [DVec3; 2],
}

/// Geoms binned by the screen tiles (`TILE` pixels square, row-major) they may cover.
struct Bins {
    /// Geoms that may cover any pixel (planes, geoms reaching behind the near plane).
    everywhere: Vec<u32>,
    /// Each tile's geoms.
    tiles: Vec<Vec<u32>>,
}

/// What a mirroring plane shows: the scene seen from the eye's mirror image. The reflected ray
/// from a point p the eye sees at e + t d is the mirrored eye's ray e' + s d' beyond s = t.
struct Mirror {
    /// The solids whose mirrored bounding spheres may cover each screen tile.
    bins: Bins,
    /// The mirrored eye in each geom's frame (ngeom; planes unused).
    eyes: Vec<DVec3>,
    /// Mirror image of a direction: d − 2 (d·n) n.
    normal: DVec3,
    /// The mirrored eye in world.
    eye: DVec3,
}

/// A directional light in world (the headlight is one).
struct DirLight {
    /// Unit direction towards the light.
    to_light: DVec3,
    diffuse: DVec3,
    specular: DVec3,
    /// The solids as seen along the light, when it casts shadows.
    shadows: Option<ShadowGrid>,
}

/// A point or spot light in world.
struct SpotLight {
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

/// A solid seen along a light: centre (u, v) in the plane ⊥ the light, squared bounding radius,
/// geom.
type Disc = (f64, f64, f64, u32);

/// The solids seen along a directional light: each bounding sphere is a disc in a plane ⊥ the
/// light, and a shadow ray from p can meet the solid only if p's projection lies in its disc.
/// The discs are binned in a uniform grid over that plane.
struct ShadowGrid {
    /// The plane's axes.
    axes: (DVec3, DVec3),
    /// Lower corner (u, v) of the grid and its cell size.
    lo: (f64, f64),
    cell: f64,
    nu: usize,
    nv: usize,
    /// Each cell's discs: centre (u, v), squared radius, geom.
    cells: Vec<Vec<Disc>>,
}

impl ShadowGrid {
    fn new(dir: DVec3, geoms: &[Geom], solids: &[u32]) -> Option<ShadowGrid> {
        if solids.is_empty() {
            return None;
        }
        let e1 = dir.any_orthonormal_vector();
        let e2 = dir.cross(e1);
        let discs: Vec<Disc> =
            solids.iter().map(|&g| (geoms[g as usize].pos.dot(e1), geoms[g as usize].pos.dot(e2), geoms[g as usize].rbound, g)).collect();
        let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
        for &(u, v, r, _) in &discs {
            lo = (lo.0.min(u - r), lo.1.min(v - r));
            hi = (hi.0.max(u + r), hi.1.max(v + r));
        }
        // about 32 cells along the longer side
        let cell = ((hi.0 - lo.0).max(hi.1 - lo.1) / 32.0).max(1e-9);
        let (nu, nv) = ((((hi.0 - lo.0) / cell) as usize + 1).min(64), (((hi.1 - lo.1) / cell) as usize + 1).min(64));
        let cell = cell.max((hi.0 - lo.0) / nu as f64).max((hi.1 - lo.1) / nv as f64);
        let mut cells = vec![vec![]; nu * nv];
        for &(u, v, r, g) in &discs {
            let i0 = (((u - r - lo.0) / cell) as usize).min(nu - 1);
            let i1 = (((u + r - lo.0) / cell) as usize).min(nu - 1);
            let j0 = (((v - r - lo.1) / cell) as usize).min(nv - 1);
            let j1 = (((v + r - lo.1) / cell) as usize).min(nv - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    cells[j * nu + i].push((u, v, r * r, g));
                }
            }
        }
        Some(ShadowGrid { axes: (e1, e2), lo, cell, nu, nv, cells })
    }

    /// The discs that may hold p's projection.
    #[inline]
    fn at(&self, p: DVec3) -> (f64, f64, &[Disc]) {
        let (u, v) = (p.dot(self.axes.0), p.dot(self.axes.1));
        let (fu, fv) = ((u - self.lo.0) / self.cell, (v - self.lo.1) / self.cell);
        if !(fu >= 0.0 && fv >= 0.0 && fu < self.nu as f64 && fv < self.nv as f64) {
            return (u, v, &[]);
        }
        (u, v, &self.cells[fv as usize * self.nu + fu as usize])
    }
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
    /// The geoms each screen tile may show.
    primary: Bins,
    /// The eye in each geom's frame.
    eyes: Vec<DVec3>,
    /// Each mirroring plane's reflection (`Geom::mirror`).
    mirrors: Vec<Mirror>,
    /// Tiles per image row.
    tiles_x: usize,
    /// Geoms that can block light or be reflected (all but planes).
    solids: Vec<u32>,
    /// The directional lights' summed ambient colour (it does not depend on the surface).
    ambient: DVec3,
    directional: Vec<DirLight>,
    spots: Vec<SpotLight>,
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
            let exponent = 128.0 * mat.map_or(0.5, |mt| mt.shininess);
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
                Some(Tex { kind: t.kind, builtin: t.builtin, rgb1: t.rgb1, rgb2: t.rgb2, scale, axes: [rot.x_axis * scale[0], rot.y_axis * scale[1]] })
            });
            geoms.push(Geom {
                kind: m.geom_type[g],
                size: m.geom_size[g],
                pos,
                rot_t,
                rot,
                rbound: m.geom_rbound[g],
                rgb: DVec3::new(rgba[0], rgba[1], rgba[2]),
                emission: mat.map_or(0.0, |mt| mt.emission),
                specular: mat.map_or(0.5, |mt| mt.specular),
                exponent,
                exponent_int: (exponent == exponent.trunc() && (0.0..=1024.0).contains(&exponent)).then_some(exponent as u32),
                spec_cut: if exponent > 0.0 { (1.0_f64 / 512.0).powf(1.0 / exponent) } else { 0.0 },
                reflectance: mat.map_or(0.0, |mt| mt.reflectance),
                mirror: None,
                texture,
            });
        }
        let solids: Vec<u32> = (0..m.ngeom as u32).filter(|&g| geoms[g as usize].rbound.is_finite()).collect();
        let (mut ambient, mut directional, mut spots) = (DVec3::ZERO, vec![], vec![]);
        if v.head_active {
            ambient += v.head_ambient;
            directional.push(DirLight { to_light: -view.forward, diffuse: v.head_diffuse, specular: v.head_specular, shadows: None });
        }
        for &(i, pos, dir) in lights {
            let l = &v.lights[i];
            if l.directional {
                ambient += l.ambient;
                let shadows = if l.castshadow { ShadowGrid::new(dir, &geoms, &solids) } else { None };
                directional.push(DirLight { to_light: -dir, diffuse: l.diffuse, specular: l.specular, shadows });
            } else {
                spots.push(SpotLight {
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
        }
        let sky = v.skybox.map(|i| {
            let t = &v.textures[i];
            (t.builtin, t.rgb1, t.rgb2)
        });
        let tiles_x = width.div_ceil(TILE);
        let eyes = geoms.iter().map(|g| g.rot_t * (view.pos - g.pos)).collect();
        let mut s = Scene {
            view: *view,
            width,
            height,
            tan_half: (0.5 * view.fovy.to_radians()).tan(),
            near: v.znear * extent,
            far: v.zfar * extent,
            solids,
            geoms,
            primary: Bins { everywhere: vec![], tiles: vec![] },
            eyes,
            mirrors: vec![],
            tiles_x,
            ambient,
            directional,
            spots,
            sky,
            eps: 1e-6 * extent,
        };
        s.primary = s.bin(s.geoms.iter().enumerate().map(|(g, geom)| (g as u32, geom.pos, geom.rbound)));
        for p in 0..s.geoms.len() {
            if s.geoms[p].kind != GeomType::Plane || s.geoms[p].reflectance <= 0.0 {
                continue;
            }
            let (origin, normal) = (s.geoms[p].pos, s.geoms[p].rot_t.row(2));
            let mirrored = s.solids.iter().map(|&g| {
                let c = s.geoms[g as usize].pos;
                (g, c - 2.0 * (c - origin).dot(normal) * normal, s.geoms[g as usize].rbound)
            });
            let bins = s.bin(mirrored);
            let eye = s.view.pos - 2.0 * (s.view.pos - origin).dot(normal) * normal;
            let eyes = s.geoms.iter().map(|g| g.rot_t * (eye - g.pos)).collect();
            s.geoms[p].mirror = Some(s.mirrors.len());
            s.mirrors.push(Mirror { bins, eyes, normal, eye });
        }
        s
    }

    /// The geoms whose bounding spheres (`g`, centre, radius) can cover each screen tile: the
    /// ones that may cover any pixel, and each tile's list.
    fn bin(&self, spheres: impl Iterator<Item = (u32, DVec3, f64)>) -> Bins {
        let aspect = self.width as f64 / self.height as f64;
        let (sx, sy) = (self.tan_half * aspect, self.tan_half);
        let tiles_y = self.height.div_ceil(TILE);
        let mut bins = Bins { everywhere: vec![], tiles: vec![vec![]; self.tiles_x * tiles_y] };
        for (g, centre, r) in spheres {
            if !r.is_finite() {
                bins.everywhere.push(g);
                continue;
            }
            let c = centre - self.view.pos;
            let (x, y, z) = (c.dot(self.view.right), c.dot(self.view.up), c.dot(self.view.forward));
            if z + r < self.near {
                continue; // wholly behind the near plane
            }
            if z - r <= self.near.max(1e-9) {
                bins.everywhere.push(g);
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
                    bins.tiles[ty * self.tiles_x + tx].push(g);
                }
            }
        }
        bins
    }

    /// Draws rows `y0..y1` into the band `out` (its rows start at `y0`).
    pub(super) fn draw_rows(&self, y0: usize, y1: usize, out: Frame<'_>) {
        let (w, h) = (self.width as f64, self.height as f64);
        let want_rgb = !out.rgb.is_empty();
        let want_depth = !out.depth.is_empty();
        // z-buffer value f (z − n) / ((f − n) z) = a − b / z
        let (a, b) = (self.far / (self.far - self.near), self.far * self.near / (self.far - self.near));
        // each column's offset along `right`, so that a ray is a row's base plus a column's offset
        let (sx, sy) = (2.0 * self.tan_half * w / h / w, 2.0 * self.tan_half / h);
        let columns: Vec<DVec3> = (0..self.width).map(|x| ((x as f64 + 0.5) * sx - self.tan_half * w / h) * self.view.right).collect();
        for y in y0..y1 {
            // unnormalised rays with unit depth along the view axis, so that t is that depth
            let base = self.view.forward + (self.tan_half - (y as f64 + 0.5) * sy) * self.view.up;
            let tiles = &self.primary.tiles[(y / TILE) * self.tiles_x..];
            for (x, col) in columns.iter().enumerate() {
                let d = base + *col;
                let tile = x / TILE;
                let candidates = self.primary.everywhere.iter().chain(&tiles[tile]);
                let hit = self.first_hit(candidates, &self.eyes, d, self.near, self.far);
                let k = (y - y0) * self.width + x;
                if want_rgb {
                    let rgb = match hit {
                        Some((g, t, n)) => self.shade(g, self.view.pos, d, t, n, Some((y / TILE) * self.tiles_x + tile)),
                        None => self.sky(d),
                    };
                    for c in 0..3 {
                        out.rgb[3 * k + c] = (rgb[c].clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
                    }
                }
                if want_depth {
                    out.depth[k] = hit.map_or(1.0, |(_, t, _)| (a - b / t) as f32);
                }
            }
        }
    }

    /// The nearest hit among `candidates` in `[t0, t1)` of the ray from the point whose position
    /// in each geom's frame `eyes` holds, along `d`: geom, ray parameter and world normal.
    fn first_hit<'a>(&self, candidates: impl Iterator<Item = &'a u32>, eyes: &[DVec3], d: DVec3, t0: f64, mut t1: f64) -> Option<(usize, f64, DVec3)> {
        let mut best = None;
        for &g in candidates {
            let geom = &self.geoms[g as usize];
            let ol = eyes[g as usize];
            let dl = geom.rot_t * d;
            if geom.kind == GeomType::Plane {
                // no bounding sphere to test against
                if let Some((t, n)) = plane(&geom.size, ol, dl, t0, t1) {
                    t1 = t;
                    best = Some((g as usize, t, n));
                }
                continue;
            }
            // the ray's line misses the bounding sphere: |o × d|² > r² |d|²
            if ol.cross(dl).length_squared() > geom.rbound * geom.rbound * dl.length_squared() {
                continue;
            }
            if let Some((t, n)) = intersect(geom.kind, &geom.size, ol, dl, t0, t1) {
                t1 = t;
                best = Some((g as usize, t, n));
            }
        }
        best.map(|(g, t, n)| (g, t, self.geoms[g].rot * n))
    }

    /// Whether geom `g` lies on the segment from `p` along `l` up to `t1`.
    #[inline]
    fn meets(&self, g: u32, p: DVec3, l: DVec3, t1: f64) -> bool {
        let geom = &self.geoms[g as usize];
        intersect(geom.kind, &geom.size, geom.rot_t * (p - geom.pos), geom.rot_t * l, 0.0, t1).is_some()
    }

    /// Whether anything solid lies between `p` and a directional light whose solids `grid` holds.
    fn shadowed(&self, grid: &ShadowGrid, p: DVec3, to_light: DVec3) -> bool {
        let (u, v, discs) = grid.at(p);
        discs.iter().any(|&(cu, cv, r2, g)| (u - cu) * (u - cu) + (v - cv) * (v - cv) <= r2 && self.meets(g, p, to_light, f64::INFINITY))
    }

    /// Whether anything solid lies on the segment from `p` along unit `l` up to `t1`.
    fn blocked(&self, p: DVec3, l: DVec3, t1: f64) -> bool {
        self.solids.iter().any(|&g| {
            let geom = &self.geoms[g as usize];
            meets_sphere(geom.pos, geom.rbound, p, l, 0.0, t1) && self.meets(g, p, l, t1)
        })
    }

    /// Colour of geom `g` hit at `o + t d` with world normal `n`. Seen directly in screen `tile`
    /// it gets shadows and reflections; what a mirror shows (`tile` None) does not.
    fn shade(&self, g: usize, o: DVec3, d: DVec3, t: f64, n: DVec3, tile: Option<usize>) -> DVec3 {
        let direct = tile.is_some();
        let geom = &self.geoms[g];
        let p = o + t * d;
        let view = -d / d.length();
        let n = if n.dot(view) < 0.0 { -n } else { n };
        let base = match &geom.texture {
            None => geom.rgb,
            Some(tex) => geom.rgb * texel(tex, p - geom.pos, || geom.rot_t * (p - geom.pos), || geom.rot_t * n),
        };
        let mut c = geom.emission * base + self.ambient * base;
        let lifted = p + self.eps * n;
        let specular = |to_light: DVec3| {
            // n·h > cut, h = (l + v) / |l + v|, tested without the square root
            let h = to_light + view;
            let nh = n.dot(h);
            if geom.specular > 0.0 && nh > 0.0 && nh * nh > geom.spec_cut * geom.spec_cut * h.length_squared() {
                geom.specular * phong(nh / h.length(), geom.exponent, geom.exponent_int)
            } else {
                0.0
            }
        };
        for l in &self.directional {
            let ndl = n.dot(l.to_light);
            if ndl <= 0.0 || (direct && l.shadows.as_ref().is_some_and(|grid| self.shadowed(grid, lifted, l.to_light))) {
                continue;
            }
            c += ndl * l.diffuse * base + specular(l.to_light) * l.specular;
        }
        for l in &self.spots {
            let v = l.pos - p;
            let dist = v.length();
            let to_light = v / dist;
            let [a0, a1, a2] = l.attenuation;
            let cos = -to_light.dot(l.dir);
            let k = if cos < l.cos_cutoff { 0.0 } else { cos.max(0.0).powf(l.exponent) } / (a0 + a1 * dist + a2 * dist * dist).max(1e-12);
            if k == 0.0 {
                continue;
            }
            c += k * l.ambient * base;
            let ndl = n.dot(to_light);
            if ndl <= 0.0 || (direct && l.castshadow && self.blocked(lifted, to_light, dist)) {
                continue;
            }
            c += k * (ndl * l.diffuse * base + specular(to_light) * l.specular);
        }
        if let (Some(tile), Some(mi)) = (tile, geom.mirror) {
            let mirror = &self.mirrors[mi];
            let dm = d - 2.0 * d.dot(mirror.normal) * mirror.normal;
            let candidates = mirror.bins.everywhere.iter().chain(&mirror.bins.tiles[tile]);
            if let Some((h, s, nr)) = self.first_hit(candidates, &mirror.eyes, dm, t * (1.0 + 1e-9), self.far) {
                c += geom.reflectance * self.shade(h, mirror.eye, dm, s, nr, None);
            }
        }
        c
    }

    /// The skybox seen along `d` (any length): a gradient from rgb2 straight down to rgb1
    /// straight up.
    fn sky(&self, d: DVec3) -> DVec3 {
        match self.sky {
            None => DVec3::ZERO,
            Some((Builtin::Gradient, top, bottom)) => bottom + (top - bottom) * (0.5 * (1.0 + d.z / d.length())),
            Some((_, rgb1, _)) => rgb1,
        }
    }
}

/// x^e, by squaring for the integer exponents materials usually give.
#[inline]
fn phong(x: f64, e: f64, int: Option<u32>) -> f64 {
    let Some(mut k) = int else { return x.powf(e) };
    let (mut acc, mut sq) = (1.0, x);
    while k > 0 {
        if k & 1 == 1 {
            acc *= sq;
        }
        sq *= sq;
        k >>= 1;
    }
    acc
}

/// Texture colour at world offset `r` from the geom's centre; cube textures, projected along the
/// normal's dominant axis, need the local point and normal.
#[inline]
fn texel(t: &Tex, r: DVec3, local_p: impl Fn() -> DVec3, local_n: impl Fn() -> DVec3) -> DVec3 {
    if t.builtin == Builtin::Flat {
        return t.rgb1;
    }
    let (u, v) = match t.kind {
        TextureKind::TwoD => (r.dot(t.axes[0]), r.dot(t.axes[1])),
        _ => {
            let (p, a) = (local_p(), local_n().abs());
            let (u, v) = if a.x >= a.y && a.x >= a.z { (p.y, p.z) } else if a.y >= a.z { (p.x, p.z) } else { (p.x, p.y) };
            (u * t.scale[0], v * t.scale[1])
        }
    };
    match t.builtin {
        Builtin::None => DVec3::ONE,
        Builtin::Flat => t.rgb1,
        Builtin::Checker => {
            // one repeat holds 2 × 2 checks, rgb2 on the diagonal through the origin
            let odd = (floor(2.0 * u) + floor(2.0 * v)) & 1 == 1;
            if odd { t.rgb1 } else { t.rgb2 }
        }
        Builtin::Gradient => t.rgb2 + (t.rgb1 - t.rgb2) * (v - floor(v) as f64),
    }
}

/// ⌊x⌋ for |x| < 2⁶³ without a libm call (SSE2 has no rounding instruction).
#[inline]
fn floor(x: f64) -> i64 {
    let i = x as i64;
    i - (x < i as f64) as i64
}
