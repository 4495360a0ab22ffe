//! How a compiled model looks: colours, materials, textures, lights, cameras and the free
//! camera's defaults, every name resolved to an index (MuJoCo's `geom_rgba`, `mat_*`, `tex_*`,
//! `light_*`, `cam_*` and `mjVisual`). The renderer reads it; the physics never does.

use glam::{DMat3, DVec3};

pub use crate::mjcf::{Builtin, TextureKind, TrackMode};

/// A texture: a procedural pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Kind.
    pub kind: TextureKind,
    /// Pattern.
    pub builtin: Builtin,
    /// First colour.
    pub rgb1: DVec3,
    /// Second colour.
    pub rgb2: DVec3,
}

/// A material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Texture index.
    pub texture: Option<usize>,
    /// Texture repetitions over the surface (per metre when `texuniform`).
    pub texrepeat: [f64; 2],
    /// Whether `texrepeat` counts per metre.
    pub texuniform: bool,
    /// Emission, as a multiple of the colour.
    pub emission: f64,
    /// Specular reflectance.
    pub specular: f64,
    /// Shininess in [0, 1] (Phong exponent / 128).
    pub shininess: f64,
    /// Mirror reflectance.
    pub reflectance: f64,
}

/// A light, in its body's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Body it is attached to.
    pub body: usize,
    /// How it follows the body.
    pub mode: TrackMode,
    /// Target body (target modes).
    pub target: Option<usize>,
    /// Directional (else a spotlight).
    pub directional: bool,
    /// Whether it casts shadows.
    pub castshadow: bool,
    /// Whether it is on.
    pub active: bool,
    /// Position in the body frame.
    pub pos: DVec3,
    /// Unit direction in the body frame.
    pub dir: DVec3,
    /// Diffuse colour.
    pub diffuse: DVec3,
    /// Ambient colour.
    pub ambient: DVec3,
    /// Specular colour.
    pub specular: DVec3,
    /// Constant, linear and quadratic attenuation.
    pub attenuation: [f64; 3],
    /// Cosine of the spotlight cutoff angle.
    pub cos_cutoff: f64,
    /// Spotlight exponent.
    pub exponent: f64,
}

/// A model camera, in its body's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Name (may be empty).
    pub name: String,
    /// Body it is attached to.
    pub body: usize,
    /// How it follows the body.
    pub mode: TrackMode,
    /// Target body (target modes).
    pub target: Option<usize>,
    /// Position in the body frame.
    pub pos: DVec3,
    /// Axes in the body frame: x right, y up, the camera looks along −z.
    pub mat: DMat3,
    /// Vertical field of view, degrees.
    pub fovy: f64,
}

/// Everything the renderer reads of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Visual {
    /// Colour of each geom, the material's where the geom keeps the default (ngeom).
    pub geom_rgba: Vec<[f64; 4]>,
    /// Material of each geom (ngeom).
    pub geom_material: Vec<Option<usize>>,
    /// Whether each geom is drawn: its `group` is 0, 1 or 2, the groups MuJoCo's viewer shows
    /// by default, and it is not fully transparent (ngeom).
    pub geom_drawn: Vec<bool>,
    /// Colour of each site, the material's where the site keeps the default (nsite).
    pub site_rgba: Vec<[f64; 4]>,
    /// Material of each site (nsite).
    pub site_material: Vec<Option<usize>>,
    /// Whether each site is drawn, as for geoms (nsite).
    pub site_drawn: Vec<bool>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Textures.
    pub textures: Vec<Texture>,
    /// The skybox texture, if any (MuJoCo draws the first).
    pub skybox: Option<usize>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Cameras, in MuJoCo's order (by body, then document order).
    pub cameras: Vec<Camera>,
    /// Free camera's vertical field of view, degrees.
    pub fovy: f64,
    /// Free camera's default azimuth, degrees.
    pub azimuth: f64,
    /// Free camera's default elevation, degrees.
    pub elevation: f64,
    /// Near clipping plane as a fraction of the extent.
    pub znear: f64,
    /// Far clipping plane as a fraction of the extent.
    pub zfar: f64,
    /// Headlight ambient colour.
    pub head_ambient: DVec3,
    /// Headlight diffuse colour.
    pub head_diffuse: DVec3,
    /// Headlight specular colour.
    pub head_specular: DVec3,
    /// Whether the headlight is on.
    pub head_active: bool,
    /// The model's extent as given by `<statistic>`, else computed by the renderer at qpos0.
    pub extent: Option<f64>,
    /// The model's centre as given by `<statistic>`.
    pub center: Option<DVec3>,
}
