//! How a compiled model looks: colours, materials, textures, lights, cameras and the free
//! camera's defaults, every name resolved to an index (MuJoCo's `geom_rgba`, `mat_*`, `tex_*`,
//! `light_*`, `cam_*` and `mjVisual`). The renderer reads it; the physics never does.

use glam::{DMat3, DVec3};

use crate::error::{Error, Result};
pub use crate::mjcf::{Builtin, TextureKind, TrackMode};
use crate::mjcf::{ModelSpec, DEFAULT_GEOM_RGBA};

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

/// Resolves the names of `spec`'s visual elements against the compiled bodies (`body_id`).
pub(super) fn compile(spec: &ModelSpec, body_id: impl Fn(&str) -> Option<usize>) -> Result<Visual> {
    let v = &spec.visual;
    let textures: Vec<Texture> = v
        .textures
        .iter()
        .map(|t| Texture { kind: t.kind, builtin: t.builtin, rgb1: DVec3::from_array(t.rgb1), rgb2: DVec3::from_array(t.rgb2) })
        .collect();
    let find_tex = |name: &str, line: u32| {
        v.textures
            .iter()
            .position(|t| t.name == name)
            .ok_or_else(|| Error::model("material", Some("texture"), line, format!("unknown texture '{name}'")))
    };
    let mut materials = Vec::with_capacity(v.materials.len());
    for m in &v.materials {
        materials.push(Material {
            texture: m.texture.as_deref().map(|t| find_tex(t, m.line)).transpose()?,
            texrepeat: m.texrepeat,
            texuniform: m.texuniform,
            emission: m.emission,
            specular: m.specular,
            shininess: m.shininess,
            reflectance: m.reflectance,
        });
    }
    let target = |name: &Option<String>, tag: &str, line: u32| -> Result<Option<usize>> {
        name.as_deref()
            .map(|n| body_id(n).ok_or_else(|| Error::model(tag, Some("target"), line, format!("unknown body '{n}'"))))
            .transpose()
    };
    let (mut geom_rgba, mut geom_material, mut lights, mut cameras) = (vec![], vec![], vec![], vec![]);
    for (b, body) in spec.bodies.iter().enumerate() {
        for g in &body.geoms {
            let mat = match &g.material {
                None => None,
                Some(name) => Some(v.materials.iter().position(|m| &m.name == name).ok_or_else(|| {
                    Error::model("geom", Some("material"), g.line, format!("unknown material '{name}'"))
                })?),
            };
            // MuJoCo: a geom with a material and the default colour takes the material's
            geom_rgba.push(match mat {
                Some(i) if g.rgba == DEFAULT_GEOM_RGBA => v.materials[i].rgba,
                _ => g.rgba,
            });
            geom_material.push(mat);
        }
        for l in &body.lights {
            lights.push(Light {
                body: b,
                mode: l.mode,
                target: target(&l.target, "light", body.line)?,
                directional: l.directional,
                castshadow: l.castshadow,
                active: l.active,
                pos: l.pos,
                dir: l.dir,
                diffuse: DVec3::from_array(l.diffuse),
                ambient: DVec3::from_array(l.ambient),
                specular: DVec3::from_array(l.specular),
                attenuation: l.attenuation,
                cos_cutoff: l.cutoff.to_radians().cos(),
                exponent: l.exponent,
            });
        }
        for c in &body.cameras {
            cameras.push(Camera {
                name: c.name.clone(),
                body: b,
                mode: c.mode,
                target: target(&c.target, "camera", c.line)?,
                pos: c.pos,
                mat: DMat3::from_quat(c.quat),
                fovy: c.fovy,
            });
        }
    }
    for (i, c) in cameras.iter().enumerate() {
        if !c.name.is_empty() && cameras[..i].iter().any(|o| o.name == c.name) {
            return Err(Error::Compile(format!("duplicate camera name '{}'", c.name)));
        }
    }
    Ok(Visual {
        geom_rgba,
        geom_material,
        materials,
        skybox: textures.iter().position(|t| t.kind == TextureKind::Skybox),
        textures,
        lights,
        cameras,
        fovy: v.fovy,
        azimuth: v.azimuth,
        elevation: v.elevation,
        znear: v.znear,
        zfar: v.zfar,
        head_ambient: DVec3::from_array(v.head_ambient),
        head_diffuse: DVec3::from_array(v.head_diffuse),
        head_specular: DVec3::from_array(v.head_specular),
        head_active: v.head_active,
        extent: v.extent,
        center: v.center,
    })
}
