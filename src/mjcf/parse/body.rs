//! The body tree: `<worldbody>` and each `<body>` with its joints, geoms, sites, cameras, lights,
//! inertial and `<frame>`s.

use glam::{DQuat, DVec3};
use roxmltree::Node;

use super::element::{line, El};
use super::Parser;
use crate::error::Result;
use super::orientation::quat_z_to;
use crate::mjcf::{BodySpec, GeomSpec, GeomType, InertialSpec, JointSpec, JointType, SiteSpec, DEFAULT_GEOM_RGBA, DEFAULT_SITE_RGBA};

pub(super) const JOINT_ATTRS: &[&str] = &[
    "name", "class", "type", "pos", "axis", "ref", "range", "limited", "margin", "armature", "damping", "stiffness",
    "springref", "frictionloss", "springdamper", "actuatorfrcrange", "actuatorfrclimited",
];
pub(super) const GEOM_ATTRS: &[&str] = &[
    "name", "class", "type", "size", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "fromto", "density",
    "mass", "shellinertia", "friction", "contype", "conaffinity", "condim", "priority", "margin", "rgba", "material", "mesh", "hfield",
    "fluidshape", "fluidcoef",
];
pub(super) const SITE_ATTRS: &[&str] =
    &["name", "class", "type", "size", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "fromto"];
pub(super) const BODY_ATTRS: &[&str] = &["name", "childclass", "mocap", "gravcomp", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis"];
pub(super) const INERTIAL_ATTRS: &[&str] =
    &["pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "mass", "diaginertia", "fullinertia"];

impl Parser<'_> {
    pub(super) fn body_children(&mut self, n: Node, body: usize, childclass: Option<&str>) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "body" => self.body(c, body, childclass)?,
                "geom" => {
                    let g = self.geom(c, childclass)?;
                    self.spec.bodies[body].geoms.push(g);
                }
                "site" => {
                    let s = self.site(c, childclass)?;
                    self.spec.bodies[body].sites.push(s);
                }
                "joint" | "freejoint" if body == 0 => return Err(self.err(c, None, "the world body cannot have joints")),
                "joint" | "freejoint" => {
                    let j = self.joint(c, childclass)?;
                    self.spec.bodies[body].joints.push(j);
                }
                "inertial" if body != 0 => {
                    let i = self.inertial(c)?;
                    self.spec.bodies[body].inertial = Some(i);
                }
                "camera" => {
                    let cam = self.camera(c, childclass)?;
                    self.spec.bodies[body].cameras.push(cam);
                }
                "light" => {
                    let l = self.light(c, childclass)?;
                    self.spec.bodies[body].lights.push(l);
                }
                "frame" => self.frame(c, body, childclass)?,
                other => return Err(self.err(c, None, format!("unsupported element <{other}> in a body"))),
            }
        }
        Ok(())
    }

    /// The default class `n`'s children take: its own `childclass`, else the enclosing one's.
    fn childclass(&self, n: Node, enclosing: Option<&str>, e: &El) -> Result<Option<String>> {
        let cc = n.attribute("childclass").or(enclosing).map(str::to_string);
        match &cc {
            Some(c) if !self.classes.contains_key(c) => Err(e.err("childclass", format!("unknown default class '{c}'"))),
            _ => Ok(cc),
        }
    }

    /// A `<frame>`: its children belong to the enclosing body, posed in the frame's pose (and
    /// its `childclass` their default).
    fn frame(&mut self, n: Node, body: usize, childclass: Option<&str>) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        e.check(&["name", "childclass", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis"])?;
        let cc = self.childclass(n, childclass, &e)?;
        let (t, q) = (e.vec3("pos", DVec3::ZERO)?, self.orientation(&e)?);
        let b = &self.spec.bodies[body];
        let before = (self.spec.bodies.len(), b.joints.len(), b.geoms.len(), b.sites.len(), b.cameras.len(), b.lights.len());
        let had_inertial = b.inertial.is_some();
        self.enter(n)?;
        let out = self.body_children(n, body, cc.as_deref());
        self.depth -= 1;
        out?;
        // what the frame's children added, carried from the frame's coordinates to the body's
        let (place, turn) = (|p: DVec3| q * p + t, |r: DQuat| (q * r).normalize());
        for child in self.spec.bodies[before.0..].iter_mut().filter(|c| c.parent == body) {
            (child.pos, child.quat) = (place(child.pos), turn(child.quat));
        }
        let b = &mut self.spec.bodies[body];
        for j in &mut b.joints[before.1..] {
            (j.pos, j.axis) = (place(j.pos), q * j.axis);
        }
        for g in &mut b.geoms[before.2..] {
            (g.pos, g.quat) = (place(g.pos), turn(g.quat));
        }
        for s in &mut b.sites[before.3..] {
            (s.pos, s.quat) = (place(s.pos), turn(s.quat));
        }
        for c in &mut b.cameras[before.4..] {
            (c.pos, c.quat) = (place(c.pos), turn(c.quat));
        }
        for l in &mut b.lights[before.5..] {
            (l.pos, l.dir) = (place(l.pos), q * l.dir);
        }
        if let Some(i) = b.inertial.as_mut().filter(|_| !had_inertial) {
            (i.pos, i.quat) = (place(i.pos), turn(i.quat));
        }
        Ok(())
    }

    pub(super) fn body(&mut self, n: Node, parent: usize, childclass: Option<&str>) -> Result<()> {
        self.enter(n)?;
        let out = self.body_at(n, parent, childclass);
        self.depth -= 1;
        out
    }

    pub(super) fn body_at(&mut self, n: Node, parent: usize, childclass: Option<&str>) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        e.check(BODY_ATTRS)?;
        let mocap = e.tristate("mocap")?.unwrap_or(false);
        if mocap && parent != 0 {
            return Err(e.err("mocap", "a mocap body must be a child of the world body"));
        }
        let cc = self.childclass(n, childclass, &e)?;
        let id = self.spec.bodies.len();
        let name = n.attribute("name").map_or_else(|| format!("body{id}"), str::to_string);
        if self.spec.bodies.iter().any(|b| b.name == name) {
            return Err(e.err("name", format!("duplicate body name '{name}'")));
        }
        self.spec.bodies.push(BodySpec {
            name,
            parent,
            pos: e.vec3("pos", DVec3::ZERO)?,
            quat: self.orientation(&e)?,
            mocap,
            gravcomp: e.f64("gravcomp", 0.0)?,
            // no joints, geoms, sites, inertial, cameras or lights until its children are read
            ..BodySpec::world(e.line)
        });
        self.body_children(n, id, cc.as_deref())?;
        if mocap && !self.spec.bodies[id].joints.is_empty() {
            return Err(e.err("mocap", "a mocap body has no joints"));
        }
        Ok(())
    }

    pub(super) fn joint(&mut self, n: Node, childclass: Option<&str>) -> Result<JointSpec> {
        let e = self.el(n, childclass)?;
        if n.has_tag_name("freejoint") {
            e.check(&["name", "group", "align"])?;
            return Ok(JointSpec {
                name: e.str("name").to_string(),
                kind: JointType::Free,
                pos: DVec3::ZERO,
                axis: DVec3::Z,
                reference: 0.0,
                range: [0.0, 0.0],
                limited: false,
                margin: 0.0,
                armature: 0.0,
                damping: 0.0,
                frictionloss: 0.0,
                stiffness: 0.0,
                springref: 0.0,
                springdamper: None,
                actfrcrange: None,
                line: e.line,
            });
        }
        e.check(JOINT_ATTRS)?;
        let kind = match e.get("type").unwrap_or("hinge") {
            "hinge" => JointType::Hinge,
            "slide" => JointType::Slide,
            "ball" => JointType::Ball,
            "free" => JointType::Free,
            v => return Err(e.err("type", format!("unknown joint type '{v}'"))),
        };
        let axis = e.vec3("axis", DVec3::Z)?;
        if axis.length() < 1e-12 {
            return Err(e.err("axis", "zero axis"));
        }
        let angular = matches!(kind, JointType::Hinge | JointType::Ball);
        let conv = |x: f64| if angular { self.angle(x) } else { x };
        let range = e.arr::<2>("range")?.unwrap_or([0.0, 0.0]);
        // a free joint is never limited, whatever its class says (MuJoCo's mjCJoint::Compile)
        let limited = match e.tristate("limited")? {
            _ if kind == JointType::Free => false,
            Some(l) => l,
            None => self.autolimits && e.has("range"),
        };
        if limited && range[0] >= range[1] && kind != JointType::Ball {
            return Err(e.err("range", format!("limited joint needs range[0] < range[1], got {range:?}")));
        }
        // (time constant, damping ratio); zeros (MuJoCo's default) leave stiffness and damping be
        let springdamper = match e.arr::<2>("springdamper")? {
            Some([tc, dr]) if tc > 0.0 && dr > 0.0 => {
                if !matches!(kind, JointType::Hinge | JointType::Slide) {
                    return Err(e.err("springdamper", "springdamper sets hinge and slide joints"));
                }
                Some([tc, dr])
            }
            Some([tc, dr]) if tc < 0.0 || dr < 0.0 => return Err(e.err("springdamper", format!("must be non-negative, got {tc} {dr}"))),
            _ => None,
        };
        // MuJoCo's clamp on the total actuator force at a hinge or slide joint
        let frc = e.arr::<2>("actuatorfrcrange")?.unwrap_or([0.0, 0.0]);
        let frc_limited = e.tristate("actuatorfrclimited")?.unwrap_or(self.autolimits && frc != [0.0, 0.0]);
        let actfrcrange = (frc_limited && matches!(kind, JointType::Hinge | JointType::Slide)).then_some(frc);
        if actfrcrange.is_some() && frc[0] >= frc[1] {
            return Err(e.err("actuatorfrcrange", format!("needs actuatorfrcrange[0] < actuatorfrcrange[1], got {frc:?}")));
        }
        Ok(JointSpec {
            name: e.str("name").to_string(),
            kind,
            pos: e.vec3("pos", DVec3::ZERO)?,
            axis: axis.normalize(),
            reference: conv(e.f64("ref", 0.0)?),
            range: [conv(range[0]), conv(range[1])],
            limited,
            margin: e.nonneg("margin", 0.0)?,
            armature: e.nonneg("armature", 0.0)?,
            damping: e.nonneg("damping", 0.0)?,
            frictionloss: e.nonneg("frictionloss", 0.0)?,
            stiffness: e.nonneg("stiffness", 0.0)?,
            springref: conv(e.f64("springref", 0.0)?),
            springdamper,
            actfrcrange,
            line: e.line,
        })
    }

    pub(super) fn geom(&mut self, n: Node, childclass: Option<&str>) -> Result<GeomSpec> {
        let e = self.el(n, childclass)?;
        e.check(GEOM_ATTRS)?;
        let kind = match e.get("type").unwrap_or("sphere") {
            "plane" => GeomType::Plane,
            "sphere" => GeomType::Sphere,
            "capsule" => GeomType::Capsule,
            "cylinder" => GeomType::Cylinder,
            "box" => GeomType::Box,
            "ellipsoid" => GeomType::Ellipsoid,
            "mesh" => GeomType::Mesh,
            "hfield" => GeomType::Hfield,
            v => return Err(e.err("type", format!("unsupported geom type '{v}'"))),
        };
        let (mesh, hfield) = geom_assets(&e, kind)?;
        let given = e.nums("size")?.unwrap_or_default();
        let needed = match kind {
            GeomType::Sphere => 1,
            GeomType::Capsule | GeomType::Cylinder => if e.has("fromto") { 1 } else { 2 },
            GeomType::Box | GeomType::Ellipsoid => if e.has("fromto") { 2 } else { 3 },
            GeomType::Plane | GeomType::Mesh | GeomType::Hfield => 0,
        };
        if given.len() < needed {
            return Err(e.err("size", format!("{kind:?} needs {needed} size values, got {}", given.len())));
        }
        let mut size = [0.0; 3];
        for (s, g) in size.iter_mut().zip(&given) {
            *s = *g;
        }
        if size[..needed].iter().any(|&s| s <= 0.0) {
            return Err(e.err("size", format!("sizes must be positive, got {given:?}")));
        }
        let (mut pos, mut quat) = (e.vec3("pos", DVec3::ZERO)?, self.orientation(&e)?);
        if let Some(ft) = e.arr::<6>("fromto")? {
            if matches!(kind, GeomType::Plane | GeomType::Sphere | GeomType::Mesh | GeomType::Hfield) {
                return Err(e.err("fromto", "fromto needs a capsule, cylinder, box or ellipsoid"));
            }
            let (a, b) = (DVec3::new(ft[0], ft[1], ft[2]), DVec3::new(ft[3], ft[4], ft[5]));
            let d = b - a;
            if d.length() < 1e-12 {
                return Err(e.err("fromto", "zero length"));
            }
            pos = (a + b) * 0.5;
            // MuJoCo's frame: +z turned onto from − to by the shortest rotation
            quat = quat_z_to(-d.normalize());
            let half = d.length() * 0.5;
            match kind {
                GeomType::Capsule | GeomType::Cylinder => size[1] = half,
                _ => size[2] = half,
            }
        }
        let mass = e.arr::<1>("mass")?.map(|m| m[0]);
        if mass.is_some_and(|m| m < 0.0) {
            return Err(e.err("mass", "must be non-negative"));
        }
        let friction = e.nums("friction")?.unwrap_or_else(|| vec![1.0, 0.005, 0.0001]);
        if friction.is_empty() || friction.len() > 3 || friction.iter().any(|&f| f < 0.0) {
            return Err(e.err("friction", "expected 1 to 3 non-negative numbers"));
        }
        let mut fr = [1.0, 0.005, 0.0001];
        fr[..friction.len()].copy_from_slice(&friction);
        let condim = self.condim(&e)?;
        let shell = self.shell_inertia(&e, kind)?;
        Ok(GeomSpec {
            name: e.str("name").to_string(),
            kind,
            size,
            pos,
            quat,
            density: e.nonneg("density", 1000.0)?,
            mass,
            shell,
            friction: fr,
            contype: e.uint("contype", 1)?,
            conaffinity: e.uint("conaffinity", 1)?,
            condim,
            priority: e.int("priority", 0)?,
            margin: e.nonneg("margin", 0.0)?,
            rgba: e.rgba("rgba", DEFAULT_GEOM_RGBA)?,
            material: e.get("material").map(str::to_string),
            mesh,
            hfield,
            group: e.int("group", 0)?,
            fluid: fluid_shape(&e)?,
            line: e.line,
        })
    }

    /// A geom's `shellinertia`, with a warning where sinew gives the shape no shell.
    fn shell_inertia(&self, e: &El, kind: GeomType) -> Result<bool> {
        let shell = e.tristate("shellinertia")?.unwrap_or(false);
        if shell && matches!(kind, GeomType::Ellipsoid | GeomType::Mesh) {
            self.warnings.borrow_mut().push(format!(
                "<geom> '{}' at line {}: shellinertia on an ellipsoid or a mesh is not modelled (its mass and inertia are the solid's)",
                e.str("name"),
                e.line
            ));
        }
        Ok(shell)
    }

    /// A geom's or pair's `condim` (1, 3, 4 or 6; default 3).
    pub(super) fn condim(&self, e: &El) -> Result<u32> {
        let condim = e.uint("condim", 3)?;
        if ![1, 3, 4, 6].contains(&condim) {
            return Err(e.err("condim", format!("must be 1, 3, 4 or 6, got {condim}")));
        }
        Ok(condim)
    }

    pub(super) fn site(&mut self, n: Node, childclass: Option<&str>) -> Result<SiteSpec> {
        let e = self.el(n, childclass)?;
        e.check(SITE_ATTRS)?;
        let (mut pos, mut quat) = (e.vec3("pos", DVec3::ZERO)?, self.orientation(&e)?);
        if let Some(ft) = e.arr::<6>("fromto")? {
            let (a, b) = (DVec3::new(ft[0], ft[1], ft[2]), DVec3::new(ft[3], ft[4], ft[5]));
            pos = (a + b) * 0.5;
            if (b - a).length() > 1e-12 {
                // MuJoCo's frame: +z turned onto from − to
                quat = quat_z_to((a - b).normalize());
            }
        }
        let kind = match e.get("type").unwrap_or("sphere") {
            "sphere" => GeomType::Sphere,
            "capsule" => GeomType::Capsule,
            "cylinder" => GeomType::Cylinder,
            "box" => GeomType::Box,
            "ellipsoid" => GeomType::Ellipsoid,
            v => return Err(e.err("type", format!("unsupported site type '{v}'"))),
        };
        // MuJoCo's default size, each given number replacing its own
        let mut size = [0.005; 3];
        for (s, g) in size.iter_mut().zip(e.nums("size")?.unwrap_or_default()) {
            *s = g;
        }
        if let Some(ft) = e.arr::<6>("fromto")? {
            let half = 0.5 * (DVec3::from_slice(&ft[3..]) - DVec3::from_slice(&ft[..3])).length();
            size[if matches!(kind, GeomType::Box | GeomType::Ellipsoid) { 2 } else { 1 }] = half;
        }
        let (rgba, material, group) = (e.rgba("rgba", DEFAULT_SITE_RGBA)?, e.get("material").map(str::to_string), e.int("group", 0)?);
        Ok(SiteSpec { name: e.str("name").to_string(), pos, quat, kind, size, rgba, material, group, line: e.line })
    }

    pub(super) fn inertial(&mut self, n: Node) -> Result<InertialSpec> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        e.check(INERTIAL_ATTRS)?;
        let mass = e.arr::<1>("mass")?.ok_or_else(|| e.err("mass", "required"))?[0];
        if mass < 0.0 {
            return Err(e.err("mass", "must be non-negative"));
        }
        let inertia = match (e.arr::<3>("diaginertia")?, e.arr::<6>("fullinertia")?) {
            (Some(d), None) => [d[0], d[1], d[2], 0.0, 0.0, 0.0],
            (None, Some(f)) => [f[0], f[1], f[2], f[3], f[4], f[5]],
            (None, None) => return Err(e.err("diaginertia", "diaginertia or fullinertia is required")),
            (Some(_), Some(_)) => return Err(e.err("fullinertia", "conflicts with diaginertia")),
        };
        Ok(InertialSpec { mass, pos: e.vec3("pos", DVec3::ZERO)?, quat: self.orientation(&e)?, inertia })
    }
}

/// A geom's `mesh` and `hfield` assets: a mesh geom needs the one, a height-field geom the other,
/// and no other geom takes either (fitting a primitive to a mesh is not supported).
fn geom_assets(e: &El, kind: GeomType) -> Result<(Option<String>, Option<String>)> {
    let mesh = e.get("mesh").map(str::to_string);
    match (kind, &mesh) {
        (GeomType::Mesh, None) => return Err(e.err("mesh", "a mesh geom needs a mesh")),
        (GeomType::Mesh, Some(_)) | (_, None) => {}
        (_, Some(_)) => return Err(e.err("mesh", "fitting a primitive geom to a mesh is not supported; use type=\"mesh\"")),
    }
    let hfield = e.get("hfield").map(str::to_string);
    if (kind == GeomType::Hfield) != hfield.is_some() {
        return Err(e.err("hfield", "a height-field geom needs an hfield, and only it takes one"));
    }
    Ok((mesh, hfield))
}

/// `fluidshape` and `fluidcoef`: the ellipsoid fluid model's coefficients when the geom takes part
/// (MuJoCo's defaults 0.5, 0.25, 1.5, 1, 1 for those not given).
fn fluid_shape(e: &El) -> Result<Option<[f64; 5]>> {
    match e.get("fluidshape").unwrap_or("none") {
        "none" => Ok(None),
        "ellipsoid" => {
            let mut coef = [0.5, 0.25, 1.5, 1.0, 1.0];
            let given = e.nums("fluidcoef")?.unwrap_or_default();
            if given.len() > 5 || given.iter().any(|&c| !c.is_finite()) {
                return Err(e.err("fluidcoef", "expected at most five finite numbers"));
            }
            coef[..given.len()].copy_from_slice(&given);
            Ok(Some(coef))
        }
        other => Err(e.err("fluidshape", format!("'{other}': none or ellipsoid"))),
    }
}
