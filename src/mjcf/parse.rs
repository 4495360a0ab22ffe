//! MJCF text → [`ModelSpec`]: XML walk, default classes, unit and orientation conversion.

use std::cell::RefCell;
use std::collections::HashMap;

use glam::{DQuat, DVec3};
use roxmltree::{Document, Node};

use super::*;

mod elements;
mod orientation;
mod visual;

use orientation::quat_z_to;
use crate::error::{Error, Result};

/// One `<default class>`: attributes per element kind and the parent class.
#[derive(Default)]
struct Class {
    parent: Option<String>,
    attrs: HashMap<String, Vec<(String, String)>>,
}

struct Parser<'d> {
    doc: &'d Document<'d>,
    /// Nesting depth of the `<body>` or `<default>` being read.
    depth: usize,
    degree: bool,
    eulerseq: [u8; 3],
    autolimits: bool,
    classes: HashMap<String, Class>,
    warnings: RefCell<Vec<String>>,
    spec: ModelSpec,
}

/// Attributes each element accepts; everything else is rejected with its name and line.
/// Attributes listed under `IGNORED` are accepted and have no effect in sinew.
const JOINT_ATTRS: &[&str] = &[
    "name", "class", "type", "pos", "axis", "ref", "range", "limited", "margin", "armature", "damping", "stiffness",
    "springref",
];
const GEOM_ATTRS: &[&str] = &[
    "name", "class", "type", "size", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "fromto", "density",
    "mass", "friction", "contype", "conaffinity", "condim", "priority", "margin", "rgba", "material",
];
const SITE_ATTRS: &[&str] =
    &["name", "class", "type", "size", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "fromto"];
const MOTOR_ATTRS: &[&str] =
    &["name", "class", "joint", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited"];
const BODY_ATTRS: &[&str] = &["name", "childclass", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis"];
const INERTIAL_ATTRS: &[&str] =
    &["pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "mass", "diaginertia", "fullinertia"];
/// Visual and soft-constraint attributes: accepted, no effect on sinew's exact constraints.
const IGNORED: &[&str] = &[
    "rgba", "material", "group", "user", "solref", "solimp", "solmix", "solreflimit", "solimplimit",
    "gap",
];
/// Deepest nesting of `<body>` or `<default>` elements accepted (gymnasium's models nest at most 7).
pub const MAX_NESTING: usize = 200;

/// Largest magnitude of any number in a model file: sinew's bound on a state entry.
pub const MAX_VALUE: f64 = crate::math::MAX_STATE;

/// Attributes that change MuJoCo's physics but are not modelled; non-default values give a warning.
const WARN_NONZERO: &[&str] = &["frictionloss", "gravcomp"];

/// Parses MJCF text into a [`ModelSpec`].
pub fn parse(xml: &str) -> Result<ModelSpec> {
    let doc = Document::parse(xml).map_err(|e| Error::Xml { line: e.pos().row, message: e.to_string() })?;
    let root = doc.root_element();
    if root.tag_name().name() != "mujoco" {
        return Err(Error::model(root.tag_name().name(), None, line(&doc, root), "root element must be <mujoco>"));
    }
    let mut p = Parser {
        doc: &doc,
        depth: 0,
        degree: true,
        eulerseq: *b"xyz",
        autolimits: true,
        classes: HashMap::new(),
        warnings: RefCell::new(Vec::new()),
        spec: ModelSpec {
            name: root.attribute("model").unwrap_or("").to_string(),
            option: OptionSpec {
                timestep: 0.002,
                gravity: DVec3::new(0.0, 0.0, -9.81),
                integrator: Integrator::Euler,
                contact: true,
                limit: true,
            },
            bodies: vec![BodySpec {
                name: "world".into(),
                parent: 0,
                pos: DVec3::ZERO,
                quat: DQuat::IDENTITY,
                joints: vec![],
                geoms: vec![],
                sites: vec![],
                inertial: None,
                cameras: vec![],
                lights: vec![],
                line: line(&doc, root),
            }],
            actuators: vec![],
            inertiafromgeom: InertiaFromGeom::Auto,
            settotalmass: None,
            contact_excludes: vec![],
            restitution: None,
            visual: VisualSpec::default(),
            warnings: vec![],
        },
    };
    p.classes.insert("main".into(), Class::default());
    // compiler settings change how everything else reads, so they go first
    for c in root.children().filter(|n| n.has_tag_name("compiler")) {
        p.compiler(c)?;
    }
    for c in root.children().filter(|n| n.has_tag_name("default")) {
        p.default(c, None)?;
    }
    for c in root.children().filter(Node::is_element) {
        match c.tag_name().name() {
            "compiler" | "default" => {}
            "option" => p.option(c)?,
            "worldbody" => p.body_children(c, 0, None)?,
            "actuator" => p.actuators(c)?,
            "custom" => p.custom(c)?,
            "tendon" => p.tendon(c)?,
            "contact" => p.contact(c)?,
            "equality" => {
                if let Some(e) = c.children().find(Node::is_element) {
                    return Err(p.err(e, None, "equality constraints are not supported"));
                }
            }
            "visual" => p.visual(c)?,
            "asset" => p.asset(c)?,
            "statistic" => p.statistic(c)?,
            "size" | "sensor" | "keyframe" | "extension" => {}
            other => return Err(p.err(c, None, format!("unsupported element <{other}>"))),
        }
    }
    p.spec.warnings = p.warnings.into_inner();
    Ok(p.spec)
}

fn line(doc: &Document, n: Node) -> u32 {
    doc.text_pos_at(n.range().start).row
}

/// Reads an element's attributes, falling back on its default class chain.
struct El<'a, 'd> {
    node: Node<'a, 'd>,
    line: u32,
    defaults: Vec<&'a [(String, String)]>,
}

impl<'a, 'd> El<'a, 'd> {
    fn tag(&self) -> &str {
        self.node.tag_name().name()
    }
    fn err(&self, attr: &str, msg: impl Into<String>) -> Error {
        Error::model(self.tag(), Some(attr), self.line, msg)
    }
    fn get(&self, name: &str) -> Option<&'a str> {
        if let Some(v) = self.node.attribute(name) {
            return Some(v);
        }
        self.defaults.iter().find_map(|d| d.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str()))
    }
    fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }
    fn str(&self, name: &str) -> &'a str {
        self.get(name).unwrap_or("")
    }
    fn nums(&self, name: &str) -> Result<Option<Vec<f64>>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        let mut out = Vec::new();
        for tok in v.split_whitespace() {
            let x: f64 = tok.parse().map_err(|_| self.err(name, format!("'{tok}' is not a number")))?;
            if !x.is_finite() {
                return Err(self.err(name, format!("'{tok}' is not finite")));
            }
            if x.abs() > MAX_VALUE {
                return Err(self.err(name, format!("'{tok}' is beyond ±{MAX_VALUE:e}, the largest value sinew accepts")));
            }
            out.push(x);
        }
        Ok(Some(out))
    }
    fn arr<const N: usize>(&self, name: &str) -> Result<Option<[f64; N]>> {
        match self.nums(name)? {
            None => Ok(None),
            Some(v) if v.len() == N => Ok(Some(std::array::from_fn(|i| v[i]))),
            Some(v) => Err(self.err(name, format!("expected {N} numbers, got {}", v.len()))),
        }
    }
    fn f64(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self.arr::<1>(name)?.map_or(default, |a| a[0]))
    }
    fn nonneg(&self, name: &str, default: f64) -> Result<f64> {
        let x = self.f64(name, default)?;
        if x < 0.0 {
            return Err(self.err(name, format!("must be non-negative, got {x}")));
        }
        Ok(x)
    }
    fn vec3(&self, name: &str, default: DVec3) -> Result<DVec3> {
        Ok(self.arr::<3>(name)?.map_or(default, DVec3::from_array))
    }
    fn uint(&self, name: &str, default: u32) -> Result<u32> {
        match self.get(name) {
            None => Ok(default),
            Some(v) => v.trim().parse().map_err(|_| self.err(name, format!("'{v}' is not a non-negative integer"))),
        }
    }
    fn int(&self, name: &str, default: i32) -> Result<i32> {
        match self.get(name) {
            None => Ok(default),
            Some(v) => v.trim().parse().map_err(|_| self.err(name, format!("'{v}' is not an integer"))),
        }
    }
    /// `true`/`false`/`auto` → Some(bool) or None for auto.
    fn tristate(&self, name: &str) -> Result<Option<bool>> {
        match self.get(name) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(v) => Err(self.err(name, format!("expected true, false or auto, got '{v}'"))),
        }
    }
    /// Rejects attributes outside `allowed` and [`IGNORED`]; warns on non-default physics ones.
    fn check(&self, allowed: &[&str], warnings: &RefCell<Vec<String>>) -> Result<()> {
        for a in self.node.attributes() {
            let n = a.name();
            if allowed.contains(&n) || IGNORED.contains(&n) {
                continue;
            }
            if WARN_NONZERO.contains(&n) {
                if a.value().split_whitespace().any(|t| !t.parse::<f64>().is_ok_and(|x| x == 0.0)) {
                    warnings.borrow_mut().push(format!(
                        "<{}> '{}' at line {}: {n}={} is not modelled by sinew and is ignored",
                        self.tag(),
                        self.str("name"),
                        self.line,
                        a.value()
                    ));
                }
                continue;
            }
            return Err(self.err(n, "unsupported attribute"));
        }
        Ok(())
    }
}

impl<'d> Parser<'d> {
    fn err(&self, n: Node, attr: Option<&str>, msg: impl Into<String>) -> Error {
        Error::model(n.tag_name().name(), attr, line(self.doc, n), msg)
    }

    /// An element reader with the defaults of `class` (or the active childclass, or "main").
    fn el<'a>(&'a self, n: Node<'a, 'd>, childclass: Option<&str>) -> Result<El<'a, 'd>> {
        let kind = n.tag_name().name();
        let mut name = n.attribute("class").or(childclass).unwrap_or("main").to_string();
        let mut defaults = Vec::new();
        loop {
            let Some(c) = self.classes.get(&name) else {
                return Err(self.err(n, Some("class"), format!("unknown default class '{name}'")));
            };
            if let Some(a) = c.attrs.get(kind) {
                defaults.push(a.as_slice());
            }
            match &c.parent {
                Some(p) => name = p.clone(),
                None => break,
            }
        }
        Ok(El { node: n, line: line(self.doc, n), defaults })
    }

    fn angle(&self, x: f64) -> f64 {
        if self.degree { x.to_radians() } else { x }
    }

    fn compiler(&mut self, n: Node) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        for a in n.attributes() {
            let v = a.value();
            match a.name() {
                "angle" => match v {
                    "degree" => self.degree = true,
                    "radian" => self.degree = false,
                    _ => return Err(e.err("angle", format!("expected degree or radian, got '{v}'"))),
                },
                "inertiafromgeom" => {
                    self.spec.inertiafromgeom = match v {
                        "true" => InertiaFromGeom::True,
                        "false" => InertiaFromGeom::False,
                        "auto" => InertiaFromGeom::Auto,
                        _ => return Err(e.err("inertiafromgeom", format!("expected true, false or auto, got '{v}'"))),
                    }
                }
                "settotalmass" => {
                    let m = e.f64("settotalmass", -1.0)?;
                    self.spec.settotalmass = (m > 0.0).then_some(m);
                }
                "eulerseq" => {
                    let b = v.as_bytes();
                    if b.len() != 3 || !b.iter().all(|c| b"xyzXYZ".contains(c)) {
                        return Err(e.err("eulerseq", format!("expected three of xyzXYZ, got '{v}'")));
                    }
                    self.eulerseq = [b[0], b[1], b[2]];
                }
                "coordinate" if v == "local" => {}
                "coordinate" => return Err(e.err("coordinate", "only local coordinates are supported")),
                "autolimits" => self.autolimits = v == "true",
                "meshdir" | "texturedir" | "assetdir" | "strippath" | "discardvisual" | "fusestatic"
                | "convexhull" | "usethread" | "alignfree" | "balanceinertia" => {}
                "boundmass" | "boundinertia" => {
                    if e.f64(a.name(), 0.0)? != 0.0 {
                        return Err(e.err(a.name(), "mass/inertia bounding is not supported"));
                    }
                }
                other => return Err(e.err(other, "unsupported attribute")),
            }
        }
        Ok(())
    }

    fn option(&mut self, n: Node) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        for a in n.attributes() {
            match a.name() {
                "timestep" => {
                    let h = e.f64("timestep", 0.002)?;
                    if h > 1.0 {
                        return Err(e.err("timestep", format!("must lie in (0, 1] s, got {h}")));
                    }
                    if h <= 0.0 {
                        return Err(e.err("timestep", format!("must be positive, got {h}")));
                    }
                    self.spec.option.timestep = h;
                }
                "gravity" => self.spec.option.gravity = e.vec3("gravity", DVec3::ZERO)?,
                "integrator" => {
                    self.spec.option.integrator = match a.value() {
                        "Euler" => Integrator::Euler,
                        "RK4" => Integrator::Rk4,
                        v @ ("implicit" | "implicitfast") => {
                            self.warnings.borrow_mut().push(format!(
                                "<option> integrator '{v}' at line {}: not available in sinew, using Euler",
                                e.line
                            ));
                            Integrator::Euler
                        }
                        v => return Err(e.err("integrator", format!("unknown integrator '{v}'"))),
                    }
                }
                "density" | "viscosity" | "wind" | "magnetic" => {
                    if e.nums(a.name())?.unwrap_or_default().iter().any(|&x| x != 0.0) {
                        self.warnings.borrow_mut().push(format!(
                            "<option> {}={} at line {}: fluid and field forces are not modelled by sinew",
                            a.name(),
                            a.value(),
                            e.line
                        ));
                    }
                }
                // MuJoCo solver settings; sinew's solver has its own
                "iterations" | "solver" | "tolerance" | "ls_iterations" | "ls_tolerance" | "noslip_iterations"
                | "noslip_tolerance" | "cone" | "impratio" | "jacobian" | "o_margin" | "o_solref" | "o_solimp"
                | "ccd_iterations" | "ccd_tolerance" | "sdf_iterations" | "sdf_initpoints" | "apirate" => {}
                other => return Err(e.err(other, "unsupported attribute")),
            }
        }
        for f in n.children().filter(|c| c.has_tag_name("flag")) {
            for a in f.attributes() {
                let off = a.value() == "disable";
                match a.name() {
                    "contact" => self.spec.option.contact = !off,
                    "limit" => self.spec.option.limit = !off,
                    "gravity" if off => self.spec.option.gravity = DVec3::ZERO,
                    _ => {}
                }
            }
        }
        Ok(())
    }

    fn default(&mut self, n: Node, parent: Option<String>) -> Result<()> {
        self.enter(n)?;
        let out = self.default_class(n, parent);
        self.depth -= 1;
        out
    }

    /// Counts one more level of nesting: an error beyond [`MAX_NESTING`] (the readers recurse).
    fn enter(&mut self, n: Node) -> Result<()> {
        if self.depth >= MAX_NESTING {
            return Err(self.err(n, None, format!("nested more than {MAX_NESTING} levels deep")));
        }
        self.depth += 1;
        Ok(())
    }

    fn default_class(&mut self, n: Node, parent: Option<String>) -> Result<()> {
        let name = match (n.attribute("class"), &parent) {
            (Some(c), _) => c.to_string(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => return Err(self.err(n, Some("class"), "nested <default> needs a class")),
        };
        if name != "main" && self.classes.contains_key(&name) {
            return Err(self.err(n, Some("class"), format!("duplicate default class '{name}'")));
        }
        let mut class = Class { parent: if name == "main" { None } else { parent.or(Some("main".into())) }, ..Default::default() };
        let mut nested = Vec::new();
        for c in n.children().filter(Node::is_element) {
            let kind = c.tag_name().name();
            if kind == "default" {
                nested.push(c);
                continue;
            }
            let allowed = match kind {
                "joint" => JOINT_ATTRS,
                "geom" => GEOM_ATTRS,
                "site" => SITE_ATTRS,
                "motor" => MOTOR_ATTRS,
                _ => &[][..],
            };
            if !allowed.is_empty() {
                let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
                e.check(allowed, &self.warnings)?;
            }
            let list = c.attributes().map(|a| (a.name().to_string(), a.value().to_string())).collect();
            class.attrs.insert(kind.to_string(), list);
        }
        self.classes.insert(name.clone(), class);
        for c in nested {
            self.default(c, Some(name.clone()))?;
        }
        Ok(())
    }

    fn body_children(&mut self, n: Node, body: usize, childclass: Option<&str>) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "body" => self.body(c, body, childclass)?,
                "geom" => {
                    let g = self.geom(c, childclass, body)?;
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
                other => return Err(self.err(c, None, format!("unsupported element <{other}> in a body"))),
            }
        }
        Ok(())
    }

    fn body(&mut self, n: Node, parent: usize, childclass: Option<&str>) -> Result<()> {
        self.enter(n)?;
        let out = self.body_at(n, parent, childclass);
        self.depth -= 1;
        out
    }

    fn body_at(&mut self, n: Node, parent: usize, childclass: Option<&str>) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        e.check(BODY_ATTRS, &self.warnings)?;
        if n.attribute("mocap") == Some("true") {
            return Err(e.err("mocap", "mocap bodies are not supported"));
        }
        let cc = n.attribute("childclass").or(childclass).map(str::to_string);
        if let Some(c) = &cc
            && !self.classes.contains_key(c)
        {
            return Err(e.err("childclass", format!("unknown default class '{c}'")));
        }
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
            joints: vec![],
            geoms: vec![],
            sites: vec![],
            inertial: None,
            cameras: vec![],
            lights: vec![],
            line: e.line,
        });
        self.body_children(n, id, cc.as_deref())
    }

    fn joint(&mut self, n: Node, childclass: Option<&str>) -> Result<JointSpec> {
        let e = self.el(n, childclass)?;
        if n.has_tag_name("freejoint") {
            e.check(&["name", "group", "align"], &self.warnings)?;
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
                stiffness: 0.0,
                springref: 0.0,
                line: e.line,
            });
        }
        e.check(JOINT_ATTRS, &self.warnings)?;
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
        let limited = match e.tristate("limited")? {
            Some(l) => l,
            None => self.autolimits && e.has("range"),
        };
        if limited && range[0] >= range[1] && kind != JointType::Ball {
            return Err(e.err("range", format!("limited joint needs range[0] < range[1], got {range:?}")));
        }
        if kind == JointType::Free && limited {
            return Err(e.err("limited", "free joints cannot be limited"));
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
            stiffness: e.nonneg("stiffness", 0.0)?,
            springref: conv(e.f64("springref", 0.0)?),
            line: e.line,
        })
    }

    fn geom(&mut self, n: Node, childclass: Option<&str>, body: usize) -> Result<GeomSpec> {
        let e = self.el(n, childclass)?;
        e.check(GEOM_ATTRS, &self.warnings)?;
        let kind = match e.get("type").unwrap_or("sphere") {
            "plane" => GeomType::Plane,
            "sphere" => GeomType::Sphere,
            "capsule" => GeomType::Capsule,
            "cylinder" => GeomType::Cylinder,
            "box" => GeomType::Box,
            "ellipsoid" => GeomType::Ellipsoid,
            v => return Err(e.err("type", format!("unsupported geom type '{v}'"))),
        };
        if kind == GeomType::Plane && body != 0 {
            return Err(e.err("type", "planes must belong to the world body"));
        }
        let given = e.nums("size")?.unwrap_or_default();
        let needed = match kind {
            GeomType::Sphere => 1,
            GeomType::Capsule | GeomType::Cylinder => if e.has("fromto") { 1 } else { 2 },
            GeomType::Box | GeomType::Ellipsoid => if e.has("fromto") { 2 } else { 3 },
            GeomType::Plane => 0,
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
            if matches!(kind, GeomType::Plane | GeomType::Sphere) {
                return Err(e.err("fromto", "fromto needs a capsule, cylinder, box or ellipsoid"));
            }
            let (a, b) = (DVec3::new(ft[0], ft[1], ft[2]), DVec3::new(ft[3], ft[4], ft[5]));
            let d = b - a;
            if d.length() < 1e-12 {
                return Err(e.err("fromto", "zero length"));
            }
            pos = (a + b) * 0.5;
            quat = quat_z_to(d.normalize());
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
        let condim = e.uint("condim", 3)?;
        if ![1, 3, 4, 6].contains(&condim) {
            return Err(e.err("condim", format!("must be 1, 3, 4 or 6, got {condim}")));
        }
        if condim > 3 {
            self.warnings.borrow_mut().push(format!(
                "<geom> '{}' at line {}: condim={condim} asks for torsional or rolling friction, which sinew does not model (sliding friction only, as condim=3)",
                e.str("name"),
                e.line
            ));
        }
        Ok(GeomSpec {
            name: e.str("name").to_string(),
            kind,
            size,
            pos,
            quat,
            density: e.nonneg("density", 1000.0)?,
            mass,
            friction: fr,
            contype: e.uint("contype", 1)?,
            conaffinity: e.uint("conaffinity", 1)?,
            condim,
            priority: e.int("priority", 0)?,
            margin: e.nonneg("margin", 0.0)?,
            rgba: e.rgba("rgba", DEFAULT_GEOM_RGBA)?,
            material: e.get("material").map(str::to_string),
            line: e.line,
        })
    }

    fn site(&mut self, n: Node, childclass: Option<&str>) -> Result<SiteSpec> {
        let e = self.el(n, childclass)?;
        e.check(SITE_ATTRS, &self.warnings)?;
        let (mut pos, mut quat) = (e.vec3("pos", DVec3::ZERO)?, self.orientation(&e)?);
        if let Some(ft) = e.arr::<6>("fromto")? {
            let (a, b) = (DVec3::new(ft[0], ft[1], ft[2]), DVec3::new(ft[3], ft[4], ft[5]));
            pos = (a + b) * 0.5;
            if (b - a).length() > 1e-12 {
                quat = quat_z_to((b - a).normalize());
            }
        }
        Ok(SiteSpec { name: e.str("name").to_string(), pos, quat })
    }

    fn inertial(&mut self, n: Node) -> Result<InertialSpec> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        e.check(INERTIAL_ATTRS, &self.warnings)?;
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
