//! The visual elements of MJCF: `<visual>`, `<statistic>`, `<asset>` textures and materials, and
//! body `<camera>`s and `<light>`s (MuJoCo's XML reference gives every default used here).

use roxmltree::Node;

use super::{line, El, Parser};
use crate::error::Result;
use crate::mjcf::{Builtin, CameraSpec, LightSpec, MaterialSpec, TextureKind, TextureSpec, TrackMode};

impl El<'_, '_> {
    /// `n` non-negative numbers (colours and their alpha: MuJoCo takes a colour above 1 as
    /// brighter, and the renderer clamps what it draws).
    fn unit<const N: usize>(&self, name: &str, default: [f64; N]) -> Result<[f64; N]> {
        let v = self.arr::<N>(name)?.unwrap_or(default);
        if v.iter().any(|&x| x < 0.0) {
            return Err(self.err(name, format!("values must be non-negative, got {v:?}")));
        }
        Ok(v)
    }
    pub(super) fn rgba(&self, name: &str, default: [f64; 4]) -> Result<[f64; 4]> {
        let [r, g, b, a] = self.unit(name, default)?;
        Ok([r, g, b, a.min(1.0)])
    }
    fn flag(&self, name: &str, default: bool) -> Result<bool> {
        match self.get(name) {
            None => Ok(default),
            Some("true") => Ok(true),
            Some("false") => Ok(false),
            Some(v) => Err(self.err(name, format!("expected true or false, got '{v}'"))),
        }
    }
    fn mode(&self) -> Result<(TrackMode, Option<String>)> {
        let mode = match self.get("mode").unwrap_or("fixed") {
            "fixed" => TrackMode::Fixed,
            "track" => TrackMode::Track,
            "trackcom" => TrackMode::TrackCom,
            "targetbody" => TrackMode::TargetBody,
            "targetbodycom" => TrackMode::TargetBodyCom,
            v => return Err(self.err("mode", format!("expected fixed, track, trackcom, targetbody or targetbodycom, got '{v}'"))),
        };
        let target = self.get("target").map(str::to_string);
        if matches!(mode, TrackMode::TargetBody | TrackMode::TargetBodyCom) && target.is_none() {
            return Err(self.err("target", "a target mode needs a target body"));
        }
        Ok((mode, target))
    }
}

impl Parser<'_> {
    /// A plain reader (no default classes) for the elements of `<visual>`, `<statistic>`.
    fn plain<'a, 'd>(&self, n: Node<'a, 'd>) -> El<'a, 'd> {
        El { node: n, line: line(self.doc, n), defaults: vec![] }
    }

    pub(super) fn visual(&mut self, n: Node) -> Result<()> {
        let v = &mut self.spec.visual;
        for c in n.children().filter(Node::is_element) {
            let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
            match c.tag_name().name() {
                "global" => {
                    v.fovy = e.f64("fovy", v.fovy)?;
                    if !(v.fovy > 0.0 && v.fovy < 180.0) {
                        return Err(e.err("fovy", format!("must be in (0, 180) degrees, got {}", v.fovy)));
                    }
                    v.azimuth = e.f64("azimuth", v.azimuth)?;
                    v.elevation = e.f64("elevation", v.elevation)?;
                }
                "map" => {
                    v.znear = e.f64("znear", v.znear)?;
                    v.zfar = e.f64("zfar", v.zfar)?;
                    if !(v.znear > 0.0 && v.zfar > v.znear) {
                        return Err(e.err("znear", format!("needs 0 < znear < zfar, got {} and {}", v.znear, v.zfar)));
                    }
                }
                "headlight" => {
                    v.head_ambient = e.unit("ambient", v.head_ambient)?;
                    v.head_diffuse = e.unit("diffuse", v.head_diffuse)?;
                    v.head_specular = e.unit("specular", v.head_specular)?;
                    v.head_active = e.uint("active", 1)? != 0;
                }
                _ => {}
            }
        }
        Ok(())
    }

    pub(super) fn statistic(&mut self, n: Node) -> Result<()> {
        let e = self.plain(n);
        if let Some(x) = e.arr::<1>("extent")? {
            if x[0] <= 0.0 {
                return Err(e.err("extent", format!("must be positive, got {}", x[0])));
            }
            self.spec.visual.extent = Some(x[0]);
        }
        self.spec.visual.center = e.arr::<3>("center")?.map(glam::DVec3::from_array);
        Ok(())
    }

    pub(super) fn asset(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "texture" => {
                    let t = self.texture(c)?;
                    self.spec.visual.textures.push(t);
                }
                "material" => {
                    let m = self.material(c)?;
                    if self.spec.visual.materials.iter().any(|o| o.name == m.name) {
                        return Err(self.err(c, Some("name"), format!("duplicate material name '{}'", m.name)));
                    }
                    self.spec.visual.materials.push(m);
                }
                "mesh" => {
                    let m = self.mesh(c)?;
                    if self.spec.meshes.iter().any(|o| o.name == m.name) {
                        return Err(self.err(c, Some("name"), format!("duplicate mesh name '{}'", m.name)));
                    }
                    self.spec.meshes.push(m);
                }
                "hfield" => {
                    let h = self.hfield(c)?;
                    if self.spec.hfields.iter().any(|o| o.name == h.name) {
                        return Err(self.err(c, Some("name"), format!("duplicate hfield name '{}'", h.name)));
                    }
                    self.spec.hfields.push(h);
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn texture(&mut self, n: Node) -> Result<TextureSpec> {
        let e = self.el(n, None)?;
        let kind = match e.get("type").unwrap_or("cube") {
            "2d" => TextureKind::TwoD,
            "cube" => TextureKind::Cube,
            "skybox" => TextureKind::Skybox,
            v => return Err(e.err("type", format!("expected 2d, cube or skybox, got '{v}'"))),
        };
        let builtin = match e.get("builtin").unwrap_or("none") {
            "none" => Builtin::None,
            "flat" => Builtin::Flat,
            "checker" => Builtin::Checker,
            "gradient" => Builtin::Gradient,
            v => return Err(e.err("builtin", format!("expected none, flat, checker or gradient, got '{v}'"))),
        };
        if builtin == Builtin::None && (e.has("file") || e.has("fileright")) {
            self.warnings.borrow_mut().push(format!(
                "<texture> '{}' at line {}: image files are not drawn by sinew's renderer (it draws the surface untextured)",
                e.str("name"),
                e.line
            ));
        }
        // an unnamed texture is named by its file, as in MuJoCo (stem, no directory)
        let file_stem = e.get("file").and_then(|f| std::path::Path::new(f).file_stem()).map(|s| s.to_string_lossy().into_owned());
        Ok(TextureSpec {
            name: e.get("name").map(str::to_string).or(file_stem).unwrap_or_default(),
            kind,
            builtin,
            rgb1: e.unit("rgb1", [0.8; 3])?,
            rgb2: e.unit("rgb2", [0.5; 3])?,
        })
    }

    fn material(&mut self, n: Node) -> Result<MaterialSpec> {
        let e = self.el(n, None)?;
        let name = e.get("name").filter(|s| !s.is_empty()).ok_or_else(|| e.err("name", "a material needs a name"))?;
        let texrepeat = e.arr::<2>("texrepeat")?.unwrap_or([1.0, 1.0]);
        if texrepeat.iter().any(|&r| r <= 0.0) {
            return Err(e.err("texrepeat", format!("must be positive, got {texrepeat:?}")));
        }
        let emission = e.nonneg("emission", 0.0)?;
        Ok(MaterialSpec {
            name: name.to_string(),
            texture: e.get("texture").map(str::to_string),
            texrepeat,
            texuniform: e.flag("texuniform", false)?,
            rgba: e.rgba("rgba", [1.0; 4])?,
            emission,
            specular: e.unit("specular", [0.5])?[0],
            shininess: e.unit("shininess", [0.5])?[0],
            reflectance: e.unit("reflectance", [0.0])?[0],
            line: e.line,
        })
    }

    pub(super) fn camera(&mut self, n: Node, childclass: Option<&str>) -> Result<CameraSpec> {
        let e = self.el(n, childclass)?;
        let (mode, target) = e.mode()?;
        let fovy = e.f64("fovy", 45.0)?;
        if !(fovy > 0.0 && fovy < 180.0) {
            return Err(e.err("fovy", format!("must be in (0, 180) degrees, got {fovy}")));
        }
        Ok(CameraSpec {
            name: e.str("name").to_string(),
            mode,
            target,
            pos: e.vec3("pos", glam::DVec3::ZERO)?,
            quat: self.orientation(&e)?,
            fovy,
            line: e.line,
        })
    }

    pub(super) fn light(&mut self, n: Node, childclass: Option<&str>) -> Result<LightSpec> {
        let e = self.el(n, childclass)?;
        let (mode, target) = e.mode()?;
        let dir = e.vec3("dir", glam::DVec3::NEG_Z)?;
        if dir.length() < 1e-12 {
            return Err(e.err("dir", "zero direction"));
        }
        let directional = match e.get("type") {
            Some("directional") => true,
            Some("spot") | Some("point") => false,
            Some(v) => return Err(e.err("type", format!("expected spot, directional or point, got '{v}'"))),
            None => e.flag("directional", false)?,
        };
        Ok(LightSpec {
            mode,
            target,
            directional,
            castshadow: e.flag("castshadow", true)?,
            active: e.flag("active", true)?,
            pos: e.vec3("pos", glam::DVec3::ZERO)?,
            dir: dir.normalize(),
            diffuse: e.unit("diffuse", [0.7; 3])?,
            ambient: e.unit("ambient", [0.0; 3])?,
            specular: e.unit("specular", [0.3; 3])?,
            attenuation: e.arr::<3>("attenuation")?.unwrap_or([1.0, 0.0, 0.0]),
            cutoff: e.f64("cutoff", 45.0)?,
            exponent: e.nonneg("exponent", 10.0)?,
        })
    }
}
