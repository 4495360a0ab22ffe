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
//! A dof at rest (its velocity one its friction alone can stop within the step) most likely
//! stays stuck: its joint is held still through the step, a joint of known acceleration −q̇/h
//! (Featherstone 2008, §9.2: D⁻¹ 0 in the ABA, so test forces pass through it as through a
//! weld; `aba::inward_held`), and its rows are not posed either. The step's answer is the rows'
//! exactly when the torque holding each such joint, with the solve's forces, lies within its
//! friction (|τ| ≤ loss: the rows' forces inside their caps, w = 0). A joint whose torque
//! exceeds it before any constraint force is let go at once (the dynamics evaluated again);
//! where one fails with the solve's forces, it is let go and the step solved again with its
//! rows, and with every dof's rows if one fails again (`hold_candidates` says which joints may
//! be held).
//! Only under Euler (MuJoCo's Euler and implicitfast): RK4's stages and leapfrog's midpoint
//! evaluate the forces elsewhere than the rows' check reads them; and not with restitution,
//! whose impacts pass impulses through the joints.

use super::solve::Level;
use super::system::{ConstraintData, RowKind};
use super::History;
use crate::collision::Contact;
use crate::dynamics::aba::AbaData;
use crate::dynamics::DynamicsData;
use crate::model::{Integrator, Model, WORLD};

/// Relative shortfall below its cap within which a friction row's force counts as at the cap.
const AT_CAP: f64 = 1e-9;
/// How many steps of its last acceleration a sliding dof's velocity must outlast for the next
/// step to take its friction as known.
const MARGIN: f64 = 1.5;

/// Before the step's dynamics: `dy.qfrc_friction` holds −loss · s on each dof that slid at its
/// cap last step (`history.sliding`) and still moves the same way, and `dy.friction_known` says
/// whether there is one.
pub fn predict(m: &Model, history: &History, (qpos, qvel): (&[f64], &[f64]), contacts: &[Contact], dy: &mut DynamicsData) {
    dy.friction_known = false;
    if m.opt.integrator != Integrator::Euler {
        return;
    }
    if !history.sliding.is_empty() {
        dy.qfrc_friction.fill(0.0);
        for &(dof, positive) in &history.sliding {
            let (loss, v) = (m.dof_frictionloss[dof], qvel[dof]);
            if loss > 0.0 && (if positive { v > 0.0 } else { v < 0.0 }) {
                dy.qfrc_friction[dof] = if positive { -loss } else { loss };
                dy.friction_known = true;
            }
        }
    }
    hold_candidates(m, qpos, qvel, contacts, dy);
}

/// The joints the step may hold still (`AbaData::lock_cap`, `lock_qacc`): one dof with friction
/// loss, not sliding on with known friction, strictly within its limits, in no equality or fixed
/// tendon with rows, and carrying no body that touched anything last step (`contacts`): the
/// torque holding a joint that bears a contact depends on how its contacts share the load,
/// which a held (rigid) chain leaves open (a stance leg's and its feet's). The inward pass holds
/// those whose friction alone could stop them within the step.
fn hold_candidates(m: &Model, qpos: &[f64], qvel: &[f64], contacts: &[Contact], dy: &mut DynamicsData) {
    let aba = &mut dy.aba;
    aba.locking = false;
    if !m.opt.hold_stuck_joints || m.opt.restitution != 0.0 || !m.dof_frictionloss.iter().any(|&l| l > 0.0) {
        return;
    }
    let h = m.opt.timestep;
    for i in 0..m.nnode {
        let dof = m.node_dofadr[i];
        let cap = if m.node_nv[i] == 1 { m.dof_frictionloss[dof] } else { 0.0 };
        let jnt = m.dof_jnt[dof];
        let within = || !m.jnt_limited[jnt] || !m.opt.limit || {
            let ([lo, hi], q) = (m.jnt_range[jnt], qpos[m.jnt_qposadr[jnt]]);
            lo < q && q < hi
        };
        let free = !(dy.friction_known && dy.qfrc_friction[dof] != 0.0);
        // D ≥ armature + h · damping: a joint moving faster than that lets its friction stop
        // cannot be held
        let stoppable = || (m.dof_armature[dof] + h * m.dof_damping[dof]) * qvel[dof].abs() <= h * cap;
        aba.lock_cap[i] = if cap > 0.0 && free && stoppable() && within() { cap } else { 0.0 };
        aba.lock_qacc[i] = -qvel[dof] / h;
        aba.locking |= aba.lock_cap[i] > 0.0;
    }
    if !aba.locking {
        return;
    }
    for c in contacts {
        for g in [c.geom1, c.geom2] {
            bear(m, m.body_node[m.geom_body[g]], |n| aba.lock_cap[n] = 0.0);
        }
    }
    // nor a joint an equality couples, or a fixed tendon with a limit or friction spans: their
    // rows would let it go each step
    let coupled = (0..m.neq).filter(|&e| m.eq_active[e]).flat_map(|e| m.eq_side(e, 0).iter().chain(m.eq_side(e, 1)));
    let spanned = (0..m.ntendon).filter(|&t| m.tendon_limited[t] || m.tendon_frictionloss[t] > 0.0).flat_map(|t| m.tendon_terms(t));
    for w in coupled.chain(spanned) {
        aba.lock_cap[m.jnt_node[m.dof_jnt[w.dof]]] = 0.0;
    }
    aba.locking = aba.lock_cap.iter().any(|&c| c > 0.0);
}

/// `f` on node n and each node it hangs from: the joints that bear a force on n.
fn bear(m: &Model, mut n: usize, mut f: impl FnMut(usize)) {
    while n != WORLD {
        f(n);
        n = m.node_parent[n];
    }
}

/// Whether the step holds any joint still.
pub fn holding(m: &Model, aba: &AbaData) -> bool {
    aba.locking && (0..m.nnode).any(|i| aba.locked[i])
}

/// Whether each held joint's torque (`aba.lock_torque`, with the solve's forces once added)
/// lies within its friction.
pub fn held(m: &Model, aba: &AbaData) -> bool {
    !aba.locking || (0..m.nnode).all(|i| !aba.locked[i] || aba.lock_torque[i].abs() <= aba.lock_cap[i])
}

/// Lets go of the held joints whose torque exceeds their friction, or of every one with `all`:
/// their rows are posed instead.
pub fn let_go(m: &Model, aba: &mut AbaData, all: bool) {
    for i in 0..m.nnode {
        if aba.locked[i] && (all || aba.lock_torque[i].abs() > aba.lock_cap[i]) {
            aba.lock_cap[i] = 0.0;
        }
    }
    if all {
        aba.locking = false;
    }
}

/// Lets go of the held joints a joint row (a limit, an equality, motion control, a tendon's
/// row) acts on and of those bearing a point row (a contact, a connect); whether there was one.
pub fn let_go_of_rows(m: &Model, con: &ConstraintData, aba: &mut AbaData) -> bool {
    if !holding(m, aba) {
        return false;
    }
    let mut any = false;
    let mut go = |n: usize| {
        if aba.locked[n] && aba.lock_cap[n] > 0.0 {
            aba.lock_cap[n] = 0.0;
            any = true;
        }
    };
    for j in 0..con.len() {
        if con.kind[j].is_point() {
            for n in con.node[j] {
                bear(m, n, &mut go);
            }
        } else {
            for &(dof, _) in con.joint_terms(j) {
                go(m.jnt_node[m.dof_jnt[dof]]);
            }
        }
    }
    any
}

/// Adds scale · Σ_k f_k δτ⁽ᵏ⁾ (the solve's forces `force`, or impulses with scale 1/h) to the
/// held joints' torques.
pub fn add_held_torques(m: &Model, con: &ConstraintData, force: &[f64], scale: f64, aba: &mut AbaData) {
    let nv = m.nv;
    for i in (0..m.nnode).filter(|&i| aba.locked[i]) {
        let (dof, tree) = (m.node_dofadr[i], m.node_tree[i]);
        for (k, &f) in force.iter().enumerate().take(con.len()) {
            if f != 0.0 && con.tree[k].contains(&tree) {
                aba.lock_torque[i] += f * scale * con.held_torque[k * nv + dof];
            }
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
    dy.aba.locking = false;
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
