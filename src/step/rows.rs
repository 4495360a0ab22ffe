//! Stage 4 — the step's constraint rows: contacts with their friction tangents (the seed's
//! static tangent kept per contact, else one drawn from the world's random stream), reachable
//! limits and motion control; and the limits and contacts a constrained motion reaches without a
//! row, added for a second solve.

use super::*;
use crate::data::RowScratch;

/// Appends to the contacts those the step's final velocities q̇ + h q̈ can reach but the first
/// detection's margin did not cover.
pub(super) fn missed_contacts(m: &Model, data: &mut Data, qvel: &[f64]) -> bool {
    if !m.opt.contact || m.collision_pairs.is_empty() {
        return false;
    }
    let h = m.opt.timestep;
    let Data { kin, coll, post, qacc, .. } = data;
    for ((e, v), a) in post.vel_end.iter_mut().zip(qvel).zip(qacc.iter()) {
        *e = v + h * a;
    }
    // post.kin is free until the post-stabilisation check, which recomputes it
    collision::reach_again(m, kin, &post.vel_end, &mut post.kin.v, coll)
}

/// Marks in `data.rows.limit_forced` each limit without a row that q̇ + h q̈ would cross within the step.
pub(super) fn missed_limits(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64]) -> bool {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let mut any = false;
    for j in m.limited_joints() {
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        let [lo, hi] = m.jnt_range[j];
        let v_end = qvel[da] + h * data.qacc[da];
        for (side, (dist, sign)) in [(qpos[qa] - lo, 1.0), (hi - qpos[qa], -1.0)].into_iter().enumerate() {
            let has_row = || (0..data.con.len()).any(|r| data.con.kind[r] == RowKind::Limit && data.con.source[r] == j && data.con.dof[r].1 == sign);
            if dist + lever * sign * v_end < 0.0 && !has_row() {
                data.rows.limit_forced[2 * j + side] = true;
                any = true;
            }
        }
    }
    any
}

pub(super) fn build_rows(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) {
    let Data { kin, aba, coll, con, history, rows: RowScratch { tangents_next, limit_forced }, feedforward, qacc, .. } = data;
    let crate::data::History { tangents, rng, .. } = history;
    tangents_next.clear();
    let h = m.opt.timestep;
    constraint::rows(
        m,
        kin,
        aba,
        qpos,
        qvel,
        qacc,
        limit_forced,
        ctrl,
        feedforward,
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
            let t = if slip.length() > constraint::SLIDING_SPEED {
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
    std::mem::swap(tangents, tangents_next);
    // leapfrog's rows are built at the midpoint: each gap before the opening drift, from the
    // velocities the drift moved with (an impact since has changed q̇, not the drift)
    let lever = m.opt.lever();
    if lever < h {
        let post = &mut data.post;
        kinematics::velocities(m, &data.kin, &post.qvel_start, &mut post.v_start);
        let con = &mut data.con;
        for j in (0..con.len()).filter(|&j| matches!(con.kind[j], RowKind::Normal | RowKind::Limit)) {
            let vel_start = constraint::row_velocity(con, j, &post.v_start, &post.qvel_start);
            con.dist_start[j] = con.dist[j] - (h - lever) * vel_start;
        }
    }
}

/// A unit vector orthogonal to `n` at a random angle, from the world's own SplitMix64 stream.
pub(super) fn random_tangent(state: &mut u64, n: DVec3) -> DVec3 {
    let z = crate::math::splitmix64(*state);
    *state = state.wrapping_add(crate::math::SPLITMIX_GAMMA);
    let angle = (z >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
    let (a, b) = n.any_orthonormal_pair();
    a * angle.cos() + b * angle.sin()
}
