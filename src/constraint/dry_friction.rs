//! Dry friction known ahead of the solve. A dof's friction loss is a ± pair of rows whose force
//! is bounded by the loss (`rows::push_friction_rows`): while the dof slides, the answer holds the
//! force at its cap against the motion, and a joint of a walking robot slides most of the time.
//! A dof that slid at its cap last step and still moves the same way most likely slides on: its
//! friction is applied as the known force −loss · sign(q̇) through the ABA instead, and its rows
//! and their LCP variables are not posed. The step's answer is then the rows' exactly when each
//! such dof ends the step still moving that way or at rest (s q̇⁺ ≥ 0, s the sign it slid with):
//! that is the LCP's condition for a force at its cap (the row against the motion at its bound,
//! its slack σ = s q̇⁺ / h ≥ 0; the other row without force, its w = s q̇⁺ / h ≥ 0). Where one
//! does not hold (the dof would stop and turn within the step), the step is solved again with
//! that dof's rows posed, and with every dof's if one turns again (`step::constrain`).
//! Only under Euler (MuJoCo's Euler and implicitfast): RK4's stages and leapfrog's midpoint
//! evaluate the forces elsewhere than the rows' check reads them.

use super::solve::Level;
use super::system::{ConstraintData, RowKind};
use super::History;
use crate::dynamics::DynamicsData;
use crate::model::{Integrator, Model};

/// Relative shortfall below its cap within which a friction row's force counts as at the cap.
const AT_CAP: f64 = 1e-9;
/// How many steps of its last acceleration a sliding dof's velocity must outlast for the next
/// step to take its friction as known.
const MARGIN: f64 = 1.5;

/// Before the step's dynamics: `dy.qfrc_friction` holds −loss · s on each dof that slid at its
/// cap last step (`history.sliding`) and still moves the same way, and `dy.friction_known` says
/// whether there is one.
pub fn predict(m: &Model, history: &History, qvel: &[f64], dy: &mut DynamicsData) {
    dy.friction_known = false;
    if history.sliding.is_empty() || m.opt.integrator != Integrator::Euler {
        return;
    }
    dy.qfrc_friction.fill(0.0);
    for &(dof, positive) in &history.sliding {
        let (loss, v) = (m.dof_frictionloss[dof], qvel[dof]);
        if loss > 0.0 && (if positive { v > 0.0 } else { v < 0.0 }) {
            dy.qfrc_friction[dof] = if positive { -loss } else { loss };
            dy.friction_known = true;
        }
    }
}

/// Whether every dof with known friction ends the step (velocities `qvel` now, accelerations
/// `dy.qacc` over the step) still moving the way it slid, or at rest: the answer is then the
/// one with the dof's rows.
pub fn holds(m: &Model, dy: &DynamicsData, qvel: &[f64]) -> bool {
    let h = m.opt.timestep;
    !dy.friction_known || dy.qfrc_friction.iter().zip(qvel).zip(&dy.qacc).all(|((&f, &v), &a)| !turns(f, v, a, h))
}

/// Whether a known friction `f` would turn its dof, moving at `v` with acceleration `a`, within
/// a step `h`: its velocity at the step's end has the sign of the force.
fn turns(f: f64, v: f64, a: f64, h: f64) -> bool {
    f * (v + h * a) > 0.0
}

/// The dofs whose known friction would turn them within the step (`holds` fails on them) lose
/// it, to be posed as rows; with `all`, every dof does.
pub fn turning_to_rows(m: &Model, dy: &mut DynamicsData, qvel: &[f64], all: bool) {
    let h = m.opt.timestep;
    if all {
        dy.friction_known = false;
        return;
    }
    let mut left = false;
    for ((f, &v), &a) in dy.qfrc_friction.iter_mut().zip(qvel).zip(&dy.qacc) {
        if turns(*f, v, a, h) {
            *f = 0.0;
        }
        left |= *f != 0.0;
    }
    dy.friction_known = left;
}

/// After the step: the dofs whose friction it held at the cap into `sliding` (the known ones and
/// those whose rows' force `force` reached it; `level`: the solve applied, whose answers are
/// impulses over the step when time stepping; None: no rows), the direction each slid in;
/// the known friction ends with the step.
pub fn record(m: &Model, dy: &mut DynamicsData, con: &ConstraintData, force: &[f64], level: Option<Level>, qvel: &[f64], sliding: &mut Vec<(usize, bool)>) {
    sliding.clear();
    // far enough from rest that the step's acceleration would not turn it within the next
    let h = m.opt.timestep;
    let away = |dof: usize, positive: bool| {
        let v = if positive { qvel[dof] } else { -qvel[dof] };
        v > MARGIN * h * dy.qacc[dof].abs()
    };
    if dy.friction_known {
        sliding.extend(dy.qfrc_friction.iter().enumerate().filter(|&(dof, &f)| f != 0.0 && away(dof, f < 0.0)).map(|(dof, &f)| (dof, f < 0.0)));
    }
    dy.friction_known = false;
    let Some(level) = level else { return };
    let per_step = if level == Level::TimeStep { m.opt.timestep } else { 1.0 };
    let before = sliding.len();
    for j in 0..con.len().min(force.len()) {
        // each dof's pair is its + row then its − row
        if con.kind[j] != RowKind::DryFriction || con.source[j] >= m.nv || con.dof[j].1 < 0.0 {
            continue;
        }
        let net = force[j] - force[j + 1];
        if net != 0.0 && net.abs() >= (1.0 - AT_CAP) * con.cap[j] * per_step && away(con.source[j], net < 0.0) {
            sliding.push((con.source[j], net < 0.0));
        }
    }
    if before > 0 && sliding.len() > before {
        sliding.sort_unstable_by_key(|&(dof, _)| dof);
    }
}
