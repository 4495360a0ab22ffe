//! What MJCF says about how a model looks: geom colours live on [`super::GeomSpec`]; textures,
//! materials, lights, cameras and `<visual>` here. None of it changes the physics.

use glam::{DQuat, DVec3};

/// How a camera or light moves with its body (MuJoCo's `mjtCamLight`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackMode {
    /// Rigidly attached to its body.
    Fixed,
    /// Constant world offset from its body's origin and constant world orientation (both as at
    /// qpos0).
    Track,
    /// As `Track`, offset from its body's subtree centre of mass.
    TrackCom,
    /// Positioned as `Fixed`, oriented towards the target body's origin.
    TargetBody,
    /// Positioned as `Fixed`, oriented towards the target body's subtree centre of mass.
    TargetBodyCom,
}

/// A `<camera>`.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraSpec {
    /// Name (may be empty).
    pub name: String,
    /// How it follows its body.
    pub mode: TrackMode,
    /// Target body name (target modes).
    pub target: Option<String>,
    /// Position in the body frame.
    pub pos: DVec3,
    /// Orientation in the body frame; the camera looks along −z with +y up.
    pub quat: DQuat,
    /// Vertical field of view, degrees.
    pub fovy: f64,
    /// Source line.
    pub line: u32,
}

/// A `<light>`.
#[derive(Clone, Debug, PartialEq)]
pub struct LightSpec {
    /// How it follows its body.
    pub mode: TrackMode,
    /// Target body name (target modes).
    pub target: Option<String>,
    /// Directional (at infinity) rather than a spotlight.
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
    pub diffuse: [f64; 3],
    /// Ambient colour.
    pub ambient: [f64; 3],
    /// Specular colour.
    pub specular: [f64; 3],
    /// Constant, linear and quadratic attenuation.
    pub attenuation: [f64; 3],
    /// Spotlight cutoff angle, degrees.
    pub cutoff: f64,
    /// Spotlight exponent.
    pub exponent: f64,
}

/// Texture kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureKind {
    /// A 2D image, tiled over a surface.
    TwoD,
    /// A cube map around the geom.
    Cube,
    /// The background.
    Skybox,
}

/// Procedural texture patterns (`builtin`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// No built-in pattern (a file texture, drawn as its mean colour is unknown: white).
    None,
    /// `rgb1` everywhere.
    Flat,
    /// 2 × 2 checks of `rgb1` and `rgb2`.
    Checker,
    /// `rgb1` above blending into `rgb2` below.
    Gradient,
}

/// A `<texture>`.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureSpec {
    /// Name (may be empty: a skybox needs none).
    pub name: String,
    /// Kind.
    pub kind: TextureKind,
    /// Pattern.
    pub builtin: Builtin,
    /// First colour.
    pub rgb1: [f64; 3],
    /// Second colour.
    pub rgb2: [f64; 3],
}

/// A `<material>`.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSpec {
    /// Name.
    pub name: String,
    /// Texture name.
    pub texture: Option<String>,
    /// Texture repetitions over the surface (per metre with `texuniform`).
    pub texrepeat: [f64; 2],
    /// Whether `texrepeat` counts per metre rather than per surface.
    pub texuniform: bool,
    /// Colour, used where the geom keeps MuJoCo's default rgba.
    pub rgba: [f64; 4],
    /// Emission, as a multiple of the colour.
    pub emission: f64,
    /// Specular reflectance in [0, 1].
    pub specular: f64,
    /// Shininess in [0, 1] (Phong exponent / 128).
    pub shininess: f64,
    /// Mirror reflectance in [0, 1].
    pub reflectance: f64,
    /// Source line.
    pub line: u32,
}

/// `<visual>` and `<statistic>`: the free camera's defaults, clipping and the headlight.
#[derive(Clone, Debug, PartialEq)]
pub struct VisualSpec {
    /// Textures in document order.
    pub textures: Vec<TextureSpec>,
    /// Materials in document order.
    pub materials: Vec<MaterialSpec>,
    /// Free camera's vertical field of view, degrees (`<global fovy>`).
    pub fovy: f64,
    /// Free camera's default azimuth, degrees.
    pub azimuth: f64,
    /// Free camera's default elevation, degrees.
    pub elevation: f64,
    /// Near clipping plane as a fraction of the model extent (`<map znear>`).
    pub znear: f64,
    /// Far clipping plane as a fraction of the model extent (`<map zfar>`).
    pub zfar: f64,
    /// Headlight ambient colour.
    pub head_ambient: [f64; 3],
    /// Headlight diffuse colour.
    pub head_diffuse: [f64; 3],
    /// Headlight specular colour.
    pub head_specular: [f64; 3],
    /// Whether the headlight is on.
    pub head_active: bool,
    /// `<statistic extent>`, overriding the computed extent.
    pub extent: Option<f64>,
    /// `<statistic center>`, overriding the computed centre.
    pub center: Option<DVec3>,
}

impl Default for VisualSpec {
    /// MuJoCo's defaults (`mj_defaultVisual`).
    fn default() -> Self {
        VisualSpec {
            textures: vec![],
            materials: vec![],
            fovy: 45.0,
            azimuth: 90.0,
            elevation: -45.0,
            znear: 0.01,
            zfar: 50.0,
            head_ambient: [0.1; 3],
            head_diffuse: [0.4; 3],
            head_specular: [0.5; 3],
            head_active: true,
            extent: None,
            center: None,
        }
    }
}

/// MuJoCo's default geom colour: a geom with a material and this colour takes the material's.
pub const DEFAULT_GEOM_RGBA: [f64; 4] = [0.5, 0.5, 0.5, 1.0];
/// MuJoCo's default site colour.
pub const DEFAULT_SITE_RGBA: [f64; 4] = [0.5, 0.5, 0.5, 1.0];
