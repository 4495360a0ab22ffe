//! Tendons: a fixed one's terms, a spatial one's path checked and resolved, their limits,
//! springs, dampers and dry friction, and their lengths at qpos0 and at the springs' rest.

use crate::dynamics::kinematics::KinData;
use crate::dynamics::tendon::{self, TendonData};
use crate::error::{Error, Result};
use crate::mjcf::{JointType, ModelSpec, PathSpec, TendonPathSpec};
use crate::model::{GeomType, Model, PathPoint, Wrap, WORLD};

/// The tendons: a fixed one's terms, a spatial one's path (checked as MuJoCo does: sites at both
/// ends and either side of each geom and pulley; geoms spheres or cylinders), limits, springs,
/// dampers and dry friction, and the lengths at qpos0 and at the springs' rest.
pub(super) fn tendons(m: &mut Model, spec: &ModelSpec) -> Result<()> {
    m.tendon_adr.push(0);
    m.tendon_path_adr.push(0);
    for t in &spec.tendons {
        match &t.path {
            TendonPathSpec::Fixed(joints) => {
                for (name, coef) in joints {
                    let Some(j) = m.jnt_name.iter().position(|n| n == name) else {
                        return Err(Error::model("fixed", Some("joint"), t.line, format!("unknown joint '{name}'")));
                    };
                    if !matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide) {
                        return Err(Error::model("fixed", Some("joint"), t.line, "fixed tendons sum hinge and slide joints only"));
                    }
                    m.tendon_wrap.push(Wrap { dof: m.jnt_dofadr[j], qpos: m.jnt_qposadr[j], coef: *coef });
                }
                if joints.is_empty() {
                    return Err(Error::model("fixed", None, t.line, "a fixed tendon needs at least one joint"));
                }
            }
            TendonPathSpec::Spatial(path) => spatial_path(m, path, t.line)?,
        }
        m.tendon_adr.push(m.tendon_wrap.len());
        m.tendon_path_adr.push(m.tendon_path.len());
        m.tendon_name.push(t.name.clone());
        m.tendon_stiffness.push(t.stiffness);
        m.tendon_damping.push(t.damping);
        m.tendon_springlength.push(t.springlength.unwrap_or([f64::NAN; 2]));
        m.tendon_limited.push(t.range.is_some());
        m.tendon_range.push(t.range.unwrap_or([0.0; 2]));
        m.tendon_margin.push(t.margin);
        m.tendon_frictionloss.push(t.frictionloss);
        m.ntendon += 1;
        // a limit's or friction's row holds the dofs of two kinematic trees at most
        if (t.range.is_some() || t.frictionloss > 0.0) && tendon_trees(m, m.ntendon - 1).len() > 2 {
            let kind = if matches!(t.path, TendonPathSpec::Fixed(_)) { "fixed" } else { "spatial" };
            return Err(Error::model(kind, None, t.line, "a limited or frictional tendon may span two kinematic trees at most"));
        }
    }
    // lengths at qpos0 and at the springs' rest (MuJoCo's tendon_length0 and default springlength)
    let lengths = |q: &[f64]| {
        let mut kin = KinData::new(m);
        crate::dynamics::kinematics::forward(m, q, &vec![0.0; m.nv], &mut kin);
        let mut ten = TendonData::new(m);
        tendon::compute(m, &kin, q, &mut ten);
        ten.length
    };
    let (length0, rest) = (lengths(&m.qpos0), lengths(&m.qpos_spring));
    m.tendon_length0 = length0;
    for (s, l) in m.tendon_springlength.iter_mut().zip(rest) {
        if s[0].is_nan() {
            *s = [l, l];
        }
    }
    Ok(())
}

/// A spatial tendon's path into `m.tendon_path`, each name resolved and the order checked.
fn spatial_path(m: &mut Model, path: &[(PathSpec, u32)], line: u32) -> Result<()> {
    let find = |names: &[String], kind: &str, name: &str, at: u32| {
        names.iter().position(|n| n == name).ok_or_else(|| Error::model(kind, Some(kind), at, format!("unknown {kind} '{name}'")))
    };
    let is_site = |k: usize| matches!(path.get(k), Some((PathSpec::Site(_), _)));
    if path.len() < 2 || !is_site(0) || !is_site(path.len() - 1) {
        return Err(Error::model("spatial", None, line, "a spatial tendon's path begins and ends with a site"));
    }
    for (k, (item, at)) in path.iter().enumerate() {
        let point = match item {
            PathSpec::Site(name) => PathPoint::Site(find(&m.site_name, "site", name, *at)?),
            PathSpec::Geom { geom, sidesite } => {
                let g = find(&m.geom_name, "geom", geom, *at)?;
                if !matches!(m.geom_type[g], GeomType::Sphere | GeomType::Cylinder) {
                    return Err(Error::model("geom", Some("geom"), *at, "a tendon wraps around spheres and cylinders only"));
                }
                if !is_site(k - 1) || !is_site(k + 1) {
                    return Err(Error::model("geom", None, *at, "a wrapping geom lies between two sites of the path"));
                }
                let side = sidesite.as_ref().map(|s| find(&m.site_name, "site", s, *at)).transpose()?;
                PathPoint::Geom { geom: g, side }
            }
            PathSpec::Pulley(divisor) => {
                if !is_site(k - 1) || !is_site(k + 1) {
                    return Err(Error::model("pulley", None, *at, "a pulley lies between two sites of the path"));
                }
                PathPoint::Pulley(*divisor)
            }
        };
        m.tendon_path.push(point);
    }
    Ok(())
}

/// The kinematic trees ([`Model::node_tree`]) tendon t's length depends on.
fn tendon_trees(m: &Model, t: usize) -> Vec<usize> {
    let mut bodies: Vec<usize> = m.tendon_terms(t).iter().map(|w| m.jnt_body[m.dof_jnt[w.dof]]).collect();
    for p in m.tendon_path(t) {
        match *p {
            PathPoint::Site(s) => bodies.push(m.site_body[s]),
            PathPoint::Geom { geom, .. } => bodies.push(m.geom_body[geom]),
            PathPoint::Pulley(_) => {}
        }
    }
    let mut trees: Vec<usize> = bodies.iter().filter(|&&b| m.body_node[b] != WORLD).map(|&b| m.node_tree[m.body_node[b]]).collect();
    trees.sort_unstable();
    trees.dedup();
    trees
}
