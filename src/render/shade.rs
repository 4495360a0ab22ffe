//! One frame's scene and its pixels: primary, shadow and reflection rays, and MuJoCo's lighting
//! (OpenGL's fixed-function model: per light ambient + diffuse max(n·l, 0) + specular
//! max(n·h, 0)^(128 · shininess), times attenuation and the spot factor). A frame is kept in
//! single precision relative to the eye, where its coordinates are small. A ray is tested
//! against the solids whose bounding spheres cover its pixel (`cover`, found a row at a time);
//! a floor is drawn by rows (`floor`); shadows of directional lights are looked up by outline
//! (`shadow`).

use glam::{DMat3, DVec3, Mat3A, Vec3A};

mod cover;
mod floor;
mod shadow;

use cover::{Bins, RowCover, Sphere};
use floor::{odd_share, Floor, FloorRow};
use shadow::ShadowGrid;
use super::raycast::{intersect, meets_sphere, plane, Hit};
use super::surface::Surface;
use super::{Frame, Poses, View};
use crate::model::visual::{Builtin, TextureKind};
use std::sync::Arc;

use crate::model::{GeomType, Model};

/// A geom as one frame sees it.
struct Geom {
    kind: GeomType,
    size: [f32; 3],
    pos: Vec3A,
    /// World axes, transposed: world → geom frame.
    rot_t: Mat3A,
    /// World axes: geom frame → world.
    rot: Mat3A,
    /// Bounding radius (∞ for planes).
    rbound: f32,
    rgb: Vec3A,
    emission: f32,
    specular: f32,
    /// Phong exponent.
    exponent: f32,
    /// The exponent when it is a small integer (the usual case): powers by squaring.
    exponent_int: Option<u32>,
    /// Below this n·h the specular term is under half a grey level: skipped.
    spec_cut: f32,
    reflectance: f32,
    /// Index into `Scene::mirrors` of a plane that reflects.
    mirror: Option<usize>,
    /// Texture colours and the repeat scale of local coordinates, when textured.
    texture: Option<Tex>,
    /// A mesh's or height field's triangles.
    mesh: Option<Arc<Surface>>,
}

#[derive(Clone, Copy)]
struct Tex {
    kind: TextureKind,
    builtin: Builtin,
    rgb1: Vec3A,
    rgb2: Vec3A,
    /// Repeats per metre along the texture's two axes.
    scale: [f32; 2],
    /// A 2D texture's axes in world, times `scale`: its coordinates are (p − pos)·axes.
    axes: [Vec3A; 2],
}

/// A pixel seen directly: its column, and what each mirror shows along its row.
#[derive(Clone, Copy)]
struct Direct<'a> {
    x: usize,
    mirrors: &'a [RowCover],
}

/// What a mirroring plane shows: the scene seen from the eye's mirror image. The reflected ray
/// from a point p the eye sees at e + t d is the mirrored eye's ray e' + s d' beyond s = t.
struct Mirror {
    /// The solids whose mirrored bounding spheres may cover each screen tile.
    bins: Bins,
    /// The mirrored eye in each geom's frame (ngeom; planes unused).
    eyes: Vec<Vec3A>,
    /// Mirror image of a direction: d − 2 (d·n) n.
    normal: Vec3A,
    /// The mirrored eye in world.
    eye: Vec3A,
}

/// The camera's axes in world.
#[derive(Clone, Copy)]
struct Axes {
    forward: Vec3A,
    up: Vec3A,
    right: Vec3A,
}

/// A directional light in world (the headlight is one).
struct DirLight {
    /// Unit direction towards the light.
    to_light: Vec3A,
    diffuse: Vec3A,
    specular: Vec3A,
    /// The solids as seen along the light, when it casts shadows.
    shadows: Option<ShadowGrid>,
}

/// A point or spot light in world.
struct SpotLight {
    pos: Vec3A,
    dir: Vec3A,
    ambient: Vec3A,
    diffuse: Vec3A,
    specular: Vec3A,
    attenuation: [f32; 3],
    cos_cutoff: f32,
    exponent: f32,
    castshadow: bool,
}

/// Everything one frame's pixels read.
pub(super) struct Scene {
    /// The camera's axes; the eye is the origin of everything below.
    view: Axes,
    width: usize,
    height: usize,
    /// tan(fovy / 2).
    tan_half: f32,
    near: f32,
    far: f32,
    geoms: Vec<Geom>,
    /// The geoms each screen tile may show.
    primary: Bins,
    /// The eye in each geom's frame.
    eyes: Vec<Vec3A>,
    /// Each mirroring plane's reflection (`Geom::mirror`).
    mirrors: Vec<Mirror>,
    /// The plane drawn by rows, when one is all every pixel may see.
    floor: Option<Floor>,
    /// Geoms that can block light or be reflected (all but planes).
    solids: Vec<u32>,
    /// The directional lights' summed ambient colour (it does not depend on the surface).
    ambient: Vec3A,
    directional: Vec<DirLight>,
    spots: Vec<SpotLight>,
    /// Sky colour below (rgb2) and above (rgb1), or black.
    sky: Option<(Builtin, Vec3A, Vec3A)>,
    /// Offset of shadow and reflection rays off the surface.
    eps: f32,
}

impl Geom {
    /// First hit of the ray `o + t d` (geom frame) in `[t0, t1)`.
    #[inline]
    fn hit(&self, o: Vec3A, d: Vec3A, t0: f32, t1: f32) -> Option<Hit> {
        match &self.mesh {
            Some(t) => t.hit(o, d, t0, t1),
            None => intersect(self.kind, &self.size, o, d, t0, t1),
        }
    }

    /// What `look` shows, relative to the eye of `view`, in single precision; `meshes`: the
    /// triangles of each mesh, then of each height field.
    fn new(m: &Model, view: &View, look: Look, meshes: &[Option<Arc<Surface>>]) -> Geom {
        let v = &m.vis;
        let f = |x: DVec3| x.as_vec3a();
        let Look { kind, size, pos, rot, rgba, material, rbound, surface } = look;
        let mat = material.map(|i| &v.materials[i]);
        let exponent = 128.0 * mat.map_or(0.5, |mt| mt.shininess) as f32;
        let texture = mat.and_then(|mt| {
            let t = &v.textures[mt.texture?];
            // MuJoCo: a 2D texture spans a plane's extent texrepeat times (per metre when
            // texuniform); a cube texture wraps the geom once (per metre when texuniform)
            let span = |k: usize| if mt.texuniform || size[k] <= 0.0 { 1.0 } else { 2.0 * size[k] };
            let scale = match t.kind {
                TextureKind::TwoD => [mt.texrepeat[0] / span(0), mt.texrepeat[1] / span(1)],
                _ => [mt.texrepeat[0], mt.texrepeat[1]],
            };
            let axes = [f(rot.x_axis * scale[0]), f(rot.y_axis * scale[1])];
            Some(Tex { kind: t.kind, builtin: t.builtin, rgb1: f(t.rgb1), rgb2: f(t.rgb2), scale: scale.map(|x| x as f32), axes })
        });
        Geom {
            kind,
            size: size.map(|x| x as f32),
            pos: f(pos - view.pos),
            rot_t: rot.transpose().as_mat3().into(),
            rot: rot.as_mat3().into(),
            rbound: rbound as f32,
            rgb: Vec3A::new(rgba[0] as f32, rgba[1] as f32, rgba[2] as f32),
            emission: mat.map_or(0.0, |mt| mt.emission) as f32,
            specular: mat.map_or(0.5, |mt| mt.specular) as f32,
            exponent,
            exponent_int: (exponent == exponent.trunc() && (0.0..=1024.0).contains(&exponent)).then_some(exponent as u32),
            spec_cut: if exponent > 0.0 { (1.0_f32 / 512.0).powf(1.0 / exponent) } else { 0.0 },
            reflectance: mat.map_or(0.0, |mt| mt.reflectance) as f32,
            mirror: None,
            texture,
            mesh: surface.and_then(|k| meshes[k].clone()),
        }
    }
}

/// What is drawn of a geom or a site of one world: its shape, pose, colour and material.
struct Look {
    kind: GeomType,
    size: [f64; 3],
    pos: DVec3,
    rot: DMat3,
    rgba: [f64; 4],
    material: Option<usize>,
    rbound: f64,
    /// Index of its triangles (a mesh's, then a height field's).
    surface: Option<usize>,
}

impl Look {
    /// Geom g at `poses`.
    fn geom(m: &Model, poses: &Poses, g: usize) -> Look {
        Look {
            kind: m.geom_type[g],
            size: m.geom_size[g],
            pos: poses.geom_xpos(m, g),
            rot: poses.xmat(m.geom_body[g]) * m.geom_mat[g],
            rgba: m.vis.geom_rgba[g],
            material: m.vis.geom_material[g],
            rbound: m.geom_rbound[g],
            surface: match (m.geom_mesh[g], m.geom_hfield[g]) {
                (Some(k), _) => Some(k),
                (_, Some(k)) => Some(m.meshes.len() + k),
                _ => None,
            },
        }
    }

    /// Site s at `poses`, drawn as a geom of its shape.
    fn site(m: &Model, poses: &Poses, s: usize) -> Look {
        let size = m.site_size[s];
        let rbound = match m.site_type[s] {
            GeomType::Capsule => size[0] + size[1],
            GeomType::Cylinder => size[0].hypot(size[1]),
            GeomType::Box => DVec3::from_array(size).length(),
            GeomType::Ellipsoid => size[0].max(size[1]).max(size[2]),
            _ => size[0],
        };
        Look {
            kind: m.site_type[s],
            size,
            pos: poses.site_xpos(m, s),
            rot: poses.xmat(m.site_body[s]) * m.site_mat[s],
            rgba: m.vis.site_rgba[s],
            material: m.vis.site_material[s],
            rbound,
            surface: None,
        }
    }
}

/// The lights of a frame: the directional lights' summed ambient colour, the directional
/// lights (the headlight first, when on) and the point and spot lights, relative to the eye.
fn light_sources(m: &Model, view: &View, lights: &[(usize, DVec3, DVec3)], geoms: &[Geom], solids: &[u32], forward: Vec3A) -> (Vec3A, Vec<DirLight>, Vec<SpotLight>) {
    let v = &m.vis;
    let f = |x: DVec3| x.as_vec3a();
    let (mut ambient, mut directional, mut spots) = (Vec3A::ZERO, vec![], vec![]);
    if v.head_active {
        ambient += f(v.head_ambient);
        directional.push(DirLight { to_light: -forward, diffuse: f(v.head_diffuse), specular: f(v.head_specular), shadows: None });
    }
    for &(i, pos, dir) in lights {
        let l = &v.lights[i];
        let dir = f(dir);
        if l.directional {
            ambient += f(l.ambient);
            let shadows = if l.castshadow { ShadowGrid::new(dir, geoms, solids) } else { None };
            directional.push(DirLight { to_light: -dir, diffuse: f(l.diffuse), specular: f(l.specular), shadows });
        } else {
            spots.push(SpotLight {
                pos: f(pos - view.pos),
                dir,
                ambient: f(l.ambient),
                diffuse: f(l.diffuse),
                specular: f(l.specular),
                attenuation: l.attenuation.map(|x| x as f32),
                cos_cutoff: l.cos_cutoff as f32,
                exponent: l.exponent as f32,
                castshadow: l.castshadow,
            });
        }
    }
    (ambient, directional, spots)
}

impl Scene {
    /// The frame of `view` of a world at `poses`, with `lights` (index, position, direction) on.
    /// Everything is stored relative to the eye, in single precision.
    /// `size` is the frame's (width, height) in pixels.
    pub(super) fn new(m: &Model, poses: &Poses, view: &View, lights: &[(usize, DVec3, DVec3)], extent: f64, size: (usize, usize), meshes: &[Option<Arc<Surface>>]) -> Scene {
        let (width, height) = size;
        let v = &m.vis;
        let f = |x: DVec3| x.as_vec3a();
        // the geoms, then the sites
        let nsite = m.site_body.len();
        let looks = (0..m.ngeom).map(|g| Look::geom(m, poses, g)).chain((0..nsite).map(|s| Look::site(m, poses, s)));
        let geoms: Vec<Geom> = looks.map(|look| Geom::new(m, view, look, meshes)).collect();
        let axes = Axes { forward: f(view.forward), up: f(view.up), right: f(view.right) };
        let shown = |g: usize| if g < m.ngeom { m.vis.geom_drawn.get(g) } else { m.vis.site_drawn.get(g - m.ngeom) };
        let drawn = |g: u32| shown(g as usize).copied().unwrap_or(true);
        let solids: Vec<u32> = (0..geoms.len() as u32).filter(|&g| drawn(g) && geoms[g as usize].rbound.is_finite()).collect();
        let (ambient, directional, spots) = light_sources(m, view, lights, &geoms, &solids, axes.forward);
        let sky = v.skybox.map(|i| {
            let t = &v.textures[i];
            (t.builtin, f(t.rgb1), f(t.rgb2))
        });
        let eyes = geoms.iter().map(|g| g.rot_t * -g.pos).collect();
        let mut s = Scene {
            view: axes,
            width,
            height,
            tan_half: (0.5 * view.fovy.to_radians()).tan() as f32,
            near: (v.znear * extent) as f32,
            far: (v.zfar * extent) as f32,
            solids,
            geoms,
            primary: Bins { everywhere: vec![], spheres: vec![] },
            eyes,
            mirrors: vec![],
            floor: None,
            ambient,
            directional,
            spots,
            sky,
            eps: (1e-5 * extent) as f32,
        };
        s.primary = s.bin(s.geoms.iter().enumerate().filter(|&(g, _)| drawn(g as u32)).map(|(g, geom)| (g as u32, geom.pos, geom.rbound)));
        if let [g] = s.primary.everywhere[..] {
            s.floor = Floor::new(&s.geoms, g as usize);
        }
        s.add_mirrors();
        s
    }

    /// Each reflecting plane's mirror image of the scene (`Geom::mirror`).
    fn add_mirrors(&mut self) {
        let s = self;
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
            let eye = 2.0 * origin.dot(normal) * normal;
            let eyes = s.geoms.iter().map(|g| g.rot_t * (eye - g.pos)).collect();
            s.geoms[p].mirror = Some(s.mirrors.len());
            s.mirrors.push(Mirror { bins, eyes, normal, eye });
        }
    }

    /// The geoms whose bounding spheres (`g`, centre, radius) may show: the ones that may cover
    /// any pixel, and the others with the rows they may cover.
    fn bin(&self, spheres: impl Iterator<Item = (u32, Vec3A, f32)>) -> Bins {
        let aspect = self.width as f32 / self.height as f32;
        let (sx, sy) = (self.tan_half * aspect, self.tan_half);
        let mut bins = Bins { everywhere: vec![], spheres: vec![] };
        for (g, centre, r) in spheres {
            if !r.is_finite() {
                bins.everywhere.push(g);
                continue;
            }
            let c = centre;
            let (x, y, z) = (c.dot(self.view.right), c.dot(self.view.up), c.dot(self.view.forward));
            if z + r < self.near {
                continue; // wholly behind the near plane
            }
            if z - r <= self.near.max(1e-9) {
                bins.everywhere.push(g);
                continue;
            }
            // bounds of x/z and y/z over the sphere, conservative
            let span = |a: f32| {
                let lo = if a - r <= 0.0 { (a - r) / (z - r) } else { (a - r) / (z + r) };
                let hi = if a + r >= 0.0 { (a + r) / (z - r) } else { (a + r) / (z + r) };
                (lo, hi)
            };
            let ((x0, x1), (y0, y1)) = (span(x), span(y));
            // screen: column = (x/z / sx + 1) W / 2, row = (1 − y/z / sy) H / 2
            let col = |u: f32| (u / sx + 1.0) * 0.5 * self.width as f32;
            let row = |u: f32| (1.0 - u / sy) * 0.5 * self.height as f32;
            let (c0, c1, r0, r1) = (col(x0), col(x1), row(y1), row(y0));
            if c1 < 0.0 || r1 < 0.0 || c0 > self.width as f32 || r0 > self.height as f32 {
                continue;
            }
            let rows = (r0.max(1.0) as usize - 1, (r1 as usize + 1).min(self.height - 1));
            bins.spheres.push(Sphere { g, centre: c, r, rows });
        }
        bins
    }

    /// Draws rows `y0..y1` into the band `out` (its rows start at `y0`).
    pub(super) fn draw_rows(&self, y0: usize, y1: usize, out: Frame<'_>) {
        let (w, h) = (self.width as f32, self.height as f32);
        let want_rgb = !out.rgb.is_empty();
        let want_depth = !out.depth.is_empty();
        // z-buffer value f (z − n) / ((f − n) z) = a − b / z
        let (a, b) = (self.far / (self.far - self.near), self.far * self.near / (self.far - self.near));
        // each column's offset along `right`, so that a ray is a row's base plus a column's offset
        let (sx, sy) = (2.0 * self.tan_half * w / h / w, 2.0 * self.tan_half / h);
        let columns: Vec<Vec3A> = (0..self.width).map(|x| ((x as f32 + 0.5) * sx - self.tan_half * w / h) * self.view.right).collect();
        let col_len2: Vec<f32> = columns.iter().map(|c| c.length_squared()).collect();
        let mut inv_len = vec![0.0_f32; self.width];
        let mut cover = RowCover::new(self.width);
        let mut mirror_cover: Vec<RowCover> = self.mirrors.iter().map(|_| RowCover::new(self.width)).collect();
        let mut floor_row = FloorRow::new(if self.floor.is_some() { self.width } else { 0 }, self.directional.len());
        let step = sx * self.view.right;
        for y in y0..y1 {
            // unnormalised rays with unit depth along the view axis, so that t is that depth
            let base = self.view.forward + (self.tan_half - (y as f32 + 0.5) * sy) * self.view.up;
            // 1 / |d| of the row's rays at once (base ⊥ columns), a loop the compiler vectorises
            let base_len2 = base.length_squared();
            for (inv, c2) in inv_len.iter_mut().zip(&col_len2) {
                *inv = 1.0 / (base_len2 + c2).sqrt();
            }
            cover.build(&self.primary, y, base + columns[0], step);
            // the mirrored ray meets a geom where the eye's ray meets its mirror image
            for (m, c) in self.mirrors.iter().zip(&mut mirror_cover) {
                c.build(&m.bins, y, base + columns[0], step);
            }
            if let Some(f) = &self.floor {
                self.floor_row(f, base + columns[0], step, -sy * self.view.up, &inv_len, &mut floor_row);
            }
            for (x, col) in columns.iter().enumerate() {
                let d = base + *col;
                let view = -d * inv_len[x];
                let seen = Direct { x, mirrors: &mirror_cover };
                // the hit (with the floor's when it is drawn by rows) and the floor's, if nearest
                let (hit, floor) = match &self.floor {
                    Some(f) => match self.solid_hit(cover.at(x), &self.eyes, d, self.near, floor_row.t[x].min(self.far)) {
                        Some(h) => (Some(h), None),
                        None if floor_row.t[x] < f32::INFINITY => (Some((f.geom(), floor_row.t[x], Vec3A::ZERO)), Some(f)),
                        None => (None, None),
                    },
                    None => (self.first_hit(&self.primary, cover.at(x), &self.eyes, d, self.near, self.far), None),
                };
                let k = (y - y0) * self.width + x;
                if want_rgb {
                    let rgb = match (hit, floor) {
                        (Some(_), Some(f)) => self.floor_colour(f, &floor_row, x, d, view, seen),
                        (Some(hit), None) => self.shade(hit, Vec3A::ZERO, d, view, Some(seen)),
                        (None, _) => self.sky(-view.z),
                    };
                    // clamped first, so the integer casts cannot saturate
                    let v = rgb.clamp(Vec3A::ZERO, Vec3A::ONE) * 255.0 + 0.5;
                    out.rgb[3 * k..3 * k + 3].copy_from_slice(&[v.x as i32 as u8, v.y as i32 as u8, v.z as i32 as u8]);
                }
                if want_depth {
                    out.depth[k] = hit.map_or(1.0, |(_, t, _)| a - b / t);
                }
            }
        }
    }

    /// The nearest hit among the geoms of `bins` everywhere and the `solids` over the pixel, in
    /// `[t0, t1)` of the ray from the point whose position in each geom's frame `eyes` holds,
    /// along `d`: geom, ray parameter and world normal.
    fn first_hit(&self, bins: &Bins, solids: &[u32], eyes: &[Vec3A], d: Vec3A, t0: f32, mut t1: f32) -> Option<(usize, f32, Vec3A)> {
        let mut best = None;
        for &g in &bins.everywhere {
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
            if let Some((t, n)) = geom.hit(ol, dl, t0, t1) {
                t1 = t;
                best = Some((g as usize, t, n));
            }
        }
        let best = best.map(|(g, t, n)| (g, t, self.geoms[g].rot * n));
        self.solid_hit(solids, eyes, d, t0, t1).or(best)
    }

    /// `first_hit` among `solids` alone.
    fn solid_hit(&self, solids: &[u32], eyes: &[Vec3A], d: Vec3A, t0: f32, mut t1: f32) -> Option<(usize, f32, Vec3A)> {
        let mut best = None;
        for &g in solids {
            let geom = &self.geoms[g as usize];
            if let Some((t, n)) = geom.hit(eyes[g as usize], geom.rot_t * d, t0, t1) {
                t1 = t;
                best = Some((g as usize, t, n));
            }
        }
        best.map(|(g, t, n)| (g, t, self.geoms[g].rot * n))
    }

    /// Whether geom `g` lies on the segment from `p` along `l` up to `t1`.
    #[inline]
    fn meets(&self, g: u32, p: Vec3A, l: Vec3A, t1: f32) -> bool {
        let geom = &self.geoms[g as usize];
        geom.hit(geom.rot_t * (p - geom.pos), geom.rot_t * l, 0.0, t1).is_some()
    }

    /// Whether a solid other than `own` lies on the segment from `p` along unit `l` up to `t1`.
    fn blocked(&self, own: usize, p: Vec3A, l: Vec3A, t1: f32) -> bool {
        self.solids.iter().any(|&g| {
            let geom = &self.geoms[g as usize];
            g as usize != own && meets_sphere(geom.pos, geom.rbound, p, l, 0.0, t1) && self.meets(g, p, l, t1)
        })
    }

    /// Colour of the hit (geom `g`, at `o + t d`, world normal `n`), `view` the unit vector back
    /// along `d`. Seen directly (`seen`) it gets shadows and reflections; what a mirror shows does
    /// not.
    fn shade(&self, (g, t, n): (usize, f32, Vec3A), o: Vec3A, d: Vec3A, view: Vec3A, seen: Option<Direct<'_>>) -> Vec3A {
        let geom = &self.geoms[g];
        let p = o + t * d;
        let n = if n.dot(view) < 0.0 { -n } else { n };
        let base = match &geom.texture {
            None => geom.rgb,
            Some(tex) => geom.rgb * texel(tex, p - geom.pos, || geom.rot_t * (p - geom.pos), || geom.rot_t * n, || self.footprint(t, d, n)),
        };
        let mut c = geom.emission * base + self.ambient * base;
        let lifted = p + self.eps * n;
        for l in &self.directional {
            let ndl = n.dot(l.to_light);
            if ndl <= 0.0 || (seen.is_some() && l.shadows.as_ref().is_some_and(|grid| self.shadowed(grid, g, lifted, l.to_light))) {
                continue;
            }
            c += ndl * l.diffuse * base + specular(geom, n, view, l.to_light) * l.specular;
        }
        if !self.spots.is_empty() {
            c += self.spot_lights(g, p, n, view, base, seen.is_some());
        }
        c + self.reflection(g, d, view, t, seen)
    }

    /// The pixel's footprint on the surface hit at `t` along `d` (normal `n`): where the hits of
    /// the rays one column right and one row up lie from it, to first order.
    fn footprint(&self, t: f32, d: Vec3A, n: Vec3A) -> [Vec3A; 2] {
        let k = 2.0 * self.tan_half / self.height as f32;
        let nd = n.dot(d);
        [k * self.view.right, k * self.view.up].map(|s| if nd == 0.0 { Vec3A::ZERO } else { t * (s - d * (n.dot(s) / nd)) })
    }

    /// What the point and spot lights add to geom `g`'s colour `base` at `p` (normal `n`, unit
    /// `view` towards the eye); with shadows when `direct`.
    fn spot_lights(&self, g: usize, p: Vec3A, n: Vec3A, view: Vec3A, base: Vec3A, direct: bool) -> Vec3A {
        let geom = &self.geoms[g];
        let lifted = p + self.eps * n;
        let mut c = Vec3A::ZERO;
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
            if ndl <= 0.0 || (direct && l.castshadow && self.blocked(g, lifted, to_light, dist)) {
                continue;
            }
            c += k * (ndl * l.diffuse * base + specular(geom, n, view, to_light) * l.specular);
        }
        c
    }

    /// What geom `g`, hit at `t d`, reflects when it is a mirror seen directly.
    fn reflection(&self, g: usize, d: Vec3A, view: Vec3A, t: f32, seen: Option<Direct<'_>>) -> Vec3A {
        let geom = &self.geoms[g];
        let (Some(at), Some(mi)) = (seen, geom.mirror) else { return Vec3A::ZERO };
        let (mirror, solids) = (&self.mirrors[mi], at.mirrors[mi].at(at.x));
        if solids.is_empty() && mirror.bins.everywhere.is_empty() {
            return Vec3A::ZERO;
        }
        let dm = d - 2.0 * d.dot(mirror.normal) * mirror.normal;
        match self.first_hit(&mirror.bins, solids, &mirror.eyes, dm, t * (1.0 + 1e-6), self.far) {
            Some(hit) => {
                let view_m = view - 2.0 * view.dot(mirror.normal) * mirror.normal;
                geom.reflectance * self.shade(hit, mirror.eye, dm, view_m, None)
            }
            None => Vec3A::ZERO,
        }
    }

    /// The skybox seen along a direction whose unit vector's z is `z`: a gradient from rgb2
    /// straight down to rgb1 straight up.
    fn sky(&self, z: f32) -> Vec3A {
        match self.sky {
            None => Vec3A::ZERO,
            Some((Builtin::Gradient, top, bottom)) => bottom + (top - bottom) * (0.5 * (1.0 + z)),
            Some((_, rgb1, _)) => rgb1,
        }
    }
}

/// Phong's specular factor of `geom` at normal `n` seen along unit `view`, lit along unit
/// `to_light`: 0 below the cut where it is under half a grey level.
#[inline]
fn specular(geom: &Geom, n: Vec3A, view: Vec3A, to_light: Vec3A) -> f32 {
    // n·h > cut, h = (l + v) / |l + v|, tested without the square root
    let h = to_light + view;
    let nh = n.dot(h);
    if geom.specular > 0.0 && nh > 0.0 && nh * nh > geom.spec_cut * geom.spec_cut * h.length_squared() {
        geom.specular * phong(nh / h.length(), geom.exponent, geom.exponent_int)
    } else {
        0.0
    }
}

/// x^e, by squaring for the integer exponents materials usually give.
#[inline]
fn phong(x: f32, e: f32, int: Option<u32>) -> f32 {
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
/// normal's dominant axis, need the local point and normal; a 2D checker is averaged over the
/// pixel's footprint (`foot`: its two edges in world).
#[inline]
fn texel(t: &Tex, r: Vec3A, local_p: impl Fn() -> Vec3A, local_n: impl Fn() -> Vec3A, foot: impl Fn() -> [Vec3A; 2]) -> Vec3A {
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
        Builtin::None => Vec3A::ONE,
        Builtin::Flat => t.rgb1,
        // one repeat holds 2 × 2 checks, rgb2 on the diagonal through the origin
        Builtin::Checker if t.kind == TextureKind::TwoD => {
            let [e0, e1] = foot();
            let width = |axis: Vec3A| 2.0 * (e0.dot(axis).abs() + e1.dot(axis).abs());
            let odd = odd_share(2.0 * u, 2.0 * v, width(t.axes[0]), width(t.axes[1]));
            t.rgb2 * (1.0 - odd) + t.rgb1 * odd
        }
        Builtin::Checker => {
            let odd = (floor(2.0 * u) + floor(2.0 * v)) & 1 == 1;
            if odd { t.rgb1 } else { t.rgb2 }
        }
        Builtin::Gradient => t.rgb2 + (t.rgb1 - t.rgb2) * (v - floor(v) as f32),
    }
}

/// ⌊x⌋ for |x| < 2⁶³ without a libm call (SSE2 has no rounding instruction).
#[inline]
fn floor(x: f32) -> i64 {
    let i = x as i64;
    i - (x < i as f32) as i64
}
