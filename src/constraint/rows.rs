//! Stage 4 — the step's constraint rows: contacts with their friction tangents (the seed's
//! static tangent kept per contact, else one drawn from the world's random stream), reachable
//! limits and motion control; and the limits and contacts a constrained motion reaches without a
//! row, added for a second solve.

use glam::{DQuat, DVec3};

use super::system::{arc_lift, jacobian, node_of_geom, ConstraintData, NewRow, RowKind, SLIDING_SPEED};
use super::test_forces::{measure, PointAccel};
use super::{Constraints, History, World};
use crate::collision::{self, Contact};
use crate::dynamics::aba::AbaData;
use crate::dynamics::tendon::TendonData;
use crate::dynamics::DynamicsData;
use crate::dynamics::kinematics::{self, point_accel, point_vel, velocity_products, KinData};
use crate::math::{Force, Motion};
use crate::state::WorldState;
use crate::model::{Actuation, Connect, FrictionModel, GeomType, Model, Wrap, WORLD};

/// What building a step's rows needs besides them (`constraint::rows`).
#[derive(Clone, Debug, Default)]
pub struct RowScratch {
    /// Limits whose rows this step must include (2 per joint, then 2 per tendon: lower, upper).
    pub limit_forced: Vec<bool>,
    /// Limits that have a row this step (as `limit_forced`), marked by [`missed_limits`] when it
    /// needs them.
    limit_row: Vec<bool>,
    /// Friction tangents being recorded this step.
    pub tangents_next: Vec<((usize, usize, usize), DVec3)>,
    /// The step's end velocities q̇ + h q̈ (nv) and the nodes' spatial velocities of them (nnode),
    /// for the second contact check.
    vel_end: Vec<f64>,
    v_end: Vec<Motion>,
    /// The nodes' spatial velocities at a leapfrog step's midpoint from the velocities its
    /// opening drift moved with (nnode).
    v_start: Vec<Motion>,
}

impl RowScratch {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        RowScratch {
            limit_forced: vec![false; 2 * (m.njnt + m.ntendon)],
            limit_row: vec![false; 2 * (m.njnt + m.ntendon)],
            tangents_next: vec![],
            vel_end: vec![0.0; m.nv],
            v_end: vec![Motion::ZERO; m.nnode],
            v_start: vec![Motion::ZERO; m.nnode],
        }
    }
}

/// Appends to the contacts those the step's final velocities q̇ + h q̈ can reach but the first
/// detection's margin did not cover.
pub fn missed_contacts(m: &Model, data: &mut World<'_>, s: &WorldState<'_>) -> bool {
    if !m.opt.contact || m.collision_pairs.is_empty() {
        return false;
    }
    let h = m.opt.timestep;
    let (kin, qacc, coll, rows) = (&data.dynamics.kin, &data.dynamics.qacc, &mut *data.coll, &mut data.constraints.rows);
    for ((e, v), a) in rows.vel_end.iter_mut().zip(s.qvel.iter()).zip(qacc.iter()) {
        *e = v + h * a;
    }
    collision::reach_again(m, kin, &rows.vel_end, &mut rows.v_end, coll)
}

/// Marks in `data.constraints.rows.limit_forced` each limit without a row that q̇ + h q̈ would cross within the step.
pub fn missed_limits(m: &Model, data: &mut World<'_>, s: &WorldState<'_>) -> bool {
    let (qpos, qvel) = (&*s.qpos, &*s.qvel);
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let dy = &*data.dynamics;
    let Constraints { con, rows, .. } = &mut *data.constraints;
    let mut any = false;
    // the limits with rows, marked at the first crossing found (one pass over the rows)
    let mut marked = false;
    let mut without_row = |source: usize, side: usize| {
        if !marked {
            rows.limit_row.fill(false);
            for r in (0..con.len()).filter(|&r| con.kind[r] == RowKind::Limit) {
                rows.limit_row[2 * con.source[r] + (con.dof[r].1 < 0.0) as usize] = true;
            }
            marked = true;
        }
        let missed = !rows.limit_row[2 * source + side];
        rows.limit_forced[2 * source + side] |= missed;
        missed
    };
    for j in m.limited_joints() {
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        let [lo, hi] = m.jnt_range[j];
        let v_end = qvel[da] + h * dy.qacc[da];
        for (side, (dist, sign)) in [(qpos[qa] - lo, 1.0), (hi - qpos[qa], -1.0)].into_iter().enumerate() {
            if dist + lever * sign * v_end < 0.0 {
                any |= without_row(j, side);
            }
        }
    }
    for t in m.limited_tendons() {
        let jac = dy.ten.jac(t, m.nv);
        let v_end: f64 = jac.iter().zip(qvel.iter().zip(&dy.qacc)).map(|(j, (v, a))| j * (v + h * a)).sum();
        let length = dy.ten.length[t];
        let [lo, hi] = m.tendon_range[t];
        for (side, (dist, sign)) in [(length - lo, 1.0), (hi - length, -1.0)].into_iter().enumerate() {
            if dist + lever * sign * v_end < 0.0 {
                any |= without_row(m.njnt + t, side);
            }
        }
    }
    any
}

/// Stage 4: the step's rows into `constraints.con`, with each contact's friction tangent chosen
/// (and recorded in the history for the next step).
pub fn build_rows(m: &Model, data: &mut World<'_>, s: &WorldState<'_>) {
    let (qpos, qvel, ctrl) = (&*s.qpos, &*s.qvel, s.ctrl);
    let (kin, aba, qacc, coll) = (&data.dynamics.kin, &data.dynamics.aba, &data.dynamics.qacc, &*data.coll);
    let Constraints { con, history, rows: RowScratch { tangents_next, limit_forced, .. }, feedforward, .. } = &mut *data.constraints;
    let History { tangents, rng, .. } = history;
    tangents_next.clear();
    let h = m.opt.timestep;
    con.clear();
    push_contact_rows(
        m,
        kin,
        aba,
        &coll.contacts,
        |ci, n, vt, at| {
            let c = &coll.contacts[ci];
            let key = (c.geom1, c.geom2, c.feature);
            // the slip the step would give the contact without constraint forces
            let slip = vt + h * at;
            // friction opposes that slip: sliding (Kokkevis 2004, §8.1) and a contact at rest that
            // the step would set slipping alike. Not the sliding velocity alone: near the slip
            // threshold it is tiny, and its direction at each of a body's contacts swings with
            // the body's spin, so friction along it turns the body to and fro, each step the other
            // way (a box on a slope just past its friction angle). A contact the step leaves at
            // rest keeps the last valid tangent of a persisting contact, or a random one when new,
            // as the seed does
            let t = if slip.length() > SLIDING_SPEED {
                -slip / slip.length()
            } else if let Some((_, t)) = tangents.iter().find(|(k, t)| *k == key && t.dot(n).abs() < 1e-6) {
                *t
            } else {
                random_tangent(rng, n)
            };
            tangents_next.push((key, t));
            t
        },
        con,
    );
    push_limit_rows(m, qpos, qvel, qacc, limit_forced, con);
    push_tendon_limit_rows(m, &data.dynamics.ten, qvel, qacc, limit_forced, con);
    push_equality_rows(m, qpos, qvel, con);
    push_connect_rows(m, kin, con);
    let known = data.dynamics.friction_known.then_some(&data.dynamics.qfrc_friction[..]);
    let held = data.dynamics.aba.locking.then_some(&data.dynamics.aba.locked[..]);
    push_friction_rows(m, &data.dynamics.ten, qvel, (known, held), con);
    push_motion_rows(m, qpos, qvel, ctrl, feedforward, con);
    std::mem::swap(tangents, tangents_next);
    // leapfrog's rows are built at the midpoint: each gap before the opening drift, from the
    // velocities the drift moved with (an impact since has changed q̇, not the drift)
    let lever = m.opt.lever();
    if lever < h {
        let Constraints { con, rows, start, .. } = &mut *data.constraints;
        kinematics::velocities(m, &data.dynamics.kin, &start.qvel, &mut rows.v_start);
        for j in (0..con.len()).filter(|&j| matches!(con.kind[j], RowKind::Normal | RowKind::Limit)) {
            let vel_start = row_velocity(con, j, &rows.v_start, &start.qvel);
            con.dist_start[j] = con.dist[j] - (h - lever) * vel_start;
        }
    }
}

/// A unit vector orthogonal to `n` at a random angle, from the world's own SplitMix64 stream.
pub fn random_tangent(state: &mut u64, n: DVec3) -> DVec3 {
    let z = crate::math::splitmix64(*state);
    *state = state.wrapping_add(crate::math::SPLITMIX_GAMMA);
    let angle = (z >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
    let (a, b) = n.any_orthonormal_pair();
    a * angle.cos() + b * angle.sin()
}

/// Builds the rows for `contacts`, limits active or reachable within the step (`qacc0`: the
/// constraint-free accelerations) or marked in `forced` (2 per joint: lower, upper) and, when the actuation is trajectory following,
/// motion control of every actuated joint toward `ctrl` (position targets) with feed-forward
/// velocity and acceleration `feedforward` (2 × nu). `tangent_for(i, n, v_t, a_t)` picks the
/// friction direction of contact i from its tangential velocity and constraint-free tangential
/// acceleration (the caller handles sliding, persistence and the seeded random choice).
pub fn push_contact_rows(m: &Model, kin: &KinData, aba: &AbaData, contacts: &[Contact], mut tangent_for: impl FnMut(usize, DVec3, DVec3, DVec3) -> DVec3, out: &mut ConstraintData) {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    if !contacts.is_empty() {
        velocity_products(m, kin, &mut out.a_vp);
    }
    // the run of contacts of one geom pair (contacts of a pair come together) and its first
    // contact's normal row and sliding tangent
    let mut run = (0, 0, None);
    for (ci, c) in contacts.iter().enumerate() {
        let nodes = [node_of_geom(m, c.geom1), node_of_geom(m, c.geom2)];
        let local = |n: usize| if n == WORLD { c.pos } else { kin.node_rot[n].transpose() * (c.pos - kin.node_pos[n]) };
        let pts = [local(nodes[0]), local(nodes[1])];
        // the contact point relative to the origin: the same world point on both sides
        let r = c.pos - kin.origin;
        let vrel = point_vel(kin, nodes[0], r) - point_vel(kin, nodes[1], r);
        let g = m.opt.gravity;
        let arel = point_accel(kin, &aba.a, g, nodes[0], r) - point_accel(kin, &aba.a, g, nodes[1], r);
        let normal_row = out.len();
        out.push(m, NewRow::contact(RowKind::Normal, nodes, pts, c.normal, c.friction.mu, ci));
        out.vel[normal_row] = c.normal.dot(vrel);
        out.jac[normal_row] = jacobian(nodes, [r; 2], [c.normal; 2]);
        out.arm[normal_row] = r;
        out.dist[normal_row] = c.dist;
        out.dist_start[normal_row] = c.dist;
        // a sphere's or capsule's surface is a radius from its centre along the normal (+n points
        // into geom1; `pos` lies midway between the surfaces)
        let centre = |g: usize, sign: f64, n: usize, p: DVec3| match m.geom_type[g] {
            GeomType::Sphere | GeomType::Capsule if n != WORLD => {
                p + kin.node_rot[n].transpose() * c.normal * (sign * (m.geom_size[g][0] + 0.5 * c.dist))
            }
            _ => p,
        };
        out.centre[normal_row] = [centre(c.geom1, 1.0, nodes[0], pts[0]), centre(c.geom2, -1.0, nodes[1], pts[1])];
        out.lift[normal_row] = arc_lift(kin, out, normal_row, h, lever);
        let fr = c.friction;
        // in a planar model a normal in the plane leaves one tangent line that motion can use
        let line = m.motion_plane.filter(|p| p.dot(c.normal).abs() < 1e-9).map(|p| p.cross(c.normal).normalize());
        let mut tangent = None;
        if fr.sliding() && fr.mu > 0.0 {
            let vt = vrel - c.normal * c.normal.dot(vrel);
            let at = arel - c.normal * c.normal.dot(arel);
            let t = tangent_for(ci, c.normal, vt, at);
            // the tangent is turned onto a planar model's line, and the pyramid's rows across
            // the plane, which no force could move, are not built
            let t = match line {
                Some(e) if t.dot(e) < 0.0 => -e,
                Some(e) => e,
                None => t,
            };
            let dirs = match (m.opt.friction, line) {
                (FrictionModel::OneTangent, _) => [t, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO],
                (FrictionModel::Pyramid, Some(_)) => [t, -t, DVec3::ZERO, DVec3::ZERO],
                (FrictionModel::Pyramid, None) => {
                    let t2 = c.normal.cross(t);
                    [t, -t, t2, -t2]
                }
            };
            for (k, d) in dirs.into_iter().enumerate().filter(|(_, d)| *d != DVec3::ZERO) {
                let row = out.len();
                out.push(m, NewRow::contact(RowKind::Tangent { normal: normal_row }, nodes, pts, d, fr.mu, ci));
                out.vel[row] = d.dot(vrel);
                out.jac[row] = jacobian(nodes, [r; 2], [d; 2]);
                out.arm[row] = r;
                if k % 2 == 1 {
                    out.mirror[row] = row - 1;
                }
            }
            tangent = Some(t);
        }
        let pair = |c: &Contact| (c.geom1, c.geom2);
        if ci == 0 || pair(&contacts[ci - 1]) != pair(c) {
            run = (ci, normal_row, tangent);
        }
        if contacts.get(ci + 1).is_none_or(|next| pair(next) != pair(c)) {
            push_turning_rows(m, kin, contacts, run, out);
        }
    }
}

/// The torsional and rolling friction rows of a run of contacts of one geom pair (`run`: its
/// first contact, that contact's normal row and sliding tangent): the couples are the same at
/// every contact of the pair, so they are built once, after the run's last contact, bounded by μ
/// times the run's normal forces together (`constraint::solve`). Torsional friction about the
/// first normal (none in a planar model whose normal lies in the plane: that turn leaves the
/// plane); rolling friction about the tangents, the first along the relative rolling (so that
/// the pyramid's full μ opposes it), else the sliding tangent (a planar model's: about the
/// plane's normal alone).
fn push_turning_rows(m: &Model, kin: &KinData, contacts: &[Contact], (ci, normal_row, tangent): (usize, usize, Option<DVec3>), out: &mut ConstraintData) {
    let c = &contacts[ci];
    let fr = c.friction;
    if !fr.sliding() || (fr.spin <= 0.0 && fr.roll <= 0.0) {
        return;
    }
    let nodes = [out.node[normal_row][0], out.node[normal_row][1]];
    let pts = out.point[normal_row];
    let line = m.motion_plane.filter(|p| p.dot(c.normal).abs() < 1e-9);
    let omega = |n: usize| if n == WORLD { DVec3::ZERO } else { kin.v[n].ang };
    let wrel = omega(nodes[0]) - omega(nodes[1]);
    if fr.spin > 0.0 && line.is_none() {
        push_spin_rows(m, (nodes, pts, ci, normal_row), &[c.normal], fr.spin, wrel, out);
    }
    if fr.roll > 0.0 {
        let rolling = wrel - c.normal * c.normal.dot(wrel);
        let a = match (line, tangent) {
            (Some(p), _) => p,
            _ if rolling.length() > SLIDING_SPEED => rolling / rolling.length(),
            (None, Some(t)) => t,
            (None, None) => c.normal.any_orthonormal_vector(),
        };
        let axes = [a, c.normal.cross(a)];
        push_spin_rows(m, (nodes, pts, ci, normal_row), &axes[..if line.is_some() { 1 } else { 2 }], fr.roll, wrel, out);
    }
}

/// One group of torsional or rolling friction rows of contact `ci` (normal row `normal_row`,
/// between `pts` on `nodes`): a ± pair of couples about each of `axes`, bounded together by
/// `mu` f_n through the λ of the group's first row; `wrel` the sides' relative angular velocity.
fn push_spin_rows(m: &Model, (nodes, pts, ci, normal_row): ([usize; 2], [DVec3; 2], usize, usize), axes: &[DVec3], mu: f64, wrel: DVec3, out: &mut ConstraintData) {
    let cone = out.len();
    for &axis in axes {
        for d in [axis, -axis] {
            let row = out.len();
            out.push(m, NewRow::contact(RowKind::Spin { normal: normal_row, cone }, nodes, pts, d, mu, ci));
            let couple = |side: usize, s: f64| if nodes[side] == WORLD { Force::ZERO } else { Force { ang: d * s, lin: DVec3::ZERO } };
            out.jac[row] = [couple(0, 1.0), couple(1, -1.0)];
            out.vel[row] = d.dot(wrel);
            if d != axis {
                out.mirror[row] = row - 1;
            }
        }
    }
}

/// The limit rows of (qpos, qvel): each limit the joint is at or can reach within the step
/// (with the constraint-free `qacc0`), and each `forced` one (2 per joint: lower, upper).
pub fn push_limit_rows(m: &Model, qpos: &[f64], qvel: &[f64], qacc0: &[f64], forced: &[bool], out: &mut ConstraintData) {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    if m.opt.limit {
        for j in m.limited_joints() {
            let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
            let [lo, hi] = m.jnt_range[j];
            for (side, (dist, sign)) in [(qpos[qa] - lo, 1.0), (hi - qpos[qa], -1.0)].into_iter().enumerate() {
                let v = sign * qvel[da];
                // active when at the limit or able to reach it within this step (which moves the
                // joint by lever × (v + h q̈₀), q̈₀ constraint-free), or when `forced`
                let v_end = v + h * sign * qacc0[da];
                if dist + lever * v.min(v_end).min(0.0) <= m.jnt_margin[j] || forced[2 * j + side] {
                    let r = out.len();
                    out.push(m, NewRow::joint(RowKind::Limit, (da, sign), j));
                    out.vel[r] = v;
                    out.dist[r] = dist;
                    out.dist_start[r] = dist;
                }
            }
        }
    }
}

/// The active equalities' rows: a ± pair each, J = ∂x₁/∂q − poly′(x₂ − x₂⁰) ∂x₂/∂q over the
/// terms' dofs, `dist` the error x₁ − x₁⁰ − poly(x₂ − x₂⁰) (negated on the − row), `lift` the
/// error's second-order change over the step's drift ([`second_order_lift`]): x₁ and x₂ move
/// linearly in q, so the error's second derivative along q̇ is −poly″ ẋ₂².
pub fn push_equality_rows(m: &Model, qpos: &[f64], qvel: &[f64], out: &mut ConstraintData) {
    for e in (0..m.neq).filter(|&e| m.eq_active[e]) {
        let (error, slope, curvature) = equality_error(m, e, qpos);
        for sign in [1.0, -1.0] {
            let r = out.len();
            let first = m.eq_side(e, 0).first().map_or(0, |w| w.dof);
            out.push(m, NewRow::joint(RowKind::Equality, (first, sign), e));
            for w in m.eq_side(e, 0) {
                out.add_term(m, w.dof, sign * w.coef);
            }
            for w in m.eq_side(e, 1).iter().filter(|_| slope != 0.0) {
                out.add_term(m, w.dof, -sign * slope * w.coef);
            }
            out.dist[r] = sign * error;
            out.dist_start[r] = out.dist[r];
            out.lift[r] = equality_lift(m, out, r, curvature, qvel);
            let vel = row_velocity(out, r, &[], qvel);
            out.vel[r] = vel;
            if sign < 0.0 {
                out.mirror[r] = r - 1;
            }
        }
    }
}

/// The end-of-step target's term for a bilateral row whose error has second derivative `accel`
/// along the step's velocities: q ← q ⊕ lever q̇⁺ moves the error by lever J q̇⁺ + ½ lever² accel,
/// while the row's b already counts `accel` over `counted` (h for point and weld rows, whose b
/// holds J̇ q̇; 0 for joint-space rows), so the target −dist / lever gains (counted − ½ lever)
/// accel and the error left is of third order in lever q̇, not of second (`arc_lift` is the
/// contacts' like).
pub fn second_order_lift(accel: f64, counted: f64, lever: f64) -> f64 {
    (counted - 0.5 * lever) * accel
}

/// [`second_order_lift`] of connect row j, from its points' (for a weld's couples, its bodies')
/// velocity-product accelerations in `out.a_vp`, computed for `kin`.
fn connect_lift(m: &Model, kin: &KinData, out: &ConstraintData, j: usize) -> f64 {
    let [n1, n2] = out.node[j];
    let accel = if out.kind[j] == (RowKind::Connect { angular: true }) {
        let alpha = |n: usize| if n == WORLD { DVec3::ZERO } else { out.a_vp[n].ang };
        alpha(n1) - alpha(n2)
    } else {
        point_accel(kin, &out.a_vp, DVec3::ZERO, n1, out.arm[j]) - point_accel(kin, &out.a_vp, DVec3::ZERO, n2, out.arm2[j])
    };
    second_order_lift(out.dir[j].dot(accel), m.opt.timestep, m.opt.lever())
}

/// [`second_order_lift`] of equality row j at `qvel`, `curvature` its poly″: the error's second
/// derivative along q̇ is −poly″ ẋ₂² (times the row's sign).
fn equality_lift(m: &Model, out: &ConstraintData, j: usize, curvature: f64, qvel: &[f64]) -> f64 {
    let rate2 = Wrap::rate(m.eq_side(out.source[j], 1), qvel);
    second_order_lift(-out.dof[j].1 * curvature * rate2 * rate2, 0.0, m.opt.lever())
}

/// Equality e's error x₁ − x₁⁰ − poly(x₂ − x₂⁰) at `qpos`, poly′(x₂ − x₂⁰) and poly″(x₂ − x₂⁰).
pub fn equality_error(m: &Model, e: usize, qpos: &[f64]) -> (f64, f64, f64) {
    let value = |side: usize| Wrap::length(m.eq_side(e, side), qpos) - m.eq_ref[e][side];
    let (x1, x2) = (value(0), value(1));
    let c = m.eq_polycoef[e];
    if m.eq_side(e, 1).is_empty() {
        return (x1 - c[0], 0.0, 0.0);
    }
    let poly = c[0] + x2 * (c[1] + x2 * (c[2] + x2 * (c[3] + x2 * c[4])));
    let slope = c[1] + x2 * (2.0 * c[2] + x2 * (3.0 * c[3] + x2 * 4.0 * c[4]));
    let curvature = 2.0 * c[2] + x2 * (6.0 * c[3] + x2 * 12.0 * c[4]);
    (x1 - poly, slope, curvature)
}

/// Connect c's errors in the kinematics `kin`: p₁ − p₂ (world), and for a weld the world rotation
/// vector taking R₂ R₂ᵀR₁(qpos0) to R₁; with each side's point relative to `kin.origin`.
pub fn connect_error(m: &Model, c: &Connect, kin: &KinData) -> ConnectError {
    let nodes = c.body.map(|b| m.body_node[b]);
    let pts = [0, 1].map(|s| {
        let (rot, pos) = m.body_offset[c.body[s]].pose();
        rot * c.anchor[s] + pos
    });
    let r = [kin.rel(nodes[0], pts[0]), kin.rel(nodes[1], pts[1])];
    let turn = c.rel.map(|rel| {
        let [q1, q2] = c.body.map(|b| DQuat::from_mat3(&kin.xmat[b]).normalize());
        kin.xmat[c.body[0]] * crate::math::quat_sub(q1, (q2 * rel).normalize())
    });
    ConnectError { nodes, pts, r, gap: r[0] - r[1], turn }
}

/// A connect's or weld's state in one configuration ([`connect_error`]).
pub struct ConnectError {
    /// Each side's node.
    pub nodes: [usize; 2],
    /// Each side's point in its node's frame (the world's: world coordinates).
    pub pts: [DVec3; 2],
    /// Each side's point relative to the kinematics' origin.
    pub r: [DVec3; 2],
    /// p₁ − p₂.
    pub gap: DVec3,
    /// A weld's rotation error (None for a connect).
    pub turn: Option<DVec3>,
}

/// The active connects' and welds' rows: a ± pair along each world axis d, J q̇ = d · (v₁(p₁) −
/// v₂(p₂)) with `dist` the error d · (p₁ − p₂); and for a weld three more pairs, J q̇ = d · (ω₁ − ω₂)
/// with `dist` d · θ, θ the world rotation vector taking R₂ R₂ᵀR₁(qpos0) to R₁ (negated on the −
/// rows). `lift` is the error's second-order change over the step's drift
/// ([`second_order_lift`]): d · (J̇ q̇ of p₁ − of p₂), the points' velocity-product accelerations,
/// and for a weld d · (α₁ − α₂), the bodies' (at θ = 0 the rotation vector's second derivative,
/// the cross terms of the two rotations cancelling).
pub fn push_connect_rows(m: &Model, kin: &KinData, out: &mut ConstraintData) {
    if m.connects.iter().any(|c| c.active) {
        velocity_products(m, kin, &mut out.a_vp);
    }
    for (c, con) in m.connects.iter().enumerate().filter(|(_, c)| c.active) {
        let ConnectError { nodes, pts, r: [r1, r2], gap, turn } = connect_error(m, con, kin);
        let vrel = point_vel(kin, nodes[0], r1) - point_vel(kin, nodes[1], r2);
        let omega = |n: usize| if n == WORLD { DVec3::ZERO } else { kin.v[n].ang };
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let rows = axes.iter().map(|&d| (false, d)).chain(turn.iter().flat_map(|_| axes.iter().map(|&d| (true, d))));
        for (k, (angular, d)) in rows.enumerate() {
            for sign in [1.0, -1.0] {
                let (r, dir) = (out.len(), d * sign);
                out.push(m, NewRow::contact(RowKind::Connect { angular }, nodes, pts, dir, 0.0, 6 * c + k));
                if angular {
                    let couple = |side: usize, s: f64| if nodes[side] == WORLD { Force::ZERO } else { Force { ang: dir * s, lin: DVec3::ZERO } };
                    out.jac[r] = [couple(0, 1.0), couple(1, -1.0)];
                    out.vel[r] = dir.dot(omega(nodes[0]) - omega(nodes[1]));
                    out.dist[r] = dir.dot(turn.unwrap_or(DVec3::ZERO));
                } else {
                    out.jac[r] = jacobian(nodes, [r1, r2], [dir; 2]);
                    out.arm[r] = r1;
                    out.arm2[r] = r2;
                    out.vel[r] = dir.dot(vrel);
                    out.dist[r] = dir.dot(gap);
                }
                out.lift[r] = connect_lift(m, kin, out, r);
                out.dist_start[r] = out.dist[r];
                if sign < 0.0 {
                    out.mirror[r] = r - 1;
                }
            }
        }
    }
}

/// Dry friction's rows: a ± pair on each dof and each tendon with friction loss, each force at
/// most that loss; none on a dof whose friction is `known` (nonzero: `dry_friction::predict`) or
/// whose joint is `held` still (per node: `AbaData::locked`).
pub fn push_friction_rows(m: &Model, ten: &TendonData, qvel: &[f64], (known, held): (Option<&[f64]>, Option<&[bool]>), out: &mut ConstraintData) {
    let rowless = |dof: usize| known.is_some_and(|f| f[dof] != 0.0) || held.is_some_and(|h| h[m.jnt_node[m.dof_jnt[dof]]]);
    for (dof, &loss) in m.dof_frictionloss.iter().enumerate().filter(|&(dof, loss)| *loss > 0.0 && !rowless(dof)) {
        for sign in [1.0, -1.0] {
            let r = out.len();
            out.push(m, NewRow::joint(RowKind::DryFriction, (dof, sign), dof));
            out.vel[r] = sign * qvel[dof];
            out.cap[r] = loss;
            if sign < 0.0 {
                out.mirror[r] = r - 1;
            }
        }
    }
    for (t, &loss) in m.tendon_frictionloss.iter().enumerate().filter(|(_, loss)| **loss > 0.0) {
        for sign in [1.0, -1.0] {
            let Some(r) = push_tendon_row(m, ten, RowKind::DryFriction, t, sign, m.nv + t, out) else { break };
            out.vel[r] = sign * ten.rate(m, t, qvel);
            out.cap[r] = loss;
            if sign < 0.0 {
                out.mirror[r] = r - 1;
            }
        }
    }
}

/// The limit rows of the limited tendons: each limit the tendon's length is at or can reach within
/// the step (with the constraint-free `qacc0`), and each `forced` one (2 per joint, then 2 per
/// tendon: lower, upper). The row's source is njnt + the tendon.
pub fn push_tendon_limit_rows(m: &Model, ten: &TendonData, qvel: &[f64], qacc0: &[f64], forced: &[bool], out: &mut ConstraintData) {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    for t in m.limited_tendons() {
        let [lo, hi] = m.tendon_range[t];
        let (length, rate) = (ten.length[t], ten.rate(m, t, qvel));
        let accel = ten.rate(m, t, qacc0) + ten.jdot_qdot[t];
        let source = m.njnt + t;
        for (side, (dist, sign)) in [(length - lo, 1.0), (hi - length, -1.0)].into_iter().enumerate() {
            let (v, v_end) = (sign * rate, sign * (rate + h * accel));
            if dist + lever * v.min(v_end).min(0.0) <= m.tendon_margin[t] || forced[2 * source + side] {
                let Some(r) = push_tendon_row(m, ten, RowKind::Limit, t, sign, source, out) else { break };
                out.vel[r] = v;
                out.dist[r] = dist;
                out.dist_start[r] = dist;
            }
        }
    }
}

/// Appends a row of kind `kind` on tendon t's length (J = `sign` J_t over the dofs it moves, J̇ q̇
/// likewise), or None when no dof moves it here.
fn push_tendon_row(m: &Model, ten: &TendonData, kind: RowKind, t: usize, sign: f64, source: usize, out: &mut ConstraintData) -> Option<usize> {
    let jac = ten.jac(t, m.nv);
    let first = jac.iter().position(|&c| c != 0.0)?;
    let r = out.len();
    out.push(m, NewRow::joint(kind, (first, sign), source));
    for (dof, &c) in jac.iter().enumerate().skip(first).filter(|(_, c)| **c != 0.0) {
        out.add_term(m, dof, sign * c);
    }
    out.jdot[r] = sign * ten.jdot_qdot[t];
    Some(r)
}

/// Motion control's rows: each actuated joint driven toward its position target `ctrl` with
/// feed-forward velocity and acceleration `feedforward` (2 × nu), under trajectory actuation.
pub fn push_motion_rows(m: &Model, qpos: &[f64], qvel: &[f64], ctrl: &[f64], feedforward: &[f64], out: &mut ConstraintData) {
    if let Actuation::Trajectory { kp, kd } = m.opt.actuation {
        // motion control drives joints (`Model` refuses it with tendon actuators)
        for (a, j) in (0..m.nu).filter_map(|a| m.actuator_joint(a).map(|j| (a, j))) {
            let da = m.jnt_dofadr[j];
            let ad = motion_target(m, a, (kp, kd), qpos, qvel, ctrl, feedforward);
            let limit = m.actuator_ctrllimited[a].then(|| m.actuator_gear[a].abs() * m.actuator_ctrlrange[a][0].abs().max(m.actuator_ctrlrange[a][1].abs()));
            for sign in [1.0, -1.0] {
                let r = out.len();
                out.push(m, NewRow::joint(RowKind::Motion { bounded: limit.is_some() }, (da, sign), a));
                out.vel[r] = sign * qvel[da];
                out.desired[r] = sign * ad;
                out.cap[r] = limit.unwrap_or(f64::INFINITY);
                if sign < 0.0 {
                    out.mirror[r] = r - 1;
                }
            }
        }
    }
}

/// J of the rows (rows × nv, row-major): each row's velocity per unit joint velocity, the row's
/// spatial forces `jac` read against the motion subspaces of the nodes from each side's node to
/// the root (a row's velocity is Σ_sides v_node · jac).
pub fn dense_jacobian(m: &Model, kin: &KinData, out: &ConstraintData) -> Vec<f64> {
    let nv = m.nv;
    let mut jm = vec![0.0; out.len() * nv];
    for j in 0..out.len() {
        let row = &mut jm[j * nv..(j + 1) * nv];
        if !out.kind[j].is_point() {
            for &(dof, c) in out.joint_terms(j) {
                row[dof] += c;
            }
            continue;
        }
        for side in 0..2 {
            let mut n = out.node[j][side];
            while n != WORLD {
                for r in 0..m.node_nv[n] {
                    row[m.node_dofadr[n] + r] += kin.s[n][r].dot(&out.jac[j][side]);
                }
                n = m.node_parent[n];
            }
        }
    }
    jm
}

/// Desired acceleration of actuator a's joint: q̈^d = q̈_ref + kd (q̇_ref − q̇) + kp (q_ref − q).
fn motion_target(m: &Model, a: usize, (kp, kd): (f64, f64), qpos: &[f64], qvel: &[f64], ctrl: &[f64], feedforward: &[f64]) -> f64 {
    // motion rows are built for joint actuators only
    let Some(j) = m.actuator_joint(a) else { return 0.0 };
    let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
    feedforward[m.nu + a] + kd * (feedforward[a] - qvel[da]) + kp * (ctrl[a] - qpos[qa])
}

/// Row j's velocity J_j q̇, from the nodes' spatial velocities `v` of that `qvel`.
pub fn row_velocity(out: &ConstraintData, j: usize, v: &[Motion], qvel: &[f64]) -> f64 {
    match out.kind[j] {
        RowKind::Normal | RowKind::Tangent { .. } | RowKind::Spin { .. } | RowKind::Connect { .. } => {
            let side = |s: usize| if out.node[j][s] == WORLD { 0.0 } else { v[out.node[j][s]].dot(&out.jac[j][s]) };
            side(0) + side(1)
        }
        RowKind::Limit | RowKind::Motion { .. } | RowKind::DryFriction | RowKind::Equality => out.joint_rate(j, qvel),
    }
}

/// After an impulse has changed the velocities but not the configuration: the rows' velocities,
/// motion-control targets and b at the new velocities, with the ABA of the new state. K and Δq̈
/// depend on the configuration only and are kept.
pub fn refresh(m: &Model, dy: &DynamicsData, s: &WorldState<'_>, feedforward: &[f64], out: &mut ConstraintData) {
    let (kin, aba, qacc0, qpos, qvel, ctrl) = (&dy.kin, &dy.aba, &dy.qacc, &*s.qpos, &*s.qvel, s.ctrl);
    if out.kind.iter().any(|k| matches!(k, RowKind::Normal | RowKind::Connect { .. })) {
        velocity_products(m, kin, &mut out.a_vp);
    }
    let mut point = PointAccel::NONE;
    for j in 0..out.len() {
        out.lift[j] = match out.kind[j] {
            RowKind::Normal => arc_lift(kin, out, j, m.opt.timestep, m.opt.lever()),
            RowKind::Connect { .. } => connect_lift(m, kin, out, j),
            RowKind::Equality => equality_lift(m, out, j, equality_error(m, out.source[j], qpos).2, qvel),
            _ => out.lift[j],
        };
        out.vel[j] = row_velocity(out, j, &kin.v, qvel);
        if let (RowKind::Motion { .. }, Actuation::Trajectory { kp, kd }) = (out.kind[j], m.opt.actuation) {
            out.desired[j] = out.dof[j].1 * motion_target(m, out.source[j], (kp, kd), qpos, qvel, ctrl, feedforward);
        }
        // a tendon row's J̇ q̇ at the new velocities
        let tendon = match out.kind[j] {
            RowKind::Limit => out.source[j].checked_sub(m.njnt),
            RowKind::DryFriction => out.source[j].checked_sub(m.nv),
            _ => None,
        };
        if let Some(t) = tendon {
            out.jdot[j] = out.dof[j].1 * dy.ten.jdot_qdot[t];
        }
        out.b[j] = measure(m, kin, aba, qacc0, out, j, &mut point);
    }
}

