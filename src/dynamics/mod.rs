//! Featherstone's dynamics of a kinematic tree: kinematics, tendons, applied forces, the articulated-body
//! algorithm (the step's), CRBA and RNEA (checks of it), and the energy of a state.

pub mod aba;
pub mod activation;
pub mod crba;
pub mod energy;
pub mod external;
pub mod muscle;
pub mod fluid;
pub mod forces;
pub mod kinematics;
pub mod rnea;
pub mod tendon;

use aba::AbaData;
use kinematics::{KinCache, KinData};
use tendon::TendonData;

use crate::math::Motion;
use crate::model::Model;

/// One evaluation of a world's dynamics: kinematics, the ABA's quantities, the applied forces
/// and the joint accelerations.
#[derive(Clone, Debug, Default)]
pub struct DynamicsData {
    /// Poses, velocities and inertias of the nodes.
    pub kin: KinData,
    /// ABA inward-pass quantities and spatial accelerations.
    pub aba: AbaData,
    /// Tendon lengths and Jacobians.
    pub ten: TendonData,
    /// Total applied generalised force (nv): actuators, passive (gravity compensation too), fluid
    /// and the bodies' external forces.
    pub qfrc_applied: Vec<f64>,
    /// Forces applied to the bodies from outside (nbody × 6: force at the centre of mass, then
    /// torque, world axes; MuJoCo's `xfrc_applied`); empty when none (a batch keeps them per
    /// world).
    pub xfrc_applied: Vec<f64>,
    /// Dry friction known ahead of the solve (nv): −loss · sign(q̇) on each dof sliding on, zero
    /// elsewhere (`constraint::dry_friction`); read only while `friction_known`.
    pub qfrc_friction: Vec<f64>,
    /// Whether the evaluations of this step add `qfrc_friction` to the applied forces.
    pub friction_known: bool,
    /// The generalised force ABA takes when `friction_known` (scratch, nv).
    pub tau: Vec<f64>,
    /// Joint accelerations of the last evaluation (nv).
    pub qacc: Vec<f64>,
    /// Activation rates of the last advance (na).
    pub act_dot: Vec<f64>,
    /// The kinematics of the state the next evaluation starts from, when computed ahead.
    pub ahead: KinCache,
    /// Node velocities of other joint velocities on the same configuration (nnode; empty without
    /// fluid forces, the one reader).
    pub v_other: Vec<Motion>,
}

impl DynamicsData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        DynamicsData { kin: KinData::new(m), ten: TendonData::new(m), aba: AbaData::new(m), qfrc_applied: vec![0.0; m.nv], xfrc_applied: Vec::new(), qfrc_friction: vec![0.0; m.nv], friction_known: false, tau: vec![0.0; m.nv], qacc: vec![0.0; m.nv], act_dot: vec![0.0; m.na], ahead: KinCache::new(m), v_other: vec![Motion::ZERO; if m.opt.density > 0.0 || m.opt.viscosity > 0.0 { m.nnode } else { 0 }] }
    }
}

/// The generalised force ABA takes: the applied forces, plus the known dry friction when
/// `known` (summed into `tau`).
pub fn total_force<'a>(applied: &'a [f64], friction: &[f64], known: bool, tau: &'a mut [f64]) -> &'a [f64] {
    if !known {
        return applied;
    }
    for ((t, a), f) in tau.iter_mut().zip(applied).zip(friction) {
        *t = a + f;
    }
    tau
}

/// Stage 1: the kinematics of (qpos, qvel) into `dy.kin`, taken from `dy.ahead` when it holds
/// them.
pub fn kinematics(m: &Model, dy: &mut DynamicsData, qpos: &[f64], qvel: &[f64]) {
    dy.ahead.take_into(m, qpos, qvel, &mut dy.kin);
}

/// Tendons, applied forces and both ABA passes, on the kinematics already in `dy.kin`; `h_damp` > 0
/// treats joint damping implicitly over that step (Featherstone 2008, Table 7.1 passes 2–3).
pub fn accelerations(m: &Model, dy: &mut DynamicsData, qpos: &[f64], qvel: &[f64], ctrl: &[f64], act: &[f64], h_damp: f64) {
    tendon::evaluate(m, &dy.kin, qpos, &mut dy.ten);
    forces::applied(m, &dy.ten, qpos, qvel, (ctrl, act), &mut dy.qfrc_applied);
    fluid::add_forces(m, &dy.kin, &dy.kin.v, &mut dy.qfrc_applied);
    external::add_forces(m, &dy.kin, &dy.xfrc_applied, &mut dy.qfrc_applied);
    external::add_gravcomp(m, &dy.kin, &mut dy.qfrc_applied);
    let tau = total_force(&dy.qfrc_applied, &dy.qfrc_friction, dy.friction_known, &mut dy.tau);
    aba::backward(m, &dy.kin, tau, h_damp, &mut dy.aba);
    aba::forward(m, &dy.kin, &mut dy.aba, &mut dy.qacc);
}

/// Forward dynamics at (qpos, qvel, ctrl) without constraints: `dy.qacc` gets the true
/// accelerations (no implicit damping), as MuJoCo's `mj_forward` with constraints disabled.
pub fn forward(m: &Model, dy: &mut DynamicsData, qpos: &[f64], qvel: &[f64], ctrl: &[f64], act: &[f64]) {
    dy.friction_known = false;
    kinematics::forward(m, qpos, qvel, &mut dy.kin);
    accelerations(m, dy, qpos, qvel, ctrl, act, 0.0);
}
