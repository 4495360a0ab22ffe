//! Quantities MuJoCo's gymnasium environments observe, computed from sinew's own state and
//! constraint forces after a step: body velocities, com-based inertias and velocities (`cinert`,
//! `cvel`), contact forces per body in MuJoCo's com-based frame (`cfrc_ext`) and the generalised
//! constraint force (`qfrc_constraint`).

use glam::DVec3;

use crate::collision::Contact;
use crate::constraint::AppliedForces;
use crate::step::data::{Data, SensorScratch};
use crate::dynamics::kinematics::KinData;
use crate::math::{Force, SpatialInertia};
use crate::model::{Model, WORLD};
use crate::sensordata::generalized_constraint_force;
use crate::tasks::World;

/// Output rows of one world.
pub struct Sensors<'a> {
    /// Body positions (nbody × 3).
    pub xpos: &'a mut [f64],
    /// Body rotation matrices, row-major (nbody × 9).
    pub xmat: &'a mut [f64],
    /// Body centres of mass (nbody × 3), MuJoCo's `xipos`.
    pub xipos: &'a mut [f64],
    /// Body velocities (nbody × 6): world angular velocity, then world velocity of the body origin.
    pub xvel: &'a mut [f64],
    /// Contact wrench on each body (nbody × 6): torque then force, world axes, about the centre of
    /// mass of the subtree of the body's root (MuJoCo's `cfrc_ext`).
    pub cfrc_ext: &'a mut [f64],
    /// Generalised constraint force of the last step (nv), MuJoCo's `qfrc_constraint`.
    pub qfrc_constraint: &'a mut [f64],
    /// Body inertia about the centre of mass of the body's root subtree, world axes (nbody × 10:
    /// xx, yy, zz, xy, xz, yz, mass × offset, mass), MuJoCo's `cinert`.
    pub cinert: &'a mut [f64],
    /// Body velocity at the centre of mass of the body's root subtree (nbody × 6: angular, then
    /// linear), MuJoCo's `cvel`.
    pub cvel: &'a mut [f64],
}

impl Sensors<'_> {
    /// The same rows, borrowed again.
    pub fn reborrow(&mut self) -> Sensors<'_> {
        Sensors {
            xpos: self.xpos,
            xmat: self.xmat,
            xipos: self.xipos,
            xvel: self.xvel,
            cfrc_ext: self.cfrc_ext,
            qfrc_constraint: self.qfrc_constraint,
            cinert: self.cinert,
            cvel: self.cvel,
        }
    }

    /// One world's outputs with its state, as a task reads them.
    pub fn world_view<'b>(&'b self, qpos: &'b [f64], qvel: &'b [f64], ctrl: &'b [f64]) -> World<'b> {
        World {
            qpos,
            qvel,
            ctrl,
            xpos: self.xpos,
            xmat: self.xmat,
            xipos: self.xipos,
            cfrc_ext: self.cfrc_ext,
            qfrc_constraint: self.qfrc_constraint,
            cinert: self.cinert,
            cvel: self.cvel,
        }
    }

    /// World `i`'s rows of outputs that hold every world's rows one after another.
    pub fn world(&mut self, i: usize, nbody: usize, nv: usize) -> Sensors<'_> {
        Sensors {
            xpos: &mut self.xpos[i * 3 * nbody..(i + 1) * 3 * nbody],
            xmat: &mut self.xmat[i * 9 * nbody..(i + 1) * 9 * nbody],
            xipos: &mut self.xipos[i * 3 * nbody..(i + 1) * 3 * nbody],
            xvel: &mut self.xvel[i * 6 * nbody..(i + 1) * 6 * nbody],
            cfrc_ext: &mut self.cfrc_ext[i * 6 * nbody..(i + 1) * 6 * nbody],
            qfrc_constraint: &mut self.qfrc_constraint[i * nv..(i + 1) * nv],
            cinert: &mut self.cinert[i * 10 * nbody..(i + 1) * 10 * nbody],
            cvel: &mut self.cvel[i * 6 * nbody..(i + 1) * 6 * nbody],
        }
    }
}

/// Root body (child of the world) of every body (nbody); the world is its own root.
pub fn body_root(m: &Model) -> Vec<usize> {
    let mut root = vec![0; m.nbody];
    for b in 1..m.nbody {
        let p = m.body_parent[b];
        root[b] = if p == 0 { b } else { root[p] };
    }
    root
}

/// Fills `out` for the state (qpos, qvel) and the constraint forces of the last step in `d`.
pub fn write(m: &Model, root: &[usize], d: &mut Data, qpos: &[f64], qvel: &[f64], mut out: Sensors<'_>) {
    let Data { dynamics, constraints, coll, sensors: SensorScratch { node_force, root_com }, .. } = d;
    // the end state's kinematics, shared with the next step
    let kin = dynamics.ahead.at(m, qpos, qvel);
    poses(m, kin, &mut out);
    // centres of mass of the roots' subtrees (MuJoCo's subtree_com[rootid]), indexed by root
    root_com.fill((DVec3::ZERO, 0.0));
    out.xipos[..3].copy_from_slice(&kin.xpos[0].to_array());
    for b in 1..m.nbody {
        let xipos = kin.xpos[b] + kin.xmat[b] * m.body_ipos[b];
        out.xipos[3 * b..3 * b + 3].copy_from_slice(&xipos.to_array());
        let (mc, mass) = &mut root_com[root[b]];
        *mc += xipos * m.body_mass[b];
        *mass += m.body_mass[b];
    }
    for (r, (mc, mass)) in root_com.iter_mut().enumerate() {
        *mc = if *mass > 0.0 { *mc / *mass } else { kin.xpos[r] };
    }
    let world = Frame { m, kin, root, root_com };
    com_based(&world, &mut out);
    constraint_forces(&world, &constraints.applied, &coll.contacts, node_force, &mut out);
}

/// What every output of a world reads: the model, the kinematics of its state, each body's root
/// and each root subtree's centre of mass and mass.
struct Frame<'a> {
    m: &'a Model,
    kin: &'a KinData,
    root: &'a [usize],
    root_com: &'a [(DVec3, f64)],
}

impl Frame<'_> {
    /// The centre of mass of the subtree of body b's root.
    fn com_of_root(&self, b: usize) -> DVec3 {
        self.root_com[self.root[b]].0
    }
}

/// xpos, xmat and xvel (angular, then linear at the body origin).
fn poses(m: &Model, kin: &KinData, out: &mut Sensors<'_>) {
    for b in 0..m.nbody {
        out.xpos[3 * b..3 * b + 3].copy_from_slice(&kin.xpos[b].to_array());
        let r = kin.xmat[b];
        for i in 0..3 {
            for j in 0..3 {
                out.xmat[9 * b + 3 * i + j] = r.col(j)[i];
            }
        }
        let n = m.body_node[b];
        let (w, v) = if n == WORLD {
            (DVec3::ZERO, DVec3::ZERO)
        } else {
            let vn = kin.v[n];
            (vn.ang, vn.point_velocity(kin.xpos[b] - kin.origin))
        };
        out.xvel[6 * b..6 * b + 3].copy_from_slice(&w.to_array());
        out.xvel[6 * b + 3..6 * b + 6].copy_from_slice(&v.to_array());
    }
}

/// cinert and cvel: about and at the root subtree's centre of mass, world axes.
fn com_based(f: &Frame<'_>, out: &mut Sensors<'_>) {
    let (m, kin) = (f.m, f.kin);
    for b in 0..m.nbody {
        let mass = m.body_mass[b];
        // the body's inertia in world axes, its centre of mass at d from the root subtree's
        let SpatialInertia { com: d, ic: i, .. } =
            SpatialInertia::new(mass, m.body_ipos[b], m.body_inertia[b]).to_parent(kin.xmat[b], kin.xpos[b] - f.com_of_root(b));
        let ci = &mut out.cinert[10 * b..10 * b + 10];
        ci[0] = i.x_axis.x + mass * (d.y * d.y + d.z * d.z);
        ci[1] = i.y_axis.y + mass * (d.x * d.x + d.z * d.z);
        ci[2] = i.z_axis.z + mass * (d.x * d.x + d.y * d.y);
        ci[3] = i.y_axis.x - mass * d.x * d.y;
        ci[4] = i.z_axis.x - mass * d.x * d.z;
        ci[5] = i.z_axis.y - mass * d.y * d.z;
        ci[6..9].copy_from_slice(&(d * mass).to_array());
        ci[9] = mass;
        let w = DVec3::from_slice(&out.xvel[6 * b..6 * b + 3]);
        let v = DVec3::from_slice(&out.xvel[6 * b + 3..6 * b + 6]) + w.cross(f.com_of_root(b) - kin.xpos[b]);
        out.cvel[6 * b..6 * b + 3].copy_from_slice(&w.to_array());
        out.cvel[6 * b + 3..6 * b + 6].copy_from_slice(&v.to_array());
    }
}

/// cfrc_ext (each contact's force on its two bodies, about their root subtree's centre of mass)
/// and qfrc_constraint (Jᵀ f) from the last step's constraint forces.
fn constraint_forces(f: &Frame<'_>, c: &AppliedForces, contacts: &[Contact], node_f: &mut [Force], out: &mut Sensors<'_>) {
    out.cfrc_ext.fill(0.0);
    let cfrc_ext = &mut *out.cfrc_ext;
    generalized_constraint_force(f.m, f.kin, (c, contacts), node_f, out.qfrc_constraint, |b, at, fs, couple| {
        let torque = (at - f.com_of_root(b)).cross(fs) + couple;
        for k in 0..3 {
            cfrc_ext[6 * b + k] += torque[k];
            cfrc_ext[6 * b + 3 + k] += fs[k];
        }
    });
}
