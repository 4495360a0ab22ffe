//! Reading one element: its attributes, falling back on its default class chain, as numbers,
//! vectors and flags, each error naming the element, attribute and line.


use glam::DVec3;
use roxmltree::{Document, Node};

use crate::error::{Error, Result};
use super::MAX_VALUE;
use crate::math::MAX_DAMPING;

/// Visual and soft-constraint attributes: accepted, no effect on sinew's exact constraints.
const IGNORED: &[&str] = &[
    "rgba", "material", "group", "user", "solref", "solimp", "solmix", "solreflimit", "solimplimit",
    "gap",
];

/// Attributes that change MuJoCo's physics but are not modelled; non-default values give a warning.
pub(super) fn line(doc: &Document, n: Node) -> u32 {
    doc.text_pos_at(n.range().start).row
}

/// Reads an element's attributes, falling back on its default class chain.
pub(super) struct El<'a, 'd> {
    pub(super) node: Node<'a, 'd>,
    pub(super) line: u32,
    pub(super) defaults: Vec<&'a [(String, String)]>,
}

impl<'a, 'd> El<'a, 'd> {
    pub(super) fn tag(&self) -> &str {
        self.node.tag_name().name()
    }
    pub(super) fn err(&self, attr: &str, msg: impl Into<String>) -> Error {
        Error::model(self.tag(), Some(attr), self.line, msg)
    }
    pub(super) fn get(&self, name: &str) -> Option<&'a str> {
        if let Some(v) = self.node.attribute(name) {
            return Some(v);
        }
        self.defaults.iter().find_map(|d| d.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str()))
    }
    pub(super) fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }
    pub(super) fn str(&self, name: &str) -> &'a str {
        self.get(name).unwrap_or("")
    }
    pub(super) fn nums(&self, name: &str) -> Result<Option<Vec<f64>>> {
        let Some(v) = self.get(name) else { return Ok(None) };
        let mut out = Vec::new();
        let max = if name == "damping" && self.node.tag_name().name() == "joint" { MAX_DAMPING } else { MAX_VALUE };
        for tok in v.split_whitespace() {
            let x: f64 = tok.parse().map_err(|_| self.err(name, format!("'{tok}' is not a number")))?;
            if !x.is_finite() {
                return Err(self.err(name, format!("'{tok}' is not finite")));
            }
            if x.abs() > max {
                return Err(self.err(name, format!("'{tok}' is beyond ±{max:e}, the largest value sinew accepts")));
            }
            out.push(x);
        }
        Ok(Some(out))
    }
    pub(super) fn arr<const N: usize>(&self, name: &str) -> Result<Option<[f64; N]>> {
        match self.nums(name)? {
            None => Ok(None),
            Some(v) if v.len() == N => Ok(Some(std::array::from_fn(|i| v[i]))),
            Some(v) => Err(self.err(name, format!("expected {N} numbers, got {}", v.len()))),
        }
    }
    pub(super) fn f64(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self.arr::<1>(name)?.map_or(default, |a| a[0]))
    }
    pub(super) fn nonneg(&self, name: &str, default: f64) -> Result<f64> {
        let x = self.f64(name, default)?;
        if x < 0.0 {
            return Err(self.err(name, format!("must be non-negative, got {x}")));
        }
        Ok(x)
    }
    pub(super) fn vec3(&self, name: &str, default: DVec3) -> Result<DVec3> {
        Ok(self.arr::<3>(name)?.map_or(default, DVec3::from_array))
    }
    pub(super) fn uint(&self, name: &str, default: u32) -> Result<u32> {
        match self.get(name) {
            None => Ok(default),
            Some(v) => v.trim().parse().map_err(|_| self.err(name, format!("'{v}' is not a non-negative integer"))),
        }
    }
    pub(super) fn int(&self, name: &str, default: i32) -> Result<i32> {
        match self.get(name) {
            None => Ok(default),
            Some(v) => v.trim().parse().map_err(|_| self.err(name, format!("'{v}' is not an integer"))),
        }
    }
    /// `true`/`false`/`auto` → Some(bool) or None for auto.
    pub(super) fn tristate(&self, name: &str) -> Result<Option<bool>> {
        match self.get(name) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(v) => Err(self.err(name, format!("expected true, false or auto, got '{v}'"))),
        }
    }
    /// Rejects attributes outside `allowed` and [`IGNORED`].
    pub(super) fn check(&self, allowed: &[&str]) -> Result<()> {
        for a in self.node.attributes() {
            let n = a.name();
            if allowed.contains(&n) || IGNORED.contains(&n) {
                continue;
            }
            return Err(self.err(n, "unsupported attribute"));
        }
        Ok(())
    }
}
