//! The sections outside the body tree: `<actuator>`s, `<custom>` numerics, `<tendon>`s and
//! `<contact>` exclusions.

use roxmltree::Node;

use super::element::{line, El};
use super::Parser;
use crate::error::Result;
use glam::DVec3;

use crate::mjcf::{ActuatorDyn, ActuatorSpec, MuscleSpec, ConnectSpec, EqualitySpec, KeySpec, PairSpec, PathSpec, SensorSpec, TendonPathSpec, TendonSpec, TransmissionSpec};

/// Attributes every actuator takes.
pub(super) const ACTUATOR_ATTRS: &[&str] =
    &["name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited"];

/// Attributes of actuator kind `kind` (`motor`, `position`, `velocity`, `intvelocity`, `damper`,
/// `cylinder`, `general`).
pub(super) fn actuator_attrs(kind: &str) -> &'static [&'static str] {
    match kind {
        "position" => &[
            "name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "kp", "kv", "dampratio",
            "timeconst", "inheritrange",
        ],
        "velocity" => &["name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "kv"],
        "intvelocity" => &[
            "name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "kp", "kv", "dampratio",
            "actrange", "actlimited", "inheritrange",
        ],
        "damper" => &["name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "kv"],
        "cylinder" => &[
            "name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "timeconst", "area",
            "diameter", "bias",
        ],
        "general" => &[
            "name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "gaintype",
            "gainprm", "biastype", "biasprm", "dyntype", "dynprm", "actlimited", "actrange", "actearly", "lengthrange",
        ],
        "muscle" => &[
            "name", "class", "joint", "tendon", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited", "lengthrange",
            "timeconst", "tausmooth", "range", "force", "scale", "lmin", "lmax", "vmax", "fpmax", "fvmax",
        ],
        _ => ACTUATOR_ATTRS,
    }
}

/// The actuator kinds read.
pub(super) const ACTUATOR_KINDS: &[&str] = &["motor", "position", "velocity", "intvelocity", "damper", "cylinder", "muscle", "general"];

/// An actuator's gain, bias and activation (its kind's shortcut, or `<general>`'s own).
struct Drive {
    gain: [f64; 3],
    bias: [f64; 3],
    dynamics: ActuatorDyn,
    actrange: Option<[f64; 2]>,
    muscle: Option<MuscleSpec>,
}

/// A servo's velocity bias: −kv, or MuJoCo's `dampratio` kept positive for the compiler to turn
/// into −kv (from the reflected inertia at qpos0).
fn damping(e: &El) -> Result<f64> {
    match (e.has("kv"), e.has("dampratio")) {
        (true, true) => Err(e.err("dampratio", "kv and dampratio cannot both be given")),
        (_, true) => e.nonneg("dampratio", 0.0),
        _ => Ok(-e.nonneg("kv", 0.0)?),
    }
}

/// Attributes of a tendon.
pub(super) const TENDON_ATTRS: &[&str] = &[
    "name", "class", "stiffness", "damping", "springlength", "limited", "range", "margin", "frictionloss", "width", "armature",
    "solreffriction", "solimpfriction",
];

impl Parser<'_> {
    pub(super) fn actuators(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            let kind = c.tag_name().name();
            if !ACTUATOR_KINDS.contains(&kind) {
                return Err(self.err(c, None, format!("unsupported actuator <{kind}>: {} are", ACTUATOR_KINDS.iter().map(|k| format!("<{k}>")).collect::<Vec<_>>().join(", "))));
            }
            let e = self.el(c, None)?;
            for t in ["site", "jointinparent", "body", "refsite", "cranksite", "slidersite"] {
                if c.attribute(t).is_some() {
                    return Err(e.err(t, "only joint and tendon transmissions are supported"));
                }
            }
            e.check(actuator_attrs(kind))?;
            let target = match (e.get("joint"), e.get("tendon")) {
                (Some(j), None) => TransmissionSpec::Joint(j.to_string()),
                (None, Some(t)) => TransmissionSpec::Tendon(t.to_string()),
                (None, None) => return Err(e.err("joint", "a joint or tendon transmission is required")),
                (Some(_), Some(_)) => return Err(e.err("tendon", "an actuator has one transmission: joint or tendon")),
            };
            let gear = e.nums("gear")?.unwrap_or_else(|| vec![1.0]);
            if gear.is_empty() || gear.len() > 6 || gear[1..].iter().any(|&g| g != 0.0) {
                return Err(e.err("gear", "only a scalar gear is supported for joint and tendon transmissions"));
            }
            let Drive { gain, bias, dynamics, actrange, muscle } = self.drive(&e, kind)?;
            let ctrlrange = e.arr::<2>("ctrlrange")?.unwrap_or([0.0, 0.0]);
            let forcerange = e.arr::<2>("forcerange")?.unwrap_or([0.0, 0.0]);
            // MuJoCo's inheritrange: the range (ctrl of a position servo, act of an intvelocity
            // one) the target's range scaled about its middle, set when the model compiles
            let inheritrange = e.nonneg("inheritrange", 0.0)?;
            if inheritrange > 0.0 && e.has(if kind == "position" { "ctrlrange" } else { "actrange" }) {
                return Err(e.err("inheritrange", "inheritrange and the range it sets cannot both be given"));
            }
            let inherits_ctrl = inheritrange > 0.0 && kind == "position";
            let ctrllimited = e.tristate("ctrllimited")?.unwrap_or(self.autolimits && (e.has("ctrlrange") || inherits_ctrl));
            let forcelimited = e.tristate("forcelimited")?.unwrap_or(self.autolimits && e.has("forcerange"));
            if ctrllimited && !inherits_ctrl && ctrlrange[0] >= ctrlrange[1] {
                return Err(e.err("ctrlrange", format!("limited control needs ctrlrange[0] < ctrlrange[1], got {ctrlrange:?}")));
            }
            if forcelimited && forcerange[0] >= forcerange[1] {
                return Err(e.err("forcerange", format!("needs forcerange[0] < forcerange[1], got {forcerange:?}")));
            }
            self.spec.actuators.push(ActuatorSpec {
                kind: kind.to_string(),
                name: e.str("name").to_string(),
                target,
                gear: gear[0],
                ctrlrange,
                ctrllimited,
                forcerange,
                forcelimited,
                gain,
                bias,
                dynamics,
                actrange,
                muscle,
                inheritrange,
                line: e.line,
            });
        }
        Ok(())
    }

    /// An actuator's fixed gain and affine bias, as MuJoCo sets them for each kind: a motor's
    /// force is ctrl; a position servo's kp (ctrl − length) − kv velocity; a velocity servo's
    /// kv (ctrl − velocity); a general actuator's from `gainprm` and `biasprm`.
    fn drive(&self, e: &El, kind: &str) -> Result<Drive> {
        let drive = |gain: [f64; 3], bias: [f64; 3], dynamics: ActuatorDyn| Drive { gain, bias, dynamics, actrange: None, muscle: None };
        Ok(match kind {
            "position" => {
                let (kp, tc) = (e.nonneg("kp", 1.0)?, e.nonneg("timeconst", 0.0)?);
                drive([kp, 0.0, 0.0], [0.0, -kp, damping(e)?], if tc > 0.0 { ActuatorDyn::FilterExact(tc) } else { ActuatorDyn::None })
            }
            "velocity" => {
                let kv = e.nonneg("kv", 1.0)?;
                drive([kv, 0.0, 0.0], [0.0, 0.0, -kv], ActuatorDyn::None)
            }
            "intvelocity" => {
                let kp = e.nonneg("kp", 1.0)?;
                Drive { actrange: self.actrange(e)?, ..drive([kp, 0.0, 0.0], [0.0, -kp, damping(e)?], ActuatorDyn::Integrator) }
            }
            "damper" => {
                let kv = e.nonneg("kv", 1.0)?;
                drive([0.0, 0.0, -kv], [0.0; 3], ActuatorDyn::None)
            }
            "cylinder" => {
                let tc = e.nonneg("timeconst", 1.0)?;
                let area = match e.arr::<1>("diameter")? {
                    Some([d]) => std::f64::consts::PI / 4.0 * d * d,
                    None => e.nonneg("area", 1.0)?,
                };
                let bias = e.nums("bias")?.unwrap_or_default();
                drive([area, 0.0, 0.0], [0, 1, 2].map(|k| bias.get(k).copied().unwrap_or(0.0)), ActuatorDyn::Filter(tc))
            }
            "muscle" => muscle(e)?,
            "general" => self.general(e)?,
            _ => drive([1.0, 0.0, 0.0], [0.0; 3], ActuatorDyn::None),
        })
    }

    /// `<general>`'s gain (fixed or affine), bias (none or affine) and dynamics (none,
    /// integrator, filter, filterexact).
    fn general(&self, e: &El) -> Result<Drive> {
        if e.get("gaintype") == Some("muscle") {
            return general_muscle(e);
        }
        // fixed, affine and none read at most the first three parameters (MuJoCo's
        // mjGAIN_AFFINE, mjBIAS_AFFINE): the rest, which a class may share with muscles, are unused
        let prm = |name: &str, default: f64| -> Result<[f64; 3]> {
            let v = e.nums(name)?.unwrap_or_else(|| vec![default]);
            Ok([0, 1, 2].map(|k| v.get(k).copied().unwrap_or(0.0)))
        };
        let gain = match e.get("gaintype").unwrap_or("fixed") {
            "fixed" => [prm("gainprm", 1.0)?[0], 0.0, 0.0],
            "affine" => prm("gainprm", 1.0)?,
            other => return Err(e.err("gaintype", format!("gain type '{other}' is not supported (fixed and affine are)"))),
        };
        let bias = match e.get("biastype").unwrap_or("none") {
            "none" => [0.0; 3],
            "affine" => prm("biasprm", 0.0)?,
            other => return Err(e.err("biastype", format!("bias type '{other}' is not supported (none and affine are)"))),
        };
        let tau = || -> Result<f64> {
            let t = prm("dynprm", 1.0)?[0];
            if t <= 0.0 {
                return Err(e.err("dynprm", format!("a filter's time constant must be positive, got {t}")));
            }
            Ok(t)
        };
        let dynamics = match e.get("dyntype").unwrap_or("none") {
            "none" => ActuatorDyn::None,
            "integrator" => ActuatorDyn::Integrator,
            "filter" => ActuatorDyn::Filter(tau()?),
            "filterexact" => ActuatorDyn::FilterExact(tau()?),
            other => return Err(e.err("dyntype", format!("activation dynamics '{other}' are not supported (none, integrator, filter and filterexact are)"))),
        };
        if e.get("actearly") == Some("true") {
            return Err(e.err("actearly", "actearly is not supported"));
        }
        Ok(Drive { gain, bias, dynamics, actrange: self.actrange(e)?, muscle: None })
    }

    /// An actuator's activation range when limited (`actlimited`, or `actrange` under autolimits).
    fn actrange(&self, e: &El) -> Result<Option<[f64; 2]>> {
        let range = e.arr::<2>("actrange")?;
        if !e.tristate("actlimited")?.unwrap_or(self.autolimits && range.is_some()) {
            return Ok(None);
        }
        match range {
            Some([lo, hi]) if lo < hi => Ok(Some([lo, hi])),
            _ => Err(e.err("actrange", "a limited activation needs actrange[0] < actrange[1]")),
        }
    }

    pub(super) fn custom(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(|c| c.has_tag_name("numeric")) {
            if c.attribute("name") == Some("sinew/restitution") {
                let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
                let r = e.f64("data", 0.0)?;
                if !(0.0..=1.0).contains(&r) {
                    return Err(e.err("data", format!("restitution must lie in [0, 1], got {r}")));
                }
                self.spec.restitution = Some(r);
            }
        }
        Ok(())
    }

    /// Fixed and spatial tendons.
    pub(super) fn tendon(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            let kind = c.tag_name().name();
            if !matches!(kind, "fixed" | "spatial") {
                return Err(self.err(c, None, format!("unsupported tendon <{kind}>: <fixed> and <spatial> are")));
            }
            let e = self.el_as(c, None, "tendon")?;
            e.check(TENDON_ATTRS)?;
            if e.f64("armature", 0.0)? != 0.0 {
                return Err(e.err("armature", "tendon armature is not supported"));
            }
            let limited = e.tristate("limited")?.unwrap_or(self.autolimits && e.has("range"));
            let range = match (limited, e.arr::<2>("range")?) {
                (false, _) => None,
                (true, Some([lo, hi])) if lo <= hi => Some([lo, hi]),
                (true, _) => return Err(e.err("range", "a limited tendon needs a range low ≤ high")),
            };
            let path = if kind == "fixed" { self.fixed_path(c)? } else { self.spatial_path(c)? };
            let springlength = match e.nums("springlength")?.as_deref() {
                None => None,
                Some([l]) if *l < 0.0 => None,
                Some([l]) => Some([*l, *l]),
                Some([lo, hi]) if lo <= hi => Some([*lo, *hi]),
                Some(_) => return Err(e.err("springlength", "one length, or a deadband low ≤ high")),
            };
            self.spec.tendons.push(TendonSpec {
                name: e.str("name").to_string(),
                path,
                stiffness: e.nonneg("stiffness", 0.0)?,
                damping: e.nonneg("damping", 0.0)?,
                springlength,
                range,
                margin: e.nonneg("margin", 0.0)?,
                frictionloss: e.nonneg("frictionloss", 0.0)?,
                line: e.line,
            });
        }
        Ok(())
    }

    /// A `<fixed>` tendon's `<joint>` terms.
    fn fixed_path(&self, c: Node) -> Result<TendonPathSpec> {
        let mut joints = vec![];
        for j in c.children().filter(Node::is_element) {
            let je = El { node: j, line: line(self.doc, j), defaults: vec![] };
            if !j.has_tag_name("joint") {
                return Err(self.err(j, None, format!("unsupported element <{}> in a fixed tendon", j.tag_name().name())));
            }
            je.check(&["joint", "coef"])?;
            let name = je.get("joint").ok_or_else(|| je.err("joint", "required"))?;
            joints.push((name.to_string(), je.f64("coef", 1.0)?));
        }
        Ok(TendonPathSpec::Fixed(joints))
    }

    /// A `<spatial>` tendon's path: `<site>`, `<geom>` and `<pulley>` elements in order.
    fn spatial_path(&self, c: Node) -> Result<TendonPathSpec> {
        let mut path = vec![];
        for p in c.children().filter(Node::is_element) {
            let pe = El { node: p, line: line(self.doc, p), defaults: vec![] };
            let required = |attr: &str| pe.get(attr).map(str::to_string).ok_or_else(|| pe.err(attr, "required"));
            let item = match p.tag_name().name() {
                "site" => {
                    pe.check(&["site"])?;
                    PathSpec::Site(required("site")?)
                }
                "geom" => {
                    pe.check(&["geom", "sidesite"])?;
                    PathSpec::Geom { geom: required("geom")?, sidesite: pe.get("sidesite").map(str::to_string) }
                }
                "pulley" => {
                    pe.check(&["divisor"])?;
                    let divisor = pe.f64("divisor", 0.0)?;
                    if divisor <= 0.0 {
                        return Err(pe.err("divisor", format!("must be positive, got {divisor}")));
                    }
                    PathSpec::Pulley(divisor)
                }
                other => return Err(self.err(p, None, format!("unsupported element <{other}> in a spatial tendon"))),
            };
            path.push((item, pe.line));
        }
        Ok(TendonPathSpec::Spatial(path))
    }

    /// `<sensor>`s: each kept with its object attributes for the compiler, which resolves them
    /// (and warns about kinds sinew does not compute).
    pub(super) fn sensor(&mut self, n: Node) -> Result<()> {
        const OBJECTS: &[&str] = &["joint", "tendon", "actuator", "site", "body", "objtype", "objname", "reftype", "refname"];
        // a contact sensor's
        const CONTACT: &[&str] = &["geom1", "geom2", "body1", "body2", "subtree1", "subtree2", "num", "data", "reduce"];
        for c in n.children().filter(Node::is_element) {
            let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
            // noise, cutoff and user do not change what sinew computes
            e.check(&[OBJECTS, CONTACT, &["name", "noise", "cutoff", "nsample", "interp", "delay", "interval"]].concat())?;
            let attrs = OBJECTS.iter().chain(CONTACT).filter_map(|&a| e.get(a).map(|v| (a.to_string(), v.to_string()))).collect();
            self.spec.sensors.push(SensorSpec { kind: c.tag_name().name().to_string(), name: e.str("name").to_string(), attrs, line: e.line });
        }
        Ok(())
    }

    /// `<joint>`, `<tendon>`, `<connect>` and `<weld>` equalities (`flex` is an error).
    pub(super) fn equality(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            let kind = c.tag_name().name();
            let tendon = match kind {
                "joint" => false,
                "tendon" => true,
                "connect" | "weld" => {
                    self.connect(c)?;
                    continue;
                }
                _ => return Err(self.err(c, None, format!("<{kind}> equality constraints are not supported (connect, weld, joint and tendon are)"))),
            };
            let e = self.el_as(c, None, "equality")?;
            let (a1, a2) = if tendon { ("tendon1", "tendon2") } else { ("joint1", "joint2") };
            e.check(&["name", "class", a1, a2, "polycoef", "active"])?;
            let obj1 = e.get(a1).ok_or_else(|| e.err(a1, "required"))?.to_string();
            let coef = e.nums("polycoef")?.unwrap_or_else(|| vec![0.0, 1.0]);
            if coef.len() > 5 {
                return Err(e.err("polycoef", "at most five coefficients (degree 4)"));
            }
            let mut polycoef = [0.0; 5];
            polycoef[..coef.len()].copy_from_slice(&coef);
            self.spec.equalities.push(EqualitySpec {
                name: e.str("name").to_string(),
                tendon,
                obj1,
                obj2: e.get(a2).map(str::to_string),
                polycoef,
                active: e.tristate("active")?.unwrap_or(true),
                order: self.spec.equalities.len() + self.spec.connects.len(),
                line: e.line,
            });
        }
        Ok(())
    }

    /// A `<connect>` or `<weld>` between bodies (site connects and welds, and a weld's own
    /// `relpose`, are refused; `torquescale`, a soft-constraint setting, is ignored).
    fn connect(&mut self, c: Node) -> Result<()> {
        let e = self.el_as(c, None, "equality")?;
        let weld = c.has_tag_name("weld");
        let allowed: &[&str] = if weld {
            &["name", "class", "body1", "body2", "anchor", "active", "relpose", "torquescale"]
        } else {
            &["name", "class", "body1", "body2", "anchor", "active"]
        };
        e.check(allowed)?;
        if weld && e.nums("relpose")?.is_some_and(|r| r != [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]) {
            return Err(e.err("relpose", "a weld holds the relative pose of qpos0; a given relpose is not supported"));
        }
        self.spec.connects.push(ConnectSpec {
            name: e.str("name").to_string(),
            body1: e.get("body1").ok_or_else(|| e.err("body1", "required (site connects are not supported)"))?.to_string(),
            body2: e.get("body2").map(str::to_string),
            anchor: match e.arr::<3>("anchor")? {
                Some(a) => DVec3::from_array(a),
                None if weld => DVec3::ZERO,
                None => return Err(e.err("anchor", "required")),
            },
            weld,
            active: e.tristate("active")?.unwrap_or(true),
            order: self.spec.equalities.len() + self.spec.connects.len(),
            line: e.line,
        });
        Ok(())
    }

    /// `<key>`s: named states, with the mocap bodies' poses (`mpos`, `mquat`).
    pub(super) fn keyframe(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            if !c.has_tag_name("key") {
                return Err(self.err(c, None, format!("unsupported element <{}> in <keyframe>", c.tag_name().name())));
            }
            let e = El { node: c, line: line(self.doc, c), defaults: vec![] };
            e.check(&["name", "time", "qpos", "qvel", "ctrl", "act", "mpos", "mquat"])?;
            self.spec.keys.push(KeySpec {
                name: e.str("name").to_string(),
                time: e.f64("time", 0.0)?,
                qpos: e.nums("qpos")?,
                qvel: e.nums("qvel")?,
                ctrl: e.nums("ctrl")?,
                act: e.nums("act")?,
                mpos: e.nums("mpos")?,
                mquat: e.nums("mquat")?,
                line: e.line,
            });
        }
        Ok(())
    }

    /// `<contact><pair>` (MuJoCo's defaults: condim 3, friction 1, margin 0; `solref`, `solimp`,
    /// `gap` and the torsional and rolling coefficients are ignored as for geoms).
    fn pair(&mut self, c: Node) -> Result<()> {
        let e = self.el(c, None)?;
        e.check(&["name", "class", "geom1", "geom2", "condim", "friction", "margin", "solreffriction"])?;
        let (Some(g1), Some(g2)) = (e.get("geom1"), e.get("geom2")) else {
            return Err(e.err("geom1", "geom1 and geom2 are required"));
        };
        let friction = e.nums("friction")?.unwrap_or_else(|| vec![1.0]);
        if friction.is_empty() || friction.len() > 5 || friction.iter().any(|&f| !(f >= 0.0 && f.is_finite())) {
            return Err(e.err("friction", "expected 1 to 5 non-negative numbers"));
        }
        let condim = self.condim(&e)?;
        let margin = e.nonneg("margin", 0.0)?;
        let mut all = [1.0, 1.0, 0.005, 0.0001, 0.0001];
        all[..friction.len()].copy_from_slice(&friction);
        self.spec.contact_pairs.push(PairSpec { geoms: [g1.to_string(), g2.to_string()], friction: all, condim, margin, line: e.line });
        Ok(())
    }

    pub(super) fn contact(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            if c.has_tag_name("pair") {
                self.pair(c)?;
                continue;
            }
            if !c.has_tag_name("exclude") {
                return Err(self.err(c, None, "only <exclude> and <pair> are read in <contact>"));
            }
            let (Some(b1), Some(b2)) = (c.attribute("body1"), c.attribute("body2")) else {
                return Err(self.err(c, Some("body1"), "body1 and body2 are required"));
            };
            self.spec.contact_excludes.push((b1.to_string(), b2.to_string()));
        }
        Ok(())
    }
}

/// `<muscle>`: MuJoCo's defaults (timeconst 0.01 0.04, tausmooth 0, range 0.75 1.05, force −1,
/// scale 200, lmin 0.5, lmax 1.6, vmax 1.5, fpmax 1.3, fvmax 1.2), each checked.
fn muscle(e: &El) -> Result<Drive> {
    let timeconst = e.arr::<2>("timeconst")?.unwrap_or([0.01, 0.04]);
    let range = e.arr::<2>("range")?.unwrap_or([0.75, 1.05]);
    let (lmin, lmax) = (e.f64("lmin", 0.5)?, e.f64("lmax", 1.6)?);
    let (vmax, fpmax, fvmax) = (e.f64("vmax", 1.5)?, e.nonneg("fpmax", 1.3)?, e.f64("fvmax", 1.2)?);
    let prm = [range[0], range[1], e.f64("force", -1.0)?, e.nonneg("scale", 200.0)?, lmin, lmax, vmax, fpmax, fvmax];
    muscle_drive(e, [timeconst[0], timeconst[1], e.nonneg("tausmooth", 0.0)?], prm)
}

/// `<general gaintype="muscle">`: MuJoCo's muscle written out, its nine parameters in `gainprm`
/// (and the same in `biasprm`), its time constants and smoothing in `dynprm`.
fn general_muscle(e: &El) -> Result<Drive> {
    if e.get("biastype") != Some("muscle") || e.get("dyntype") != Some("muscle") {
        return Err(e.err("gaintype", "a muscle gain needs biastype=\"muscle\" and dyntype=\"muscle\""));
    }
    // the given parameters, the muscle's defaults after them
    let nine = |name: &str, default: &[f64]| -> Result<Vec<f64>> {
        let given = e.nums(name)?.unwrap_or_default();
        Ok((0..default.len()).map(|k| given.get(k).copied().unwrap_or(default[k])).collect())
    };
    let gain = nine("gainprm", &[0.75, 1.05, -1.0, 200.0, 0.5, 1.6, 1.5, 1.3, 1.2])?;
    if e.has("biasprm") && nine("biasprm", &gain)?[..9] != gain[..9] {
        return Err(e.err("biasprm", "a muscle's biasprm must equal its gainprm (one muscle, two curves)"));
    }
    let dyn_prm = nine("dynprm", &[0.01, 0.04, 0.0])?;
    let prm: [f64; 9] = std::array::from_fn(|k| gain[k]);
    muscle_drive(e, [dyn_prm[0], dyn_prm[1], dyn_prm[2]], prm)
}

/// A muscle's drive from its time constants and smoothing (`tau`) and its nine parameters
/// (range, force, scale, lmin, lmax, vmax, fpmax, fvmax), checked as MuJoCo checks them.
fn muscle_drive(e: &El, tau: [f64; 3], prm: [f64; 9]) -> Result<Drive> {
    if tau[..2].iter().any(|&t| t.is_nan() || t <= 0.0) {
        return Err(e.err("timeconst", format!("time constants must be positive, got {:?}", &tau[..2])));
    }
    if tau[2].is_nan() || tau[2] < 0.0 {
        return Err(e.err("tausmooth", format!("must be non-negative, got {}", tau[2])));
    }
    let [r0, r1, _, _, lmin, lmax, vmax, _, fvmax] = prm;
    if r0.is_nan() || r0 >= r1 {
        return Err(e.err("range", format!("needs range[0] < range[1], got {:?}", [r0, r1])));
    }
    if lmin.is_nan() || lmax.is_nan() || lmin >= 1.0 || lmax <= 1.0 {
        return Err(e.err("lmin", format!("needs lmin < 1 < lmax, got {lmin} and {lmax}")));
    }
    if vmax.is_nan() || fvmax.is_nan() || vmax <= 0.0 || fvmax < 1.0 {
        return Err(e.err("vmax", format!("needs vmax > 0 and fvmax ≥ 1, got {vmax} and {fvmax}")));
    }
    let lengthrange = e.arr::<2>("lengthrange")?.filter(|r| r != &[0.0, 0.0]);
    if lengthrange.is_some_and(|r| r[0].is_nan() || r[0] >= r[1]) {
        return Err(e.err("lengthrange", format!("needs lengthrange[0] < lengthrange[1], got {lengthrange:?}")));
    }
    Ok(Drive {
        gain: [0.0; 3],
        bias: [0.0; 3],
        dynamics: ActuatorDyn::Muscle(tau),
        actrange: None,
        muscle: Some(MuscleSpec { prm, lengthrange }),
    })
}
