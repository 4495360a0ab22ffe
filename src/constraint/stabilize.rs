//! Stage 9 — post-stabilisation of contact penetration (Cline & Pai 2003, *Post-stabilization for
//! rigid body simulation with contact and constraints*): after the step the configuration is
//! checked; if a contact now penetrates by more than [`SLOP`], the positions (not the velocities,
//! so no energy is added) move by δq = Σ p_k Δq̈⁽ᵏ⁾ with p ≥ 0 solving the LCP
//! J_j δq + d_j ≥ 0 ⟂ p_j ≥ 0 over the step's contact normals (gaps detected afresh), contacts
//! that penetrate now but had no row (their Δq̈ by a test force through the step's ABA
//! quantities), and limit rows (the step's, any the projection would cross, and any joint the
//! step carried past its limit by more than [`LIMIT_SLOP`], which the projection brings back).
//!
//! Why: a contact row makes its predicted gap close at the step's end, and the prediction carries
//! the arcs a turning body's point and a sphere's or capsule's centre move on to second order
//! (`ConstraintData::lift`), but not beyond, nor a box face's contact point sliding over it; and
//! the contact forces can turn a body so that a point without a row reaches the floor. Baumgarte
//! terms alone remove that only over several steps.

use glam::DVec3;

use super::impact::INERT_ROW;
use super::lcp::{self, LcpWork, Role};
use super::system::{self as constraint, RowKind};
use super::delta_pass::{delta_pass, DeltaScratch, LANES};
use super::test_forces::{add_response, responses, tree_dofs};
use super::{Constraints, StepStart, World};
use crate::collision::{self, CollisionData, Contact};
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::{self, KinData};
use crate::dynamics::tendon::{self, TendonData};
use crate::integrate::integrate_pos;
use crate::math::Force;
use crate::model::{Model, WORLD};
use crate::state::WorldState;

/// Penetration left to the Baumgarte term (m).
pub const SLOP: f64 = 1e-4;
/// Limit violation left to the Baumgarte term (rad or m): the contact solve can turn a joint that
/// had no limit row (it was moving away from its limit) back past it.
pub const LIMIT_SLOP: f64 = 1e-5;
/// Fastest a projection pass separates a penetrating contact (m/s; a step's [`PASSES`] move it at
/// most three times as far): a model whose rest pose overlaps its own geoms (a gripper's fingers
/// meshed into each other) is eased apart over several steps, as PhysX's and Bullet's
/// depenetration limits do, instead of flung apart in one.
pub const DEPENETRATION_SPEED: f64 = 1.0;
/// The penetration the step began with that a contact's correction velocity removes: at most
/// [`SLOP`]; beyond it the projection moves the bodies out after the step, and a velocity for
/// the same depth would remain once they are out (a robot whose keyframe sinks two feet 1.8 cm
/// into a height field rolled off them). A limit's whole violation (the step's projection brings
/// back only its own crossings).
pub fn corrected_start(kind: RowKind, dist_start: f64) -> f64 {
    if kind == RowKind::Normal { dist_start.max(-SLOP) } else { dist_start }
}

/// Passes of check and projection at most per step (the LCP uses the ABA of the step's start).
const PASSES: usize = 3;

/// Scratch of the projection, allocated with the world.
#[derive(Clone, Debug, Default)]
pub struct StabilizeData {
    /// Penetrating contacts of the configuration after the step.
    coll: CollisionData,
    /// Projection rows: gap after the step, J (nv each), Δq̈ per unit p (nv each, meaningful on the
    /// row's trees' dofs only), and the limit (joint, sign) of a limit row.
    gap: Vec<f64>,
    jac: Vec<f64>,
    dqdd: Vec<f64>,
    limit: Vec<Option<(usize, f64)>>,
    /// Trees of each row's sides ([`ConstraintData::tree`](constraint::ConstraintData::tree)):
    /// rows that share none have K_ab = 0.
    tree: Vec<[usize; 2]>,
    /// The step's row each projection row is (usize::MAX: a row of its own), whose K entries
    /// the step's test forces measured.
    row: Vec<usize>,
    m: Vec<f64>,
    role: Vec<Role>,
    p: Vec<f64>,
    dq: Vec<f64>,
    delta: DeltaScratch,
    work: LcpWork,
    /// The tendons after the step.
    ten: TendonData,
    /// Variables the solve leaves out.
    left_out: Vec<bool>,
}

impl StabilizeData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        StabilizeData {
            coll: CollisionData::new(m),
            dq: vec![0.0; m.nv],
            delta: DeltaScratch::new(m),
            ten: TendonData::new(m),
            ..Default::default()
        }
    }
}

/// Projects `qpos` (after the step, with `qvel` after the step) out of penetration, using the rows
/// and Δq̈ in `data.constraints.con` and the kinematics and ABA quantities of the step's start. The
/// projection's LCP counts in `data.stats`. Whether it moved `qpos`.
pub fn project(m: &Model, data: &mut World<'_>, s: &mut WorldState<'_>) -> bool {
    let (qpos, qvel) = (&mut *s.qpos, &*s.qvel);
    let con = &data.constraints.con;
    // a tendon's length after the step needs its kinematics: a step with a tendon limit row checks
    let checked = |j: usize| con.kind[j] == RowKind::Normal || (con.kind[j] == RowKind::Limit && con.source[j] >= m.njnt);
    if !(0..con.len()).any(checked) && !m.limited_joints().any(|j| violation(m, qpos, j).is_some()) {
        return false;
    }
    for pass in 0..PASSES {
        // the check's kinematics stay in `ahead`, the next step's when they are the last
        if !gather(m, data, qpos, qvel) {
            return pass > 0;
        }
        solve(m, data, qpos);
    }
    true
}

/// Leapfrog's opening drift can carry a joint past its limit before any row acts (the rows see
/// the midpoint, where the limit is already crossed, and correct it over `CORRECTION_TIME`): a
/// violation the step created is removed from the positions, velocities kept, and one the step
/// began with is not deepened — each limited joint ends within [min(q_start, lo), max(q_start, hi)].
pub fn hold_limits(m: &Model, start: &StepStart, qpos: &mut [f64]) {
    if !m.opt.limit {
        return;
    }
    for j in m.limited_joints() {
        let a = m.jnt_qposadr[j];
        let [lo, hi] = m.jnt_range[j];
        let q0 = start.qpos[a];
        qpos[a] = qpos[a].clamp(q0.min(lo), q0.max(hi));
    }
}

/// Limit row sign and (negative) gap of joint j when it is past a limit by more than [`LIMIT_SLOP`].
fn violation(m: &Model, qpos: &[f64], j: usize) -> Option<(f64, f64)> {
    if !m.opt.limit {
        return None;
    }
    let q = qpos[m.jnt_qposadr[j]];
    let [lo, hi] = m.jnt_range[j];
    if q < lo - LIMIT_SLOP {
        Some((1.0, q - lo))
    } else if q > hi + LIMIT_SLOP {
        Some((-1.0, hi - q))
    } else {
        None
    }
}

/// Checks the configuration `qpos`: false when no contact penetrates beyond [`SLOP`] and no joint
/// is past a limit beyond [`LIMIT_SLOP`], else true with the projection rows filled.
fn gather(m: &Model, data: &mut World<'_>, qpos: &[f64], qvel: &[f64]) -> bool {
    let (kin, aba, coll) = (&data.dynamics.kin, &data.dynamics.aba, &*data.coll);
    let ahead = &mut data.dynamics.ahead;
    let Constraints { con, post, .. } = &mut *data.constraints;
    let nv = m.nv;
    let new = ahead.at(m, qpos, qvel);
    collision::penetrations(m, new, &mut post.coll);
    // the tendons' lengths serve their limits alone (a hand's spatial tendons wrap at a cost)
    if m.limited_tendons().next().is_some() {
        tendon::evaluate(m, new, qpos, &mut post.ten);
    }
    let tendon_violated = m.limited_tendons().any(|t| {
        let ([lo, hi], l) = (m.tendon_range[t], post.ten.length[t]);
        l < lo - LIMIT_SLOP || l > hi + LIMIT_SLOP
    });
    // every row's gap below is a fresh detection's or at least zero
    if post.coll.contacts.iter().all(|c| c.dist >= -SLOP) && !m.limited_joints().any(|j| violation(m, qpos, j).is_some()) && !tendon_violated {
        return false;
    }
    // the rows' Δq̈ (a solve computes only those of the rows it kept)
    responses(m, kin, aba, con, |_, kind| matches!(kind, RowKind::Normal | RowKind::Limit));
    post.gap.clear();
    post.jac.clear();
    post.dqdd.clear();
    post.limit.clear();
    post.tree.clear();
    post.row.clear();
    // the step's contact rows, their points carried by each side's node:
    // d' = d + n'·(p₁' − p₂'), n' turned with side 2 (a first-order estimate)
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Normal) {
        let moved = |side: usize| {
            let n = con.node[j][side];
            if n == WORLD {
                (DVec3::ZERO, con.dir[j])
            } else {
                let old = kin.node_rot[n] * con.point[j][side] + kin.node_pos[n];
                let now = new.node_rot[n] * con.point[j][side] + new.node_pos[n];
                (now - old, new.node_rot[n] * (kin.node_rot[n].transpose() * con.dir[j]))
            }
        };
        let ((d1, _), (d2, n2)) = (moved(0), moved(1));
        // the surfaces' closest points move over them as the bodies turn (a capsule's end rolls),
        // so a fresh detection of the same feature, where there is one, is the better gap
        let o = &coll.contacts[con.source[j]];
        let key = (o.geom1, o.geom2, o.feature);
        let gap = match post.coll.contacts.iter().find(|c| (c.geom1, c.geom2, c.feature) == key) {
            Some(c) => c.dist,
            None => (con.dist[j] + n2.dot(d1 - d2)).max(0.0),
        };
        post.gap.push(gap.max(-DEPENETRATION_SPEED * m.opt.timestep));
        push_jacobian(m, kin, con.node[j], con.jac[j], &mut post.jac);
        post.dqdd.extend_from_slice(&con.dqdd[j * nv..(j + 1) * nv]);
        post.limit.push(None);
        post.tree.push(con.tree[j]);
        post.row.push(j);
    }
    // contacts penetrating now that had no row: a test force each
    for i in 0..post.coll.contacts.len() {
        let c = post.coll.contacts[i];
        let known = (0..con.len()).any(|j| {
            con.kind[j] == RowKind::Normal && {
                let o = &coll.contacts[con.source[j]];
                (o.geom1, o.geom2, o.feature) == (c.geom1, c.geom2, c.feature)
            }
        });
        if c.dist < -SLOP && !known {
            push_contact_row(m, kin, aba, new, post, &c);
        }
    }
    // the step's limit rows take part so the projection cannot push a joint past its limit, and
    // brings back one the step carried past it
    for j in (0..con.len()).filter(|&j| con.kind[j] == RowKind::Limit) {
        let (source, sign) = (con.source[j], con.dof[j].1);
        // a joint's position or a tendon's length (source njnt + the tendon) after the step
        let (x, [lo, hi]) = match source.checked_sub(m.njnt) {
            None => (qpos[m.jnt_qposadr[source]], m.jnt_range[source]),
            Some(t) => (post.ten.length[t], m.tendon_range[t]),
        };
        let gap = if sign > 0.0 { x - lo } else { hi - x };
        post.gap.push(if gap < -LIMIT_SLOP { gap } else { gap.max(0.0) });
        let start = post.jac.len();
        post.jac.resize(start + nv, 0.0);
        for &(dof, c) in con.joint_terms(j) {
            post.jac[start + dof] += c;
        }
        post.dqdd.extend_from_slice(&con.dqdd[j * nv..(j + 1) * nv]);
        post.limit.push(Some((source, sign)));
        post.tree.push(con.tree[j]);
        post.row.push(j);
    }
    // limits the step crossed without a row: a unit test torque each
    for joint in m.limited_joints() {
        if let Some((sign, gap)) = violation(m, qpos, joint).filter(|&(sign, _)| !post.limit.contains(&Some((joint, sign)))) {
            push_limit_row(m, kin, aba, post, joint, sign, gap);
        }
    }
    true
}

/// Contact `c`'s normal velocity per unit of each dof's velocity (nv) in the configuration of
/// `kin`, where it was found.
pub fn contact_normal_rate(m: &Model, kin: &KinData, c: &Contact) -> Vec<f64> {
    let nodes = [m.body_node[m.geom_body[c.geom1]], m.body_node[m.geom_body[c.geom2]]];
    let at = |side: usize| {
        let n = nodes[side];
        if n == WORLD { c.pos - kin.origin } else { kin.rel(n, kin.node_rot[n].transpose() * (c.pos - kin.node_pos[n])) }
    };
    let mut out = Vec::with_capacity(m.nv);
    push_jacobian(m, kin, nodes, constraint::jacobian(nodes, [at(0), at(1)], [c.normal; 2]), &mut out);
    out
}

/// Appends the projection row of contact `c`, found penetrating after the step without a row of
/// the step (`new`: the kinematics there), its Δq̈ by a test force through the step's start.
fn push_contact_row(m: &Model, kin: &KinData, aba: &AbaData, new: &KinData, post: &mut StabilizeData, c: &Contact) {
    let nv = m.nv;
    // the contact's point and normal carried back with each side's node to the step's start,
    // whose kinematics and ABA quantities the projection uses
    let nodes = [m.body_node[m.geom_body[c.geom1]], m.body_node[m.geom_body[c.geom2]]];
    let back = |side: usize| {
        let n = nodes[side];
        if n == WORLD {
            return (c.pos - kin.origin, c.normal);
        }
        let turn = kin.node_rot[n] * new.node_rot[n].transpose();
        (kin.rel(n, new.node_rot[n].transpose() * (c.pos - new.node_pos[n])), turn * c.normal)
    };
    let ((r1, n1), (r2, n2)) = (back(0), back(1));
    let jac = constraint::jacobian(nodes, [r1, r2], [n1, n2]);
    post.gap.push(c.dist.max(-DEPENETRATION_SPEED * m.opt.timestep));
    push_jacobian(m, kin, nodes, jac, &mut post.jac);
    let trees = nodes.map(|n| if n == WORLD { WORLD } else { m.node_tree[n] });
    post.delta.clear(m, trees);
    for side in 0..2 {
        if nodes[side] != WORLD {
            post.delta.sub_force(nodes[side], 0, &jac[side]);
        }
    }
    let start = post.dqdd.len();
    post.dqdd.resize(start + nv, 0.0);
    delta_pass(m, kin, aba, trees, [&[]; LANES], &mut post.delta, &mut post.dqdd, lane_zero(start));
    post.limit.push(None);
    post.tree.push(trees);
    post.row.push(usize::MAX);
}

/// Appends the projection row of joint `joint`'s limit (row sign `sign`, gap `gap`), its Δq̈ by a
/// unit test torque through the step's ABA quantities.
fn push_limit_row(m: &Model, kin: &KinData, aba: &AbaData, post: &mut StabilizeData, joint: usize, sign: f64, gap: f64) {
    let (nv, dof) = (m.nv, m.jnt_dofadr[joint]);
    post.gap.push(gap);
    let start = post.jac.len();
    post.jac.resize(start + nv, 0.0);
    post.jac[start + dof] = sign;
    post.dqdd.resize(start + nv, 0.0);
    let tree = m.node_tree[m.jnt_node[joint]];
    post.delta.clear(m, [tree, WORLD]);
    let mut dtau: [&[(usize, f64)]; LANES] = [&[]; LANES];
    let torque = [(dof, sign)];
    dtau[0] = &torque;
    delta_pass(m, kin, aba, [tree, WORLD], dtau, &mut post.delta, &mut post.dqdd, lane_zero(start));
    post.limit.push(Some((joint, sign)));
    post.tree.push([tree, WORLD]);
    post.row.push(usize::MAX);
}

/// A delta pass's Δq̈ destinations with lane 0's at `start` and no other lane used.
fn lane_zero(start: usize) -> [Option<usize>; LANES] {
    let mut at = [None; LANES];
    at[0] = Some(start);
    at
}

/// Appends the row's J (nv) for node forces `jac`: τ = Jᵀ f, carried to the root as RNEA's
/// inward force pass (Featherstone 2008, Table 5.1).
fn push_jacobian(m: &Model, kin: &KinData, nodes: [usize; 2], jac: [Force; 2], out: &mut Vec<f64>) {
    let start = out.len();
    out.resize(start + m.nv, 0.0);
    for side in 0..2 {
        kinematics::add_joint_forces(m, kin, nodes[side], &jac[side], &mut out[start..]);
    }
}

/// One projection δq = Σ p_k Δq̈⁽ᵏ⁾ from the LCP on the rows in `post`. A limit without a row that
/// δq would cross gets one (Δq̈ by a unit test torque) and the LCP is solved again; if one is still
/// crossed after that, the step is shortened to stop at it.
fn solve(m: &Model, data: &mut World<'_>, qpos: &mut [f64]) {
    let (kin, aba) = (&data.dynamics.kin, &data.dynamics.aba);
    let Constraints { con, post, stats, projections, .. } = &mut *data.constraints;
    *projections += 1;
    let nv = m.nv;
    for attempt in 0..=LIMIT_PASSES {
        let k = post.gap.len();
        // K_ab = J_a · Δq̈_b over the dofs of the trees both rows move (J_a is zero off a's
        // trees, Δq̈_b off b's): one character's of many in a scene, zero between separate trees;
        // between two of the step's rows, the step's own measure (its test forces were pushed
        // through the same ABA quantities). K = J M⁻¹ Jᵀ is symmetric: the upper triangle is
        // computed, the lower copied
        post.m.clear();
        post.m.resize(k * k, 0.0);
        for a in 0..k {
            let [ta, tb] = post.tree[a];
            for b in a..k {
                let shared = |t: usize| t != WORLD && post.tree[b].contains(&t);
                let trees = [if shared(ta) { ta } else { WORLD }, if shared(tb) { tb } else { WORLD }];
                if trees == [WORLD; 2] {
                    continue;
                }
                let (ja, jb) = (post.row[a], post.row[b]);
                let mut dot = 0.0;
                if ja != usize::MAX && jb != usize::MAX {
                    dot = con.k[con.k_index(jb, ja)];
                } else {
                    for r in tree_dofs(m, trees) {
                        dot += post.jac[a * nv + r.start..a * nv + r.end].iter().zip(&post.dqdd[b * nv + r.start..b * nv + r.end]).map(|(x, y)| x * y).sum::<f64>();
                    }
                }
                (post.m[a * k + b], post.m[b * k + a]) = (dot, dot);
            }
        }
        // an inert row (K_aa at round-off of the largest: the dofs cannot move its contact along
        // its normal, as where a link's mesh overlaps its base's around the hinge axis) gets no
        // push, which 1/K_aa would make unbounded
        let k_max = (0..k).map(|a| post.m[a * k + a]).fold(0.0, f64::max);
        for a in 0..k {
            if post.m[a * k + a] <= INERT_ROW * k_max {
                for b in 0..k {
                    (post.m[a * k + b], post.m[b * k + a]) = (0.0, 0.0);
                }
                post.m[a * k + a] = 1.0;
                post.gap[a] = post.gap[a].max(0.0);
            }
        }
        post.role.clear();
        for a in 0..k {
            let d = post.m[a * k + a];
            post.m[a * k + a] += lcp::REGULARISATION * d.abs().max(1e-300);
            post.role.push(Role::Normal);
        }
        post.p.clear();
        post.p.resize(k, 0.0);
        // nothing is left out, so one solve; were rows brought back, M is complete and the solve
        // is simply repeated
        post.left_out.clear();
        while !lcp::solve(lcp::Problem { n: k, m: &post.m, q: &post.gap, role: &post.role }, true, None, &mut post.left_out, &mut post.p, &mut post.work, stats) {}
        post.dq.fill(0.0);
        for a in 0..k {
            let p = post.p[a];
            if p != 0.0 {
                add_response(m, post.tree[a], p, &post.dqdd[a * nv..(a + 1) * nv], &mut post.dq);
            }
        }
        if attempt == LIMIT_PASSES {
            break;
        }
        let mut added = false;
        for j in m.limited_joints() {
            if let Some((sign, room, _)) = crossing(m, qpos, &post.dq, &post.limit, j) {
                push_limit_row(m, kin, aba, post, j, sign, room);
                added = true;
            }
        }
        if !added {
            break;
        }
    }
    let mut alpha = 1.0f64;
    for j in m.limited_joints() {
        if let Some((_, room, step)) = crossing(m, qpos, &post.dq, &post.limit, j) {
            alpha = alpha.min(room / step);
        }
    }
    integrate_pos(m, qpos, &post.dq, alpha);
}

/// Whether the projection `dq` carries joint j past a limit that has no row among `rows`: that
/// limit's row sign, the room left before it (not below zero) and the joint's step |dq|.
fn crossing(m: &Model, qpos: &[f64], dq: &[f64], rows: &[Option<(usize, f64)>], j: usize) -> Option<(f64, f64, f64)> {
    let (q, dq) = (qpos[m.jnt_qposadr[j]], dq[m.jnt_dofadr[j]]);
    let [lo, hi] = m.jnt_range[j];
    let (sign, room) = if dq < 0.0 { (1.0, q - lo) } else { (-1.0, hi - q) };
    (dq.abs() > room.max(0.0) && !rows.contains(&Some((j, sign)))).then_some((sign, room.max(0.0), dq.abs()))
}

/// Times a projection may add limit rows and solve again.
const LIMIT_PASSES: usize = 2;

