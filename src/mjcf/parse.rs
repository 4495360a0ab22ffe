//! MJCF text → [`ModelSpec`]: XML walk, default classes, unit and orientation conversion.

use std::cell::RefCell;
use std::collections::HashMap;

use glam::DVec3;
use roxmltree::{Document, Node};

use super::{BodySpec, InertiaFromGeom, Integrator, ModelSpec, OptionSpec, VisualSpec};

mod assets;
mod body;
mod element;
mod sections;
mod orientation;
mod visual;

use body::{GEOM_ATTRS, JOINT_ATTRS, SITE_ATTRS};
use element::{line, El};
use sections::{actuator_attrs, ACTUATOR_ATTRS, ACTUATOR_KINDS, TENDON_ATTRS};

use crate::error::{Error, Result};

/// The key of a class's attributes that every actuator kind shares.
const SHARED_ACTUATOR: &str = "<actuator>";

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

/// Deepest nesting of `<body>` or `<default>` elements accepted (gymnasium's models nest at most 7).
pub const MAX_NESTING: usize = 200;

/// Largest magnitude of any number in a model file: sinew's bound on a state entry.
pub const MAX_VALUE: f64 = crate::math::MAX_STATE;


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
                implicit: false,
                contact: true,
                limit: true,
                density: 0.0,
                viscosity: 0.0,
                wind: DVec3::ZERO,
                nconmax: None,
            },
            bodies: vec![BodySpec::world(line(&doc, root))],
            actuators: vec![],
            tendons: vec![],
            sensors: vec![],
            equalities: vec![],
            keys: vec![],
            connects: vec![],
            inertiafromgeom: InertiaFromGeom::Auto,
            inertiagroups: [0, 5],
            settotalmass: None,
            bounds: [0.0; 2],
            contact_excludes: vec![],
            contact_pairs: vec![],
            restitution: None,
            visual: VisualSpec::default(),
            meshes: vec![],
            hfields: vec![],
            meshdir: None,
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
            "equality" => p.equality(c)?,
            "visual" => p.visual(c)?,
            "asset" => p.asset(c)?,
            "statistic" => p.statistic(c)?,
            "keyframe" => p.keyframe(c)?,
            "sensor" => p.sensor(c)?,
            "size" => p.size(c)?,
            "extension" => {}
            other => return Err(p.err(c, None, format!("unsupported element <{other}>"))),
        }
    }
    p.spec.warnings = p.warnings.into_inner();
    Ok(p.spec)
}

impl<'d> Parser<'d> {
    fn err(&self, n: Node, attr: Option<&str>, msg: impl Into<String>) -> Error {
        Error::model(n.tag_name().name(), attr, line(self.doc, n), msg)
    }

    /// An element reader with the defaults of `class` (or the active childclass, or "main").
    fn el<'a>(&'a self, n: Node<'a, 'd>, childclass: Option<&str>) -> Result<El<'a, 'd>> {
        self.el_as(n, childclass, n.tag_name().name())
    }

    /// [`Parser::el`] with the defaults of element kind `kind` (a `<fixed>` tendon takes the
    /// `<tendon>` defaults).
    fn el_as<'a>(&'a self, n: Node<'a, 'd>, childclass: Option<&str>, kind: &str) -> Result<El<'a, 'd>> {
        let mut name = n.attribute("class").or(childclass).unwrap_or("main").to_string();
        let mut defaults = Vec::new();
        loop {
            let Some(c) = self.classes.get(&name) else {
                return Err(self.err(n, Some("class"), format!("unknown default class '{name}'")));
            };
            if let Some(a) = c.attrs.get(kind) {
                defaults.push(a.as_slice());
            }
            if let Some(a) = c.attrs.get(SHARED_ACTUATOR).filter(|_| ACTUATOR_KINDS.contains(&kind)) {
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
                "inertiagrouprange" => {
                    let [lo, hi] = e.arr::<2>("inertiagrouprange")?.unwrap_or([0.0, 5.0]);
                    self.spec.inertiagroups = [lo as i32, hi as i32];
                }
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
                "meshdir" => self.spec.meshdir = Some(v.to_string()),
                "assetdir" => {
                    if self.spec.meshdir.is_none() {
                        self.spec.meshdir = Some(v.to_string());
                    }
                }
                "texturedir" | "strippath" | "discardvisual" | "fusestatic"
                | "convexhull" | "usethread" | "alignfree" | "balanceinertia" => {}
                "boundmass" => self.spec.bounds[0] = e.nonneg("boundmass", 0.0)?,
                "boundinertia" => self.spec.bounds[1] = e.nonneg("boundinertia", 0.0)?,
                other => return Err(e.err(other, "unsupported attribute")),
            }
        }
        Ok(())
    }

    /// `<size>`: `nconmax` bounds the contacts a step keeps (−1, MuJoCo's default: sized from the
    /// model); the other sizes are MuJoCo's memory arena's, which sinew sizes itself.
    fn size(&mut self, n: Node) -> Result<()> {
        let e = El { node: n, line: line(self.doc, n), defaults: vec![] };
        self.spec.option.nconmax = match e.int("nconmax", -1)? {
            -1 => None,
            k if k > 0 => Some(k as usize),
            k => return Err(e.err("nconmax", format!("must be positive, or -1 for sinew's default, got {k}"))),
        };
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
                            self.spec.option.implicit = true;
                            if v == "implicit" {
                                self.warnings.borrow_mut().push(format!(
                                    "<option> integrator 'implicit' at line {}: read as 'implicitfast' (joint and actuator damping implicit, the Coriolis terms' derivative left out)",
                                    e.line
                                ));
                            }
                            Integrator::Euler
                        }
                        v => return Err(e.err("integrator", format!("unknown integrator '{v}'"))),
                    }
                }
                "density" => self.spec.option.density = e.nonneg("density", 0.0)?,
                "viscosity" => self.spec.option.viscosity = e.nonneg("viscosity", 0.0)?,
                "wind" => self.spec.option.wind = e.vec3("wind", DVec3::ZERO)?,
                // MuJoCo solver settings; sinew's solver has its own
                "iterations" | "solver" | "tolerance" | "ls_iterations" | "ls_tolerance" | "noslip_iterations"
                | "noslip_tolerance" | "cone" | "impratio" | "jacobian" | "o_margin" | "o_solref" | "o_solimp"
                | "ccd_iterations" | "ccd_tolerance" | "sdf_iterations" | "sdf_initpoints" | "apirate" => {}
                // the field magnetometers read: no force
                "magnetic" => {}
                other => return Err(e.err(other, "unsupported attribute")),
            }
        }
        for f in n.children().filter(|c| c.has_tag_name("flag")) {
            for a in f.attributes() {
                let off = a.value() == "disable";
                match a.name() {
                    "contact" => self.spec.option.contact = !off,
                    "limit" => self.spec.option.limit = !off,
                    // every constraint off: contacts and limits (MuJoCo's mjDSBL_CONSTRAINT)
                    "constraint" if off => (self.spec.option.contact, self.spec.option.limit) = (false, false),
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
                "motor" | "position" | "velocity" | "intvelocity" | "damper" | "cylinder" | "muscle" | "general" => actuator_attrs(kind),
                "tendon" => TENDON_ATTRS,
                "equality" => &["active"][..],
                _ => &[][..],
            };
            if !allowed.is_empty() {
                let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
                e.check(allowed)?;
            }
            let list: Vec<(String, String)> = c.attributes().map(|a| (a.name().to_string(), a.value().to_string())).collect();
            if ACTUATOR_KINDS.contains(&kind) {
                // MuJoCo's class holds one actuator default: a range or gear any actuator
                // element sets there, every actuator of the class takes (the later one first)
                let shared = class.attrs.entry(SHARED_ACTUATOR.to_string()).or_default();
                for (k, v) in list.iter().filter(|(k, _)| ACTUATOR_ATTRS.contains(&k.as_str()) && k != "name" && k != "class") {
                    shared.retain(|(s, _)| s != k);
                    shared.push((k.clone(), v.clone()));
                }
            }
            class.attrs.insert(kind.to_string(), list);
        }
        self.classes.insert(name.clone(), class);
        for c in nested {
            self.default(c, Some(name.clone()))?;
        }
        Ok(())
    }

}
