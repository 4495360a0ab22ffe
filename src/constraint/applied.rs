//! The forces the last step's rows applied, kept past the step for what reads them after it
//! (cfrc_ext, qfrc_constraint, touch and the accelerations of the sensors, `Sim.contacts`): the
//! rows themselves are scratch that a batch's worlds borrow from its threads
//! ([`crate::step::data::Kept`]).

use glam::DVec3;

use super::system::{ConstraintData, RowKind};
use crate::model::{ConstraintMode, Model};

/// One contact's force on geom 1 (world coordinates, N; geom 2 takes its negation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForce {
    /// Normal and friction together.
    pub total: DVec3,
    /// Along the normal.
    pub normal: f64,
    /// The sliding friction rows' part.
    pub friction: DVec3,
    /// The couple of the torsional and rolling friction rows (N m).
    pub torque: DVec3,
}

/// One connect row's force, pulling its two points together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConnectForce {
    /// The nodes of the two sides.
    pub node: [usize; 2],
    /// Where it applies on each side, relative to the step's `KinData::origin`.
    pub arm: [DVec3; 2],
    /// The force (a torque for an angular row), world coordinates.
    pub force: DVec3,
    /// Whether the row holds orientations.
    pub angular: bool,
}

/// The last step's constraint forces, in force units whatever the constraint mode.
#[derive(Clone, Debug, Default)]
pub struct AppliedForces {
    /// Per contact of the step (its index in `CollisionData::contacts`).
    pub contact: Vec<ContactForce>,
    /// Per connect row.
    pub connect: Vec<ConnectForce>,
    /// (dof, generalised force) per term of the joint rows, in row order.
    pub joint: Vec<(usize, f64)>,
}

impl AppliedForces {
    /// No force.
    pub fn clear(&mut self) {
        self.contact.clear();
        self.connect.clear();
        self.joint.clear();
    }

    /// The forces `force` (impulses over the step in velocity mode) of the rows `con` over
    /// `ncontact` contacts.
    pub fn record(&mut self, m: &Model, con: &ConstraintData, force: &[f64], ncontact: usize) {
        self.clear();
        if con.is_empty() || force.len() < con.len() {
            return;
        }
        // velocity-level time stepping solves for impulses over the step
        let per_force = if m.opt.constraint_mode == ConstraintMode::Velocity { 1.0 / m.opt.timestep } else { 1.0 };
        self.contact.resize(ncontact, ContactForce::default());
        for j in 0..con.len() {
            let f = force[j] * per_force;
            match con.kind[j] {
                RowKind::Spin { .. } => self.contact[con.source[j]].torque += con.dir[j] * f,
                RowKind::Normal | RowKind::Tangent { .. } => {
                    let c = &mut self.contact[con.source[j]];
                    // as the outputs have always summed them, bit for bit
                    c.total += con.dir[j] * force[j] * per_force;
                    match con.kind[j] {
                        RowKind::Normal => c.normal = f,
                        _ => c.friction += con.dir[j] * f,
                    }
                }
                RowKind::Connect { angular } => {
                    self.connect.push(ConnectForce { node: con.node[j], arm: [con.arm[j], con.arm2[j]], force: con.dir[j] * f, angular });
                }
                _ => self.joint.extend(con.joint_terms(j).iter().map(|&(dof, c)| (dof, c * force[j] * per_force))),
            }
        }
    }
}
