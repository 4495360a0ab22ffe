//! The sections outside the body tree: `<actuator>` motors, `<custom>` numerics, `<tendon>` and
//! `<contact>` exclusions.

use roxmltree::Node;

use super::element::{line, El};
use super::Parser;
use crate::error::Result;
use crate::mjcf::ActuatorSpec;

pub(super) const MOTOR_ATTRS: &[&str] =
    &["name", "class", "joint", "gear", "ctrlrange", "ctrllimited", "forcerange", "forcelimited"];

impl Parser<'_> {
    pub(super) fn actuators(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            if !c.has_tag_name("motor") {
                return Err(self.err(c, None, format!("unsupported actuator <{}>: only <motor> is", c.tag_name().name())));
            }
            let e = self.el(c, None)?;
            for t in ["tendon", "site", "jointinparent", "body"] {
                if c.attribute(t).is_some() {
                    return Err(e.err(t, "only joint transmissions are supported"));
                }
            }
            e.check(MOTOR_ATTRS, &self.warnings)?;
            let joint = e.get("joint").ok_or_else(|| e.err("joint", "required"))?.to_string();
            let gear = e.nums("gear")?.unwrap_or_else(|| vec![1.0]);
            if gear.is_empty() || gear.len() > 6 || gear[1..].iter().any(|&g| g != 0.0) {
                return Err(e.err("gear", "only a scalar gear is supported for joint transmissions"));
            }
            let ctrlrange = e.arr::<2>("ctrlrange")?.unwrap_or([0.0, 0.0]);
            let forcerange = e.arr::<2>("forcerange")?.unwrap_or([0.0, 0.0]);
            let ctrllimited = e.tristate("ctrllimited")?.unwrap_or(self.autolimits && e.has("ctrlrange"));
            let forcelimited = e.tristate("forcelimited")?.unwrap_or(self.autolimits && e.has("forcerange"));
            if ctrllimited && ctrlrange[0] >= ctrlrange[1] {
                return Err(e.err("ctrlrange", format!("limited control needs ctrlrange[0] < ctrlrange[1], got {ctrlrange:?}")));
            }
            if forcelimited && forcerange[0] >= forcerange[1] {
                return Err(e.err("forcerange", format!("needs forcerange[0] < forcerange[1], got {forcerange:?}")));
            }
            self.spec.actuators.push(ActuatorSpec {
                name: e.str("name").to_string(),
                joint,
                gear: gear[0],
                ctrlrange,
                ctrllimited,
                forcerange,
                forcelimited,
                line: e.line,
            });
        }
        Ok(())
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

    /// Fixed tendons without stiffness, damping, friction or limits have no physical effect and are
    /// accepted (gymnasium's humanoid has two); any other tendon is an error.
    pub(super) fn tendon(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            if !c.has_tag_name("fixed") {
                return Err(self.err(c, None, "only passive fixed tendons are supported"));
            }
            for a in c.attributes() {
                let inert = match a.name() {
                    "name" | "class" | "rgba" | "group" | "solreflimit" | "solimplimit" | "width" | "material" => true,
                    "limited" => a.value() == "false",
                    "stiffness" | "damping" | "frictionloss" => a.value().trim().parse::<f64>() == Ok(0.0),
                    _ => false,
                };
                if !inert {
                    return Err(self.err(c, Some(a.name()), "tendon physics (stiffness, damping, limits) is not supported"));
                }
            }
        }
        Ok(())
    }

    pub(super) fn contact(&mut self, n: Node) -> Result<()> {
        for c in n.children().filter(Node::is_element) {
            if !c.has_tag_name("exclude") {
                return Err(self.err(c, None, "only <exclude> is supported in <contact>"));
            }
            let (Some(b1), Some(b2)) = (c.attribute("body1"), c.attribute("body2")) else {
                return Err(self.err(c, Some("body1"), "body1 and body2 are required"));
            };
            self.spec.contact_excludes.push((b1.to_string(), b2.to_string()));
        }
        Ok(())
    }
}
