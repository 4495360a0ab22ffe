//! The visual elements of a description, every name resolved against the compiled bodies.

use glam::{DMat3, DVec3};

use crate::error::{Error, Result};
use crate::mjcf::{LightSpec, ModelSpec, TextureKind, DEFAULT_GEOM_RGBA, DEFAULT_SITE_RGBA};
use crate::model::visual::{Camera, Light, Material, Texture, Visual};

/// The materials, each texture name resolved.
fn materials(spec: &ModelSpec) -> Result<Vec<Material>> {
    let v = &spec.visual;
    let find_tex = |name: &str, line: u32| {
        v.textures
            .iter()
            .position(|t| t.name == name)
            .ok_or_else(|| Error::model("material", Some("texture"), line, format!("unknown texture '{name}'")))
    };
    v.materials
        .iter()
        .map(|m| {
            Ok(Material {
                texture: m.texture.as_deref().map(|t| find_tex(t, m.line)).transpose()?,
                texrepeat: m.texrepeat,
                texuniform: m.texuniform,
                emission: m.emission,
                specular: m.specular,
                shininess: m.shininess,
                reflectance: m.reflectance,
            })
        })
        .collect()
}

/// Resolves the names of `spec`'s visual elements against the compiled bodies (`body_id`).
pub(super) fn compile(spec: &ModelSpec, body_id: impl Fn(&str) -> Option<usize>) -> Result<Visual> {
    let v = &spec.visual;
    let textures: Vec<Texture> = v
        .textures
        .iter()
        .map(|t| Texture { kind: t.kind, builtin: t.builtin, rgb1: DVec3::from_array(t.rgb1), rgb2: DVec3::from_array(t.rgb2) })
        .collect();
    let materials = materials(spec)?;
    let target = |name: &Option<String>, tag: &str, line: u32| -> Result<Option<usize>> {
        name.as_deref()
            .map(|n| body_id(n).ok_or_else(|| Error::model(tag, Some("target"), line, format!("unknown body '{n}'"))))
            .transpose()
    };
    let (mut geom_rgba, mut geom_material, mut lights, mut cameras) = (vec![], vec![], vec![], vec![]);
    let (mut site_rgba, mut site_material) = (vec![], vec![]);
    // MuJoCo: an element with a material and the default colour takes the material's
    let look = |tag: &str, material: &Option<String>, rgba: [f64; 4], default: [f64; 4], line: u32| -> Result<(Option<usize>, [f64; 4])> {
        let mat = material
            .as_deref()
            .map(|name| v.materials.iter().position(|m| m.name == name).ok_or_else(|| Error::model(tag, Some("material"), line, format!("unknown material '{name}'"))))
            .transpose()?;
        Ok((mat, match mat {
            Some(i) if rgba == default => v.materials[i].rgba,
            _ => rgba,
        }))
    };
    for (b, body) in spec.bodies.iter().enumerate() {
        for g in &body.geoms {
            let (mat, rgba) = look("geom", &g.material, g.rgba, DEFAULT_GEOM_RGBA, g.line)?;
            geom_rgba.push(rgba);
            geom_material.push(mat);
        }
        for s in &body.sites {
            let (mat, rgba) = look("site", &s.material, s.rgba, DEFAULT_SITE_RGBA, s.line)?;
            site_rgba.push(rgba);
            site_material.push(mat);
        }
        for l in &body.lights {
            lights.push(light(b, l, target(&l.target, "light", body.line)?));
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
    unique_camera_names(&cameras)?;
    // MuJoCo's viewer shows groups 0–2; a fully transparent element shows nothing
    let shown = |group: i32, rgba: &[f64; 4]| (0..3).contains(&group) && rgba[3] > 0.0;
    let geom_drawn = spec.bodies.iter().flat_map(|b| &b.geoms).zip(&geom_rgba).map(|(g, c)| shown(g.group, c)).collect();
    let site_drawn = spec.bodies.iter().flat_map(|b| &b.sites).zip(&site_rgba).map(|(s, c)| shown(s.group, c)).collect();
    Ok(Visual {
        geom_rgba,
        geom_material,
        geom_drawn,
        site_rgba,
        site_material,
        site_drawn,
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

/// Light `l` of body `b`, aimed at body `target` (if any).
fn light(b: usize, l: &LightSpec, target: Option<usize>) -> Light {
    Light {
        body: b,
        mode: l.mode,
        target,
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
    }
}

/// A named camera is chosen by name, so two may not share one.
fn unique_camera_names(cameras: &[Camera]) -> Result<()> {
    match cameras.iter().enumerate().find(|(i, c)| !c.name.is_empty() && cameras[..*i].iter().any(|o| o.name == c.name)) {
        Some((_, c)) => Err(Error::Compile(format!("duplicate camera name '{}'", c.name))),
        None => Ok(()),
    }
}
