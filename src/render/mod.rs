//! Pictures of worlds without GL: every pixel's ray is cast against the analytic geoms (plane,
//! sphere, capsule, cylinder, box, ellipsoid) and shaded as MuJoCo's fixed-function renderer
//! shades (headlight and model lights, Phong specular, shadows, checker and gradient textures,
//! planar reflections). Depth is MuJoCo's z-buffer value from the model's near and far planes.
//!
//! [`Renderer`] holds what a model's frames share (its extent, the cameras' anchors at qpos0);
//! [`Poses`] is one world's body poses; [`Renderer::draw`] draws many frames in parallel.

pub mod camera;
mod hfield_grid;
mod raycast;
mod surface;
mod shade;

use glam::{DMat3, DVec3};
use rayon::iter::{IndexedParallelIterator, IntoParallelRefMutIterator, ParallelIterator};

pub use camera::{CameraChoice, FreeCamera, View};
use crate::model::{GeomType, Model};
use crate::dynamics::kinematics::{self, KinData};

/// Largest image side accepted, in pixels.
pub const MAX_SIDE: usize = 16384;

/// Rows of a frame drawn as one parallel task.
const BAND: usize = 8;


/// One world's body poses and subtree centres of mass, from its qpos.
#[derive(Clone, Debug)]
pub struct Poses {
    kin: KinData,
    /// Zero velocities: poses need none.
    qvel: Vec<f64>,
    /// Subtree centre of mass of each body (nbody), MuJoCo's `subtree_com`.
    pub com: Vec<DVec3>,
    /// Geoms and sites of this world away from the model's place, each with its position in its
    /// body's frame.
    moved: Vec<(Placed, DVec3)>,
    /// This world's surfaces where its height fields are its own.
    surfaces: Option<Surfaces>,
}

impl Poses {
    /// Poses at `qpos`.
    pub fn new(m: &Model, qpos: &[f64]) -> Poses {
        let mut p = Poses { kin: KinData::new(m), qvel: vec![0.0; m.nv], com: vec![DVec3::ZERO; m.nbody], moved: vec![], surfaces: None };
        p.update(m, qpos);
        p
    }

    /// Recomputes the poses for `qpos`.
    pub fn update(&mut self, m: &Model, qpos: &[f64]) {
        kinematics::forward(m, qpos, &self.qvel, &mut self.kin);
        let mut mass = vec![0.0; m.nbody];
        for b in 0..m.nbody {
            mass[b] = m.body_mass[b];
            self.com[b] = m.body_mass[b] * (self.kin.xpos[b] + self.kin.xmat[b] * m.body_ipos[b]);
        }
        for b in (1..m.nbody).rev() {
            let p = m.body_parent[b];
            mass[p] += mass[b];
            let c = self.com[b];
            self.com[p] += c;
        }
        for b in 0..m.nbody {
            self.com[b] = if mass[b] > 0.0 { self.com[b] / mass[b] } else { self.kin.xpos[b] };
        }
    }

    /// Body origin in world.
    #[inline]
    pub fn xpos(&self, b: usize) -> DVec3 {
        self.kin.xpos[b]
    }

    /// Body axes in world.
    #[inline]
    pub fn xmat(&self, b: usize) -> DMat3 {
        self.kin.xmat[b]
    }

    /// The same poses with geoms and sites placed in their bodies' frames as given.
    pub fn with_placed(mut self, moved: &[(Placed, DVec3)]) -> Poses {
        self.moved = moved.to_vec();
        self
    }

    /// These poses drawn with `surfaces` (a world's own height fields), if any.
    pub fn with_surfaces(mut self, surfaces: Option<Surfaces>) -> Poses {
        self.surfaces = surfaces;
        self
    }

    /// Where `what` sits in its body's frame in this world.
    fn local(&self, what: Placed, model: DVec3) -> DVec3 {
        self.moved.iter().find(|(k, _)| *k == what).map_or(model, |(_, p)| *p)
    }

    /// Geom centre in world.
    pub fn geom_xpos(&self, m: &Model, g: usize) -> DVec3 {
        let b = m.geom_body[g];
        self.kin.xpos[b] + self.kin.xmat[b] * self.local(Placed::Geom(g), m.geom_pos[g])
    }

    /// Site position in world.
    pub fn site_xpos(&self, m: &Model, s: usize) -> DVec3 {
        let b = m.site_body[s];
        self.kin.xpos[b] + self.kin.xmat[b] * self.local(Placed::Site(s), m.site_pos[s])
    }
}

/// A geom or a site, placed in its body per world (a target, a marker).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placed {
    /// Geom index.
    Geom(usize),
    /// Site index.
    Site(usize),
}

impl Placed {
    /// Its position in its body's frame in the model.
    pub fn model_pos(self, m: &Model) -> DVec3 {
        match self {
            Placed::Geom(g) => m.geom_pos[g],
            Placed::Site(s) => m.site_pos[s],
        }
    }
}

/// What every frame of one model shares.
#[derive(Clone, Debug)]
pub struct Renderer {
    /// The model's extent (MuJoCo's `stat.extent`): clipping planes and the default camera
    /// distance scale with it.
    pub extent: f64,
    /// The model's centre (MuJoCo's `stat.center`).
    pub center: DVec3,
    cam_anchors: camera::Anchors,
    light_anchors: camera::Anchors,
    /// Each mesh's, then each height field's, triangles (None: parry refused them; not drawn).
    surfaces: Surfaces,
}

/// Each mesh's, then each height field's, triangles as drawn (None: not drawn).
pub type Surfaces = std::sync::Arc<[Option<std::sync::Arc<surface::Surface>>]>;

/// A height field's surface as drawn.
fn hfield_surface(h: &crate::geometry::HField) -> Option<std::sync::Arc<surface::Surface>> {
    Some(std::sync::Arc::new(surface::Surface::height_field(h)))
}

/// What to draw into: either buffer may be empty (not wanted).
pub struct Frame<'a> {
    /// Row-major RGB, 3 bytes per pixel, row 0 at the top (H × W × 3), or empty.
    pub rgb: &'a mut [u8],
    /// Row-major depth (H × W): MuJoCo's z-buffer value in [0, 1] (1 where nothing is drawn), or
    /// empty.
    pub depth: &'a mut [f32],
}

impl Renderer {
    /// Measures the model at qpos0 as MuJoCo's compiler does (`setStat`) and anchors its
    /// tracking cameras and lights.
    pub fn new(m: &Model) -> Renderer {
        let poses = Poses::new(m, &m.qpos0);
        let (cam_anchors, light_anchors) = camera::anchors(m, &poses);
        let (extent, center) = statistics(m, &poses);
        Renderer {
            extent: m.vis.extent.unwrap_or(extent),
            center: m.vis.center.unwrap_or(center),
            cam_anchors,
            light_anchors,
            surfaces: m
                .meshes
                .iter()
                .map(|mesh| {
                    let s = surface::Surface::new(&mesh.vert, &mesh.face, &mesh.corner_normal).or_else(|| surface::Surface::new(&mesh.hull.vert, &mesh.hull.tris, &[]));
                    s.map(std::sync::Arc::new)
                })
                .chain(m.hfields.iter().map(hfield_surface))
                .collect(),
        }
    }

    /// The surfaces of a world whose model `m` has height fields of its own: the meshes' shared,
    /// the height fields' made from `m`.
    pub fn surfaces_for(&self, m: &Model) -> Surfaces {
        let meshes = self.surfaces.len() - m.hfields.len();
        self.surfaces[..meshes].iter().cloned().chain(m.hfields.iter().map(hfield_surface)).collect()
    }

    /// The view a camera gives of a world.
    pub fn view(&self, m: &Model, poses: &Poses, cam: &CameraChoice) -> View {
        match cam {
            CameraChoice::Free(f) => camera::free_view(f, m.vis.fovy, poses),
            CameraChoice::Model(i) => camera::model_view(m, &self.cam_anchors, poses, *i),
        }
    }

    /// Draws one frame per (poses, camera) into `rgb` (frames × H × W × 3, or empty) and `depth`
    /// (frames × H × W, or empty), in parallel on rayon's pool.
    pub fn draw(&self, m: &Model, worlds: &[(&Poses, CameraChoice)], width: usize, height: usize, rgb: &mut [u8], depth: &mut [f32]) {
        let scenes: Vec<shade::Scene> =
            worlds.iter().map(|(p, c)| self.scene(m, p, &self.view(m, p, c), width, height)).collect();
        let bands_per_frame = height.div_ceil(BAND);
        let nbands = bands_per_frame * scenes.len();
        let (rgb_band, depth_band) = (3 * width * BAND, width * BAND);
        // every band's slices, paired; an unwanted buffer gives empty slices
        let mut rgb_parts: Vec<&mut [u8]> = split_bands(rgb, 3 * width * height, rgb_band, nbands);
        let mut depth_parts: Vec<&mut [f32]> = split_bands(depth, width * height, depth_band, nbands);
        rgb_parts
            .par_iter_mut()
            .zip(depth_parts.par_iter_mut())
            .enumerate()
            .for_each(|(k, (rgb, depth))| {
                let (frame, band) = (k / bands_per_frame, k % bands_per_frame);
                let y0 = band * BAND;
                scenes[frame].draw_rows(y0, (y0 + BAND).min(height), Frame { rgb, depth });
            });
    }

    fn scene(&self, m: &Model, poses: &Poses, view: &View, width: usize, height: usize) -> shade::Scene {
        let lights = (0..m.vis.lights.len())
            .filter(|&i| m.vis.lights[i].active)
            .map(|i| {
                let (pos, dir) = camera::light_pose(m, &self.light_anchors, poses, i);
                (i, pos, dir)
            })
            .collect::<Vec<_>>();
        let surfaces = poses.surfaces.as_ref().unwrap_or(&self.surfaces);
        shade::Scene::new(m, poses, view, &lights, self.extent, (width, height), surfaces)
    }
}

/// Splits `buf` (empty, or `frames` frames of `frame_len`) into `n` bands: each frame's bands of
/// `band` entries, the last one of a frame shorter. An empty buffer gives `n` empty slices.
fn split_bands<T>(buf: &mut [T], frame_len: usize, band: usize, n: usize) -> Vec<&mut [T]> {
    if buf.is_empty() {
        return (0..n).map(|_| <&mut [T]>::default()).collect();
    }
    buf.chunks_mut(frame_len).flat_map(|f| f.chunks_mut(band)).collect()
}

/// MuJoCo's model statistics at qpos0 (`setStat`): the centre of the box around body origins
/// and centres of mass, joint anchors, sites and geoms (geoms by their bounding radius, a plane by
/// a tenth of its size or 1 when infinite), and its extent, its longest side but at least twice
/// the mean body size.
fn statistics(m: &Model, p: &Poses) -> (f64, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let mut add = |x: DVec3, r: f64| {
        lo = lo.min(x - r);
        hi = hi.max(x + r);
    };
    let xipos = |b: usize| p.xpos(b) + p.xmat(b) * m.body_ipos[b];
    let anchor = |j: usize| {
        let b = m.jnt_body[j];
        p.xpos(b) + p.xmat(b) * m.jnt_pos[j]
    };
    for b in 1..m.nbody {
        add(p.xpos(b), 0.0);
        add(xipos(b), 0.0);
    }
    for j in 0..m.njnt {
        add(anchor(j), 0.0);
    }
    for s in 0..m.site_body.len() {
        add(p.xpos(m.site_body[s]) + p.xmat(m.site_body[s]) * m.site_pos[s], 0.0);
    }
    for g in 0..m.ngeom {
        let r = match m.geom_type[g] {
            GeomType::Plane if m.geom_size[g][0] > 0.0 || m.geom_size[g][1] > 0.0 => 0.1 * m.geom_size[g][0].max(m.geom_size[g][1]),
            GeomType::Plane => 1.0,
            _ => m.geom_rbound[g],
        };
        add(p.geom_xpos(m, g), r);
    }
    let center = if hi.x >= lo.x { (lo + hi) * 0.5 } else { DVec3::ZERO };
    let mut extent = if hi.x > lo.x { (hi - lo).max_element().max(1e-5) } else { 2.0 };
    // mean body size: the farthest joint anchor or geom surface from each body's centre of mass
    if m.nbody > 1 {
        let mut size = vec![0.0_f64; m.nbody];
        for j in 0..m.njnt {
            let b = m.jnt_body[j];
            for id in [b, m.body_parent[b]] {
                size[id] = size[id].max((xipos(id) - anchor(j)).length());
            }
        }
        for g in (0..m.ngeom).filter(|&g| m.geom_type[g] != GeomType::Plane) {
            let b = m.geom_body[g];
            size[b] = size[b].max(m.geom_rbound[g] + (xipos(b) - p.geom_xpos(m, g)).length());
        }
        let mean = size[1..].iter().map(|s| s.max(1e-5)).sum::<f64>() / (m.nbody - 1) as f64;
        extent = extent.max(2.0 * mean);
    }
    (extent, center)
}
