//! One simulation step. [`step`] reads as the pipeline; each stage lives in the room named for
//! what it does (`dynamics`, `collision`, `constraint`, `integrate`).

pub mod data;
pub mod run;
pub mod state;

use crate::collision;
mod impacts;

use impacts::impacts;
use crate::constraint::rows::{build_rows, missed_contacts, missed_limits};
use crate::constraint::solve::{apply_to_qacc, correction_work, solve_rows, Level};
use crate::constraint::{dry_friction, stabilize, test_forces, RowKind};
use crate::dynamics::{self, activation, kinematics};
use crate::integrate::{self, rk4::{rk4, rk4_activations}};
use crate::model::{ConstraintMode, Integrator, Model};
use data::Data;
use crate::state::WorldState;

pub use crate::timing::{Stage, STAGES, STAGE_NAMES};
use crate::timing::timed;

/// Forward dynamics at the state without constraints: fills `data.dynamics.qacc` with the true
/// accelerations (no implicit damping), as MuJoCo's `mj_forward` with constraints disabled.
pub fn forward(m: &Model, data: &mut Data, s: &WorldState<'_>) {
    dynamics::forward(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act);
}

/// Advances the state (time, qpos, qvel, act) by one time step under its ctrl.
pub fn step(m: &Model, data: &mut Data, s: &mut WorldState<'_>) {
    let h = m.opt.timestep;
    let h_damp = damping_horizon(m, data);
    // leapfrog: the step's dynamics are the midpoint configuration's
    let leapfrog = m.opt.integrator == Integrator::Leapfrog;
    if leapfrog {
        data.constraints.start.qpos.copy_from_slice(s.qpos);
        data.constraints.start.qvel.copy_from_slice(s.qvel);
        timed!(data, Stage::Integration, integrate::integrate_pos(m, s.qpos, s.qvel, 0.5 * h));
    }
    // 1. poses and velocities
    timed!(data, Stage::Kinematics, dynamics::kinematics(m, &mut data.dynamics, s.qpos, s.qvel));
    // 2. articulated inertias and the constraint-free accelerations, with the dry friction of
    // the dofs sliding on as known forces
    dry_friction::predict(m, &data.constraints.history, (s.qpos, s.qvel), &data.coll.contacts, &mut data.dynamics);
    timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h_damp));
    if !dry_friction::held(m, &data.dynamics.aba) {
        // a held joint whose torque exceeds its friction before any constraint force slips
        dry_friction::let_go(m, &mut data.dynamics.aba, false);
        timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h_damp));
    }
    // 3. contacts of this configuration (reach over the step from velocities and accelerations)
    timed!(data, Stage::Collision, collision::collide(m, &data.dynamics, s, &mut data.coll));
    // 4. constraint rows: contacts (normal + friction), active limits, dry friction, motion control
    timed!(data, Stage::Rows, build_rows(m, &mut data.world(), s));
    rows_off_held_joints(m, data, s, h_damp);
    if data.constraints.con.is_empty() && !(dry_friction::holds(m, &data.dynamics, s.qvel) && dry_friction::held(m, &data.dynamics.aba)) {
        // a known friction would turn its dof, or a held joint's friction cannot hold it: their
        // rows instead
        dry_friction::turning_to_rows(m, &mut data.dynamics, s.qvel, false);
        dry_friction::let_go(m, &mut data.dynamics.aba, false);
        timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h_damp));
        timed!(data, Stage::Rows, build_rows(m, &mut data.world(), s));
        rows_off_held_joints(m, data, s, h_damp);
    }
    data.constraints.history.constrained = !data.constraints.con.is_empty();
    if data.constraints.con.is_empty() {
        // 8. nothing to constrain: the plain step
        free_step(m, data, s, h_damp);
        record_friction(m, data, s.qvel, None);
    } else {
        // 5–7. b, K, impacts and the constraint solve, into q̈ (and q̇ for impacts)
        let level = constrain(m, data, s, h_damp);
        // 8. integrate under the energy bound
        let bounded = constrained_integration(m, data, s, level, leapfrog);
        advance_activations(m, data, s);
        // 9. limits leapfrog's drift crossed, penetration and limits the linearised rows missed
        if leapfrog {
            timed!(data, Stage::Projection, stabilize::hold_limits(m, &data.constraints.start, s.qpos));
        }
        let moved = timed!(data, Stage::Projection, stabilize::project(m, &mut data.world(), s));
        if bounded && moved {
            timed!(data, Stage::Projection, data.energy.lifted(m, &mut data.dynamics, s.qpos, s.qvel));
        }
        let c = &mut data.constraints;
        c.applied.record(m, &c.con, &c.solve.force, data.coll.contacts.len());
        record_friction(m, data, s.qvel, Some(level));
    }
    *s.time += h;
}

/// Lets go of the held joints that a joint row acts on, and evaluates the dynamics and the rows
/// again without them, until none is (`dry_friction::let_go_of_rows`).
fn rows_off_held_joints(m: &Model, data: &mut Data, s: &WorldState<'_>, h_damp: f64) {
    while dry_friction::let_go_of_rows(m, &data.constraints.con, &mut data.dynamics.aba) {
        timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h_damp));
        timed!(data, Stage::Rows, build_rows(m, &mut data.world(), s));
    }
}

/// The known dry friction and the torques holding the held joints among the applied constraint
/// forces, and the dofs sliding at their friction's cap into the history (`level`: the solve
/// applied, if any).
fn record_friction(m: &Model, data: &mut Data, qvel: &[f64], level: Option<Level>) {
    let (dy, c) = (&mut data.dynamics, &mut data.constraints);
    if dy.friction_known {
        c.applied.joint.extend(dy.qfrc_friction.iter().enumerate().filter(|(_, f)| **f != 0.0).map(|(dof, &f)| (dof, f)));
    }
    if dry_friction::holding(m, &dy.aba) {
        let aba = &dy.aba;
        c.applied.joint.extend((0..m.nnode).filter(|&i| aba.locked[i]).map(|i| (m.node_dofadr[i], aba.lock_torque[i])));
    }
    dry_friction::record(m, dy, &c.con, &c.solve.force, level, qvel, &mut c.history.sliding);
}

/// Stage 8 of a step with constraint rows: semi-implicit Euler (the seed's scheme; RK4's
/// constrained steps too), or leapfrog's closing kick and drift. A semi-implicit step with
/// contacts is held to the energy it began with plus the work of the applied forces and of the
/// rows' corrections; returns whether it was.
fn constrained_integration(m: &Model, data: &mut Data, s: &mut WorldState<'_>, level: Level, leapfrog: bool) -> bool {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let bounded = !leapfrog && data.constraints.con.kind.contains(&RowKind::Normal);
    if bounded {
        let rows = correction_work(m, &data.world(), level);
        timed!(data, Stage::Integration, data.energy.begin(m, &data.dynamics.kin, s.qvel, rows));
    }
    timed!(data, Stage::Integration, integrate::kick_drift(m, s.qpos, s.qvel, &data.dynamics.qacc, h, lever));
    if bounded {
        timed!(data, Stage::Integration, data.energy.bound(m, &mut data.dynamics, s.qpos, s.qvel));
    }
    bounded
}

/// The horizon over which a step treats joint damping implicitly. Euler and leapfrog treat it
/// implicitly (MuJoCo's `Euler`), and so does a step with constraint rows, which is
/// semi-implicit Euler; RK4's stages do not (0). An RK4 model evaluates first as the last step
/// needed (contacts and rows are chosen with these accelerations) and again when this step
/// turns out otherwise.
fn damping_horizon(m: &Model, data: &Data) -> f64 {
    match m.opt.integrator {
        Integrator::Rk4 if !(m.may_constrain() && data.constraints.history.constrained) => 0.0,
        _ => m.opt.timestep,
    }
}

/// The activations over the step by their rates at its start (semi-implicit Euler's and
/// leapfrog's; RK4 advances them with its stages).
fn advance_activations(m: &Model, data: &mut Data, s: &mut WorldState<'_>) {
    if m.na == 0 {
        return;
    }
    if m.opt.integrator == Integrator::Rk4 {
        rk4_activations(m, s.ctrl, s.act, &mut data.rk4, m.opt.timestep);
    } else {
        activation::rates(m, s.ctrl, s.act, &mut data.dynamics.act_dot);
        activation::advance(m, s.act, &data.dynamics.act_dot, m.opt.timestep);
    }
}

/// Stage 8 of a step without constraint rows, from the dynamics evaluated with damping over
/// `h_damp`.
fn free_step(m: &Model, data: &mut Data, s: &mut WorldState<'_>, h_damp: f64) {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    data.constraints.solve.force.clear();
    data.constraints.applied.clear();
    match m.opt.integrator {
        Integrator::Euler | Integrator::Leapfrog => {
            timed!(data, Stage::Integration, integrate::kick_drift(m, s.qpos, s.qvel, &data.dynamics.qacc, h, lever));
            advance_activations(m, data, s);
        }
        Integrator::Rk4 => {
            if h_damp != 0.0 {
                timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, 0.0));
            }
            timed!(data, Stage::Integration, rk4(m, &mut data.dynamics, &mut data.rk4, s, h))
        }
    }
}

/// Stages 5–7 with the rows of stage 4: b, impacts, the constraint solve into q̈ (impacts into
/// q̇). A limit or contact without a row that the constrained motion would reach (pushed there
/// by contact forces, say) gets its row and the solve runs once more from the constraint-free
/// accelerations; so does a dof whose known dry friction would turn it (`dry_friction`). The
/// level of the solve applied: forces, or impulses over the step.
fn constrain(m: &Model, data: &mut Data, s: &mut WorldState<'_>, h_damp: f64) -> Level {
    let h = m.opt.timestep;
    // with constraints the step is semi-implicit Euler: damping implicit over the step
    if h_damp != h {
        timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h));
    }
    let (mut redo, mut slips) = (false, 0);
    let mut level;
    data.constraints.solve.impact_warm.clear();
    loop {
        let before_all = data.constraints.stats;
        // 5. b; K by test forces once a solve needs it (rows that the constraint-free motion
        // already satisfies need no K)
        timed!(data, Stage::Rows, test_forces::bias(m, &data.dynamics.kin, &data.dynamics.aba, &data.dynamics.qacc, &mut data.constraints.con));
        // 6. impacts (e > 0)
        let impacted = impacts(m, &mut data.world(), s);
        if m.opt.constraint_mode == ConstraintMode::Velocity {
            // 7'. one impulse solve: q̈ = q̈₀ + Σ p_k Δq̈⁽ᵏ⁾ / h
            level = Level::TimeStep;
            solve_rows(m, &mut data.world(), level);
            apply_to_qacc(m, &mut data.world(), 1.0 / h);
        } else {
            // 7. constraint forces at the acceleration level, added to q̈; where that LCP has no
            // exact answer (Painlevé's configurations, a pile's redundant contacts), the step's
            // impulses instead, as in 7', whose LCP always has one (Stewart & Trinkle 1996;
            // Anitescu & Potra 1997)
            let before = data.constraints.stats;
            level = Level::Acceleration;
            solve_rows(m, &mut data.world(), level);
            if data.constraints.stats.inexact_since(&before) {
                let stats = &mut data.constraints.stats;
                (stats.fallback_pgs, stats.inexact, stats.fallback_zero) = (before.fallback_pgs, before.inexact, before.fallback_zero);
                stats.impulse_steps += 1;
                level = Level::TimeStep;
                solve_rows(m, &mut data.world(), level);
                apply_to_qacc(m, &mut data.world(), 1.0 / h);
            } else {
                apply_to_qacc(m, &mut data.world(), 1.0);
            }
        }
        // the held joints' torques with the solve's forces; a solve with no exact answer may
        // owe it to the joints held (a contact no free joint can move)
        let holding = dry_friction::holding(m, &data.dynamics.aba);
        let inexact = holding && data.constraints.stats.inexact_since(&before_all);
        if holding {
            let scale = if level == Level::Acceleration { 1.0 } else { 1.0 / h };
            let c = &data.constraints;
            dry_friction::add_held_torques(m, &c.con, &c.solve.force, scale, &mut data.dynamics.aba);
        }
        // with no force, no impulse and the accelerations the rows were chosen with, the motion
        // is the constraint-free one they were chosen for: nothing can have been missed
        let pushed = impacted || h_damp != h || data.constraints.solve.force.iter().any(|&f| f != 0.0);
        let missed = pushed && (missed_limits(m, &mut data.world(), s) | timed!(data, Stage::Collision, missed_contacts(m, &mut data.world(), s)));
        // a known dry friction that would turn its dof within the step: that dof's rows instead
        // (every sliding dof's, the second time)
        let slipped = !dry_friction::holds(m, &data.dynamics, s.qvel) || !dry_friction::held(m, &data.dynamics.aba) || inexact;
        if !slipped && (redo || !missed) {
            break;
        }
        if slipped {
            slips += 1;
            dry_friction::turning_to_rows(m, &mut data.dynamics, s.qvel, slips > 1);
            dry_friction::let_go(m, &mut data.dynamics.aba, slips > 1 || inexact);
        }
        redo = true;
        // the first solve's limit rows stay (an impulse may have made them look inactive)
        for r in (0..data.constraints.con.len()).filter(|&r| data.constraints.con.kind[r] == RowKind::Limit) {
            let side = (data.constraints.con.dof[r].1 < 0.0) as usize;
            data.constraints.rows.limit_forced[2 * data.constraints.con.source[r] + side] = true;
        }
        timed!(data, Stage::Dynamics, dynamics::accelerations(m, &mut data.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h));
        timed!(data, Stage::Rows, build_rows(m, &mut data.world(), s));
        rows_off_held_joints(m, data, s, h);
        data.constraints.solve.impact_warm.clear();
    }
    if redo {
        data.constraints.rows.limit_forced.fill(false);
    }
    level
}

/// The constraint system a step from (qpos, qvel, ctrl) starts with, for inspection (MuJoCo's
/// `efc_J` and `efc_AR` are the like), at that configuration (leapfrog's step would use its
/// midpoint's).
#[derive(Clone, Debug)]
pub struct ConstraintSystem {
    /// Row kinds.
    pub kind: Vec<RowKind>,
    /// J (rows × nv, row-major): each row's velocity per unit q̇.
    pub jac: Vec<f64>,
    /// K (rows × rows, row-major), every column by test forces: each row's acceleration per unit
    /// force of each row.
    pub k: Vec<f64>,
    /// b: each row's acceleration without constraint force.
    pub b: Vec<f64>,
    /// The joint-space inertia K is built with (nv × nv, CRBA): M, plus h times the joint damping,
    /// which the constrained step treats implicitly (K = J (M + h B)⁻¹ Jᵀ).
    pub inertia: Vec<f64>,
}

/// Stages 1–5 of [`step`] on a copy of `data` (the world and its history are untouched): the
/// rows of the state and their J, K and b.
pub fn constraint_system(m: &Model, data: &Data, s: &WorldState<'_>) -> ConstraintSystem {
    let mut d = data.clone();
    let h = m.opt.timestep;
    kinematics::forward(m, s.qpos, s.qvel, &mut d.dynamics.kin);
    // every row posed: no joint held still
    d.dynamics.aba.locking = false;
    // the constrained step's dynamics: damping implicit over the step, whatever the integrator
    dynamics::accelerations(m, &mut d.dynamics, s.qpos, s.qvel, s.ctrl, s.act, h);
    collision::collide(m, &d.dynamics, s, &mut d.coll);
    build_rows(m, &mut d.world(), s);
    test_forces::assemble(m, &d.dynamics.kin, &d.dynamics.aba, &d.dynamics.qacc, &mut d.constraints.con);
    let mut inertia = crate::dynamics::crba::crba(m, &d.dynamics.kin);
    for (k, damping) in m.dof_damping.iter().enumerate() {
        inertia[k * m.nv + k] += h * damping;
    }
    ConstraintSystem { kind: d.constraints.con.kind.clone(), jac: crate::constraint::rows::dense_jacobian(m, &d.dynamics.kin, &d.constraints.con), k: d.constraints.con.k_dense(), b: d.constraints.con.b.clone(), inertia }
}
