//! Where cameras and lights are: MuJoCo's free camera (`mjvCamera`, `mjv_updateCamera`) and the
//! model's cameras and lights with their tracking modes (`mj_camlight`).

use glam::{DMat3, DVec3};

use super::Poses;
use crate::model::visual::TrackMode;
use crate::model::Model;

/// A camera's pose and lens: it looks along `forward` with `up` at the top of the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub pos: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit up direction (⊥ forward).
    pub up: DVec3,
    /// Unit right direction, forward × up.
    pub right: DVec3,
    /// Vertical field of view, degrees.
    pub fovy: f64,
}

impl View {
    /// A view from camera axes as MuJoCo stores them (columns x right, y up; it looks along −z).
    pub fn from_axes(pos: DVec3, mat: DMat3, fovy: f64) -> View {
        View { pos, forward: -mat.z_axis, up: mat.y_axis, right: mat.x_axis, fovy }
    }
}

/// MuJoCo's free camera: it orbits `lookat` at `distance`, `azimuth` degrees about +z from +x
/// and `elevation` degrees above the horizontal (negative looks down). With `track_body` set
/// (MuJoCo's `mjCAMERA_TRACKING`), `lookat` is that body's subtree centre of mass in every frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeCamera {
    /// Point looked at.
    pub lookat: DVec3,
    /// Distance from the eye to `lookat`.
    pub distance: f64,
    /// Azimuth, degrees.
    pub azimuth: f64,
    /// Elevation, degrees.
    pub elevation: f64,
    /// Body whose subtree centre of mass is looked at, if tracking.
    pub track_body: Option<usize>,
}

/// Which camera draws a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraChoice {
    /// The free camera.
    Free(FreeCamera),
    /// A model camera, by index.
    Model(usize),
}

/// What tracking cameras and lights keep from the reference configuration qpos0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Anchors {
    /// World offset from the body origin (track).
    pub pos0: Vec<DVec3>,
    /// World offset from the body's subtree centre of mass (trackcom).
    pub poscom0: Vec<DVec3>,
    /// World axes (track, trackcom); for a light, its world direction in the z column.
    pub mat0: Vec<DMat3>,
}

/// How a camera or light hangs on the bodies: attached to `body` at `pos`, `mat` in its frame,
/// moved as `mode` says (toward `target` for the target modes).
struct Mount {
    mode: TrackMode,
    body: usize,
    target: Option<usize>,
    pos: DVec3,
    mat: DMat3,
}

/// World pose of the `i`th camera or light, mounted as `mount` says: MuJoCo's `mj_camlight`.
/// Target modes aim −z at the target, keeping x horizontal.
fn attached(mount: &Mount, anchors: &Anchors, i: usize, poses: &Poses) -> (DVec3, DMat3) {
    let Mount { mode, body, target, pos, mat } = *mount;
    let (bpos, bmat) = (poses.xpos(body), poses.xmat(body));
    match mode {
        TrackMode::Fixed => (bpos + bmat * pos, bmat * mat),
        TrackMode::Track => (bpos + anchors.pos0[i], anchors.mat0[i]),
        TrackMode::TrackCom => (poses.com[body] + anchors.poscom0[i], anchors.mat0[i]),
        TrackMode::TargetBody | TrackMode::TargetBodyCom => {
            let p = bpos + bmat * pos;
            let t = target.unwrap_or(0);
            let aim = if mode == TrackMode::TargetBody { poses.xpos(t) } else { poses.com[t] };
            (p, aim_at(p, aim).unwrap_or(bmat * mat))
        }
    }
}

/// Axes whose −z points from `from` to `to` with x horizontal (None when they coincide or the
/// direction is vertical).
fn aim_at(from: DVec3, to: DVec3) -> Option<DMat3> {
    let z = (from - to).try_normalize()?;
    let x = DVec3::Z.cross(z).try_normalize()?;
    Some(DMat3::from_cols(x, z.cross(x), z))
}

/// World pose of model camera `i`.
pub fn model_view(m: &Model, anchors: &Anchors, poses: &Poses, i: usize) -> View {
    let c = &m.vis.cameras[i];
    let (pos, mat) = attached(&Mount { mode: c.mode, body: c.body, target: c.target, pos: c.pos, mat: c.mat }, anchors, i, poses);
    View::from_axes(pos, mat, c.fovy)
}

/// World position and unit direction of light `i`.
pub fn light_pose(m: &Model, anchors: &Anchors, poses: &Poses, i: usize) -> (DVec3, DVec3) {
    let l = &m.vis.lights[i];
    let local = light_axes(l.dir);
    let (pos, mat) = attached(&Mount { mode: l.mode, body: l.body, target: l.target, pos: l.pos, mat: local }, anchors, i, poses);
    (pos, -mat.z_axis)
}

/// Axes whose −z is `dir`.
pub(super) fn light_axes(dir: DVec3) -> DMat3 {
    let z = -dir;
    let x = z.any_orthonormal_vector();
    DMat3::from_cols(x, z.cross(x), z)
}

/// World pose of the free camera (`mjv_updateCamera`).
pub fn free_view(cam: &FreeCamera, fovy: f64, poses: &Poses) -> View {
    let lookat = match cam.track_body {
        Some(b) => poses.com[b],
        None => cam.lookat,
    };
    let (sa, ca) = cam.azimuth.to_radians().sin_cos();
    let (se, ce) = cam.elevation.to_radians().sin_cos();
    let forward = DVec3::new(ce * ca, ce * sa, se);
    let up = DVec3::new(-se * ca, -se * sa, ce);
    View { pos: lookat - cam.distance * forward, forward, up, right: forward.cross(up), fovy }
}

/// The anchors of the model's cameras and lights, from their poses at `poses` (qpos0).
pub fn anchors(m: &Model, poses: &Poses) -> (Anchors, Anchors) {
    let mut cams = Anchors::default();
    for c in &m.vis.cameras {
        push_anchor(&mut cams, poses, c.body, c.pos, c.mat);
    }
    let mut lights = Anchors::default();
    for l in &m.vis.lights {
        push_anchor(&mut lights, poses, l.body, l.pos, light_axes(l.dir));
    }
    (cams, lights)
}

fn push_anchor(a: &mut Anchors, poses: &Poses, body: usize, pos: DVec3, mat: DMat3) {
    let world = poses.xpos(body) + poses.xmat(body) * pos;
    a.pos0.push(world - poses.xpos(body));
    a.poscom0.push(world - poses.com[body]);
    a.mat0.push(poses.xmat(body) * mat);
}
