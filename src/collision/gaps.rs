//! The pairs' gaps: lower bounds on a pair's distance kept from detection to detection, lowered
//! by how far the joints moved, which spare pairs their tests while every plane group is apart.

use glam::DVec3;

use super::broadphase::{apart, own_reach_of, test_margin};
use super::data::{has_own_reach, pose, posed, reach, CollisionData};
use super::narrowphase::pair;
use super::pair_narrowed;
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::math::quat_wxyz;
use crate::model::{GeomPair, JointType, Model, PairTest};

/// Each gap pair: its gap lowered by the joints' travel since `qpos_gap` (only the joints below
/// the common ancestor change the pair's distance), the pair tested where the gap does not exceed
/// its margin plus `spare`, and the gaps made those of `qpos`.
pub(super) fn lower_and_test_gaps(m: &Model, kin: &KinData, aba: &AbaData, qpos: &[f64], out: &mut CollisionData, spare: f64) {
    let (mut skips, mut least, mut unknown) = (0, f64::INFINITY, false);
    for (i, gp) in m.gap_pairs.iter().enumerate() {
        let t = &out.body_travel;
        let gap = out.pair_gap[i] - (t[gp.bodies[0]] + t[gp.bodies[1]] - 2.0 * t[gp.ancestor]);
        let gap = if gap > gp.margin + spare {
            skips += 1;
            gap
        } else {
            test_lazily(m, kin, aba, out, gp.pair, gp.margin + spare)
        };
        out.pair_gap[i] = gap;
        least = least.min(gap - gp.margin);
        unknown |= gap.is_nan();
    }
    out.gap_skips = skips;
    out.least_slack = if unknown { f64::NEG_INFINITY } else { least };
    out.shrink = 0.0;
    out.qpos_gap.copy_from_slice(qpos);
}

/// How far the configuration moved since the gaps' (`qpos_gap`), as
/// [`CollisionData::body_travel`]: each joint moves a point of its subtree by at most its arm
/// times its change (the rotation angle for a ball or free joint, plus a free joint's
/// translation), a bound along the straight path between the configurations, so that any change
/// counts, a reset's included. Returns a bound on how much that took off any gap.
pub(super) fn travel(m: &Model, qpos: &[f64], out: &mut CollisionData) -> f64 {
    let (mut j, mut most, mut unbounded) = (0, 0.0_f64, false);
    for b in 1..m.nbody {
        let parent = m.body_parent[b];
        let mut t = out.body_travel[parent];
        // joints come in body order
        while j < m.njnt && m.jnt_body[j] == b {
            let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
            let last = &out.qpos_gap;
            let angle = |k: usize| {
                let r = quat_wxyz(&last[k..k + 4]).conjugate() * quat_wxyz(&qpos[k..k + 4]);
                2.0 * r.xyz().length().atan2(r.w.abs())
            };
            t += match m.jnt_type[j] {
                JointType::Hinge | JointType::Slide => m.dof_arm[da] * (qpos[qa] - last[qa]).abs(),
                JointType::Ball => m.dof_arm[da] * angle(qa),
                JointType::Free => {
                    let moved = DVec3::new(qpos[qa] - last[qa], qpos[qa + 1] - last[qa + 1], qpos[qa + 2] - last[qa + 2]);
                    moved.length() + m.dof_arm[da + 3] * angle(qa + 3)
                }
            };
            j += 1;
        }
        out.body_travel[b] = t;
        out.top_travel[b] = if parent == 0 { t } else { out.top_travel[parent] };
        // a pair's decrease is its two bodies' travel below their ancestor: at most twice the
        // largest, less what the joints above a child of the world add to both when it is below
        let own = if m.gaps_within_trees { t - out.top_travel[b] } else { t };
        most = most.max(own);
        unbounded |= own.is_nan();
    }
    // NaN (an unbounded arm times no change) is no bound
    if unbounded { f64::INFINITY } else { 2.0 * most }
}

/// A bound on how much any gap shrank since `qpos_gap`, without the bodies' travel: Σ arm |Δq|
/// over [`Model::gap_arms`] (a pair's distance changes only through the joints on the
/// paths from its common ancestor to its two bodies, disjoint sets among them); ∞ when there is
/// no such list.
pub(super) fn quick_travel(m: &Model, qpos: &[f64], out: &CollisionData) -> f64 {
    let Some(arms) = &m.gap_arms else { return f64::INFINITY };
    let s: f64 = arms.iter().map(|&(qa, arm)| arm * (qpos[qa] - out.qpos_gap[qa]).abs()).sum();
    if s.is_nan() { f64::INFINITY } else { s }
}

/// Collision pair k while every plane group is apart: its geoms posed and bounded as needed, the
/// pair tested. Returns a lower bound on the distance between its geoms where it exceeds `spare`
/// (where it can spare the next test of a [`PairTest::Spheres`] pair), else −∞ or less.
pub(super) fn test_lazily(m: &Model, kin: &KinData, aba: &AbaData, out: &mut CollisionData, k: usize, spare: f64) -> f64 {
    let p = &m.collision_pairs[k];
    for g in [p.g1, p.g2] {
        if !posed(out, g) {
            pose(m, kin, out, g);
        }
    }
    // with the shared bound first, which settles most pairs, then each geom's own
    if !(has_own_reach(out, p.g1) && has_own_reach(out, p.g2)) {
        if apart(out, p, p.margin + reach(out, p.g1) + reach(out, p.g2)) {
            return spheres_gap(out, p, spare);
        }
        for g in [p.g1, p.g2] {
            own_reach_of(m, kin, aba, out, g);
        }
    }
    let margin = p.margin + reach(out, p.g1) + reach(out, p.g2);
    if apart(out, p, margin) {
        return spheres_gap(out, p, spare);
    }
    let tested = test_margin(m, kin, aba, out, k, margin);
    if tested < margin {
        if apart(out, p, tested) { spheres_gap(out, p, spare) } else { pair(m, kin, out, p, tested) }
    } else {
        pair_narrowed(m, kin, aba, out, k, margin)
    }
}

/// The distance between a pair's bounding spheres where it exceeds `spare`, else −∞ (also for
/// a pair that is not [`PairTest::Spheres`]): the square root only where it pays.
#[inline(always)]
pub(super) fn spheres_gap(out: &CollisionData, p: &GeomPair, spare: f64) -> f64 {
    if p.test != PairTest::Spheres {
        return f64::NEG_INFINITY;
    }
    let d2 = out.geom_xpos[p.g1].distance_squared(out.geom_xpos[p.g2]);
    let far = p.radii + spare;
    if d2 > far * far { d2.sqrt() - p.radii } else { f64::NEG_INFINITY }
}
