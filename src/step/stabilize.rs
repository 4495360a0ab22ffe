//! Stage 8 — post-stabilisation of contact penetration (Cline & Pai 2003, *Post-stabilization for
//! rigid body simulation with contact and constraints*): after the step, the contact points are
//! carried to the new configuration; if one now penetrates by more than [`SLOP`], the positions
//! (not the velocities, so no energy is added) move by δq = M⁻¹ Jᵀ p, with p ≥ 0 solving the normal
//! rows' LCP  K p + d ≥ 0 ⟂ p ≥ 0  on the step's K and Δq̈ columns (K of the start of the step),
//! the step's limit rows included so that no joint is pushed past its limit.
//!
//! Why: a contact row makes the *linearised* gap close at the step's end, but a point on a body
//! turning at ω moves on an arc, off the straight line by about h²ω²r/2 — at dt = 0.01 centimetres
//! for a half-metre limb. Baumgarte terms alone remove it only over several steps.

use glam::DVec3;

use crate::data::Data;
use crate::model::{JointType, Model, WORLD};

use super::constraint::RowKind;
use super::integrate::integrate_pos;
use super::kinematics::{self, KinData};
use super::lcp::{self, LcpWork, Role};

/// Penetration left to the Baumgarte term (m).
pub const SLOP: f64 = 1e-4;

/// Scratch of the projection, allocated with the world.
#[derive(Clone, Debug, Default)]
pub struct StabilizeData {
    /// Kinematics of the configuration after the step.
    pub kin: KinData,
    /// Normal and limit rows taking part.
    rows: Vec<usize>,
    /// Their gaps after the step (limits: not below zero).
    gap: Vec<f64>,
    m: Vec<f64>,
    role: Vec<Role>,
    p: Vec<f64>,
    dq: Vec<f64>,
    /// End-of-step velocities (nv), scratch for the step's second contact check.
    pub vel_end: Vec<f64>,
    work: LcpWork,
    /// Projections run.
    pub projections: u64,
}

impl StabilizeData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        StabilizeData { kin: KinData::new(m), dq: vec![0.0; m.nv], vel_end: vec![0.0; m.nv], ..Default::default() }
    }
}

/// Projects `qpos` (after the step, with `qvel` after the step) out of penetration, using the rows,
/// K and Δq̈ in `data.con` and the kinematics of the step's start in `data.kin`. The projection's
/// LCP counts in `data.stats`.
pub fn project(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &[f64]) {
    if !(0..data.con.len()).any(|j| data.con.kind[j] == RowKind::Normal) {
        return;
    }
    // K is the start of the step's, so a projection can fall short: checked and repeated
    for _ in 0..PASSES {
        if !gaps(m, data, qpos, qvel) {
            return;
        }
        solve(m, data, qpos);
    }
}

/// Passes of check and projection at most per step.
const PASSES: usize = 3;

/// The normal rows' gaps at `qpos` into `post.gap` (and the limit rows' after them), or false when
/// no contact penetrates beyond [`SLOP`].
fn gaps(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64]) -> bool {
    let Data { kin, con, post, .. } = data;
    kinematics::forward(m, qpos, qvel, &mut post.kin);
    let new = &post.kin;
    // the contact point, carried by each side's node: d' = d + n'·(p₁' − p₂'), n' turned with side 2
    post.rows.clear();
    post.gap.clear();
    let mut worst = 0.0f64;
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Normal) {
        let moved = |side: usize| {
            let n = con.node[j][side];
            if n == WORLD { (DVec3::ZERO, con.dir[j]) } else {
                let old = kin.node_rot[n] * con.point[j][side] + kin.node_pos[n];
                let now = new.node_rot[n] * con.point[j][side] + new.node_pos[n];
                (now - old, new.node_rot[n] * (kin.node_rot[n].transpose() * con.dir[j]))
            }
        };
        let ((d1, _), (d2, n2)) = (moved(0), moved(1));
        let gap = con.dist[j] + n2.dot(d1 - d2);
        worst = worst.min(gap);
        post.rows.push(j);
        post.gap.push(gap);
    }
    if worst >= -SLOP {
        return false;
    }
    // limit rows take part so the projection cannot push a joint past its limit (nor deeper
    // into a violation it already has)
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Limit) {
        let (joint, (_, sign)) = (con.source[j], con.dof[j]);
        let q = qpos[m.jnt_qposadr[joint]];
        let [lo, hi] = m.jnt_range[joint];
        post.rows.push(j);
        post.gap.push((if sign > 0.0 { q - lo } else { hi - q }).max(0.0));
    }
    true
}

/// One projection δq = Σ p_k Δq̈⁽ᵏ⁾ from the LCP on the rows and gaps in `post`.
fn solve(m: &Model, data: &mut Data, qpos: &mut [f64]) {
    let Data { con, post, stats, .. } = data;
    post.projections += 1;
    let (nr, k) = (con.len(), post.rows.len());
    post.m.clear();
    post.role.clear();
    for (a, &j) in post.rows.iter().enumerate() {
        for &i in &post.rows {
            post.m.push(con.k[j * nr + i]);
        }
        post.m[a * k + a] += lcp::REGULARISATION * con.k[j * nr + j].abs().max(1e-300);
        post.role.push(Role::Normal);
    }
    post.p.clear();
    post.p.resize(k, 0.0);
    lcp::solve(k, &post.m, &post.gap, &post.role, None, &mut post.p, &mut post.work, stats);
    post.dq.fill(0.0);
    for (a, &j) in post.rows.iter().enumerate() {
        let p = post.p[a];
        if p != 0.0 {
            for (d, c) in post.dq.iter_mut().zip(&con.dqdd[j * m.nv..(j + 1) * m.nv]) {
                *d += p * c;
            }
        }
    }
    // limits without a row are not in the LCP: shorten the step so that none is crossed
    let mut alpha = 1.0f64;
    for j in (0..m.njnt).filter(|&j| m.jnt_limited[j] && matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide)) {
        let (q, dq) = (qpos[m.jnt_qposadr[j]], post.dq[m.jnt_dofadr[j]]);
        let sign = if dq < 0.0 { 1.0 } else { -1.0 };
        let has_row = post.rows.iter().any(|&r| con.kind[r] == RowKind::Limit && con.source[r] == j && con.dof[r].1 == sign);
        let [lo, hi] = m.jnt_range[j];
        let room = if dq < 0.0 { q - lo } else { hi - q };
        if !has_row && dq.abs() > room.max(0.0) {
            alpha = alpha.min(room.max(0.0) / dq.abs());
        }
    }
    integrate_pos(m, qpos, &post.dq, alpha);
}
