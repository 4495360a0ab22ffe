//! Stage 8's close — the energy bound of a step with contacts: a landing never ends with more energy
//! than it began with plus the work of the applied forces (and 0.1% of its kinetic energy).
//!
//! Why: the constrained step is semi-implicit Euler with the velocity-product (gyroscopic and
//! Coriolis) forces taken at the step's start. Its energy error grows with the cube of the
//! speeds, and a landing can turn a light link fast (an 8-link chain dropped at h = 0.01 gained
//! 3.1 J of its 27 J in one step: `benches/landing_energy.py` before this bound).
//! Implicit velocity products would need the coupled ∂c/∂q̇, which the ABA (and with it K by test
//! forces) cannot carry. Instead the step's energy is budgeted and the velocities after the
//! step are scaled onto the budget when they exceed it (energy projection: Dinev, Liu & Kavan
//! 2018, *Stabilizing Integrators for Real-Time Physics*, ACM TOG 37(1)). Scaling q̇ by α ∈ [0, 1]
//! keeps every velocity-level constraint the solve met (J q̇ = 0 and J q̇ ≥ 0 hold for α q̇), and it
//! is the smallest change of q̇ in the kinetic metric that removes the excess.
//!
//! The budget is semi-implicit Euler's own: its modified energy H = T + U + (h/2) q̇ᵀQ_g (Q_g
//! gravity's generalised force; H is what the step keeps exactly under constant forces, as in
//! `constraint::impact::rebound`), and the applied forces' work as the step applies them: h q̄̇ᵀτ
//! with τ the forces of the step's start (actuators, springs, fluid) held over it and the
//! damping −B q̇⁺ of the implicit step, q̄̇ the mean of the velocities before and after; and the
//! constraint rows' work toward the targets that ask for energy (a penetration's or an
//! equality's error removed, a motion-control trajectory: `constraint::solve::correction_work`).
//! What a step adds beyond these, less `SLACK` of the kinetic energy left for the budget's own
//! linearisation, is the integrator's error. Post-stabilisation's lift out of a penetration that
//! follows is not paid from the velocities (it slowed a cylinder rolling on a line contact by
//! 0.4% in a second): it is reported in [`EnergyBound::allowance`]. Only steps with contact rows are
//! bounded: without contacts the chain's momentum is conserved, which scaling would not keep.

use crate::dynamics::kinematics::{self, KinData};
use crate::dynamics::{energy, DynamicsData};
use crate::model::Model;

/// What the bound keeps of a step: the modified energy and the velocities its force phase began
/// with (after any impact, whose exact impulses do not add energy).
#[derive(Clone, Debug, Default)]
pub struct EnergyBound {
    /// H of the step's start plus the rows' work.
    start: f64,
    /// |T| + |U| of the step's start: the scale of round-off.
    scale: f64,
    /// q̇ the step's force phase began with, the applied forces' (after any impact).
    qvel: Vec<f64>,
    /// What the last bounded step may add beyond its start's H and the applied work: the rows'
    /// corrections, the slack, and the energy post-stabilisation's move gave it
    /// ([`EnergyBound::lifted`]).
    pub allowance: f64,
    /// H at the step's end before post-stabilisation.
    end: f64,
    /// Steps whose velocities the bound scaled.
    pub bounded: u64,
}

/// Excess left to the step, as a fraction of its kinetic energy: the budget's own error. Its
/// work terms are the step's linearisation (friction's and the arc terms' work on a rolling
/// body are not exactly zero in it), and bounding them to round-off slowed a cylinder rolling
/// down an incline by 1% in a second; a landing's gain is tens of percent.
const SLACK: f64 = 1e-3;
/// Excess (of the energies' scale) left to round-off.
const ROUND_OFF: f64 = 1e-9;

impl EnergyBound {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        EnergyBound { qvel: vec![0.0; m.nv], ..Default::default() }
    }

    /// Records H and q̇ of the force phase's start, `kin` the kinematics of (qpos, `qvel`), and
    /// the work `rows` the constraint rows' corrections do over the step
    /// ([`crate::constraint::solve::correction_work`]).
    pub fn begin(&mut self, m: &Model, kin: &KinData, qvel: &[f64], rows: f64) {
        let (t, u, g) = terms(m, kin, qvel);
        self.start = t + u + 0.5 * m.opt.timestep * g + rows;
        self.allowance = rows;
        self.scale = t.abs() + u.abs();
        self.qvel.copy_from_slice(qvel);
    }

    /// Scales `qvel` (after the step, at `qpos`) onto the budget if the step exceeded it, with the
    /// end state's kinematics computed into `dy.ahead` (post-stabilisation's check takes them).
    /// Whether it scaled.
    pub fn bound(&mut self, m: &Model, dy: &mut DynamicsData, qpos: &[f64], qvel: &mut [f64]) -> bool {
        let h = m.opt.timestep;
        let (t1, u1, g1) = terms(m, dy.ahead.at(m, qpos, qvel), qvel);
        self.end = t1 + u1 + 0.5 * h * g1;
        // f(α) = H(α q̇⁺) − budget(α) = a α² + b α + c, with the applied forces τ_e (damping
        // excluded: its force is −B q̇⁺ over the implicit step)
        let (mut damp_end, mut damp_cross, mut tau_start, mut tau_end) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..m.nv {
            let (b, vs, v1) = (m.dof_damping[k], self.qvel[k], qvel[k]);
            let tau = dy.qfrc_applied[k] + b * vs;
            (damp_end, damp_cross) = (damp_end + b * v1 * v1, damp_cross + b * vs * v1);
            (tau_start, tau_end) = (tau_start + vs * tau, tau_end + v1 * tau);
        }
        // the budget: the start's H, the applied work and the slack
        let budget = self.start + 0.5 * h * tau_start + SLACK * t1 + ROUND_OFF * (self.scale + t1 + u1.abs());
        self.allowance += SLACK * t1;
        let a = t1 + 0.5 * h * damp_end;
        let b = 0.5 * h * (g1 - tau_end + damp_cross);
        let c = u1 - budget;
        let excess = a + b + c;
        // c > 0: the positions alone exceed the budget, which no scaling of q̇ meets
        if excess.is_nan() || excess <= 0.0 || a <= 0.0 || c > 0.0 {
            return false;
        }
        // the largest α with f(α) ≤ 0: f is convex with f(0) ≤ 0 < f(1)
        let q = -0.5 * (b + b.signum() * (b * b - 4.0 * a * c).sqrt());
        let alpha = if q == 0.0 { 0.0 } else { (q / a).max(c / q).clamp(0.0, 1.0) };
        for v in qvel.iter_mut() {
            *v *= alpha;
        }
        self.end = alpha * alpha * t1 + u1 + alpha * 0.5 * h * g1;
        // the configuration is the same: only the velocities are new
        kinematics::forward_velocity(m, qvel, &mut dy.ahead.kin);
        dy.ahead.keep(qpos, qvel);
        self.bounded += 1;
        true
    }

    /// Adds to [`EnergyBound::allowance`] the energy post-stabilisation's move out of a
    /// penetration gave the end state (`qpos`, `qvel`).
    pub fn lifted(&mut self, m: &Model, dy: &mut DynamicsData, qpos: &[f64], qvel: &[f64]) {
        let (t, u, g) = terms(m, dy.ahead.at(m, qpos, qvel), qvel);
        self.allowance += (t + u + 0.5 * m.opt.timestep * g - self.end).max(0.0);
    }
}

/// T, U (of the moving bodies) and g·P of a state from its kinematics `kin` and `qvel`.
fn terms(m: &Model, kin: &KinData, qvel: &[f64]) -> (f64, f64, f64) {
    let (t, g) = energy::kinetic_and_gravity_power(m, kin, qvel);
    (t, energy::moving_gravity_potential(m, kin), g)
}
