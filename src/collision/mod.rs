//! Stage 3 — collision detection: contact points for the current configuration.
//!
//! Pairs: plane–{sphere, capsule, box}, sphere–sphere, sphere–capsule, capsule–capsule, sphere–box
//! (exact), capsule–box (the segment's ends and its point nearest the box, as spheres) and box–box
//! (separating axes: face contacts clipped to the overlap of the faces, or one edge–edge point);
//! a mesh's convex hull against a plane, a sphere, a capsule, a box or another hull, and a height
//! field's triangle prisms against all but planes (`convex.rs`, `terrain.rs`); an ellipsoid against
//! a plane in closed form and against every other shape by its support function
//! (`ellipsoid.rs`); a cylinder against a plane in closed form and against every other shape by
//! its support function's closest point and the rim points and vertices of a flat contact
//! (`cylinder.rs`). Filtering follows MuJoCo: contype/conaffinity
//! bits, no contact within a body or between a body and its parent (unless the parent is the
//! world), `<exclude>` pairs. A contact's friction and condim are MuJoCo's: the higher-priority
//! geom's, else the larger of each.
//!
//! The broadphase has two levels. First a world plane is tested against the sphere that holds a
//! whole subtree of the world's child (`Model::plane_groups`), decided with one O(nv) bound on how
//! far any geom point moves within the step (`Model::dof_arm`). Then each remaining pair is tested
//! on its bounding spheres, with each geom's own bound from its velocity. While every group is
//! apart (nothing near the floor) the pairs are spared more: geoms are posed and bounded only as
//! pairs need them (a pair apart with the shared bound needs neither geom's own), and each pair of
//! bounded geoms keeps a lower bound on its distance, its *gap* (the bounding spheres' distance or,
//! for sphere and capsule pairs, the exact one at its last test), lowered at each detection by how
//! far the joints below the two geoms' common ancestor have moved them since (each joint's arm
//! times its change of position); while the gap exceeds the largest margin the pair can have, the
//! pair is not tested. When the least gap exceeds that margin by a bound on how far the joints
//! moved any pair (one pass over the hinges and slides below the children of the world where those
//! are all the joints there, else twice the largest travel below such a child), every pair is
//! settled at once and the gaps are kept as they were. Poses and bounds are flagged with the
//! number of the detection they belong to, so a new detection forgets them by counting. A scene
//! whose floor is far and whose limbs are apart costs a few bounds per step.
//!
//! Detection is speculative: a pair within its margin plus the distance its geoms can cover in one
//! step yields a (separated, dist > 0) contact, whose row only stops it at the surface. Two moving
//! geoms are bounded by their bodies' relative motion where that is less (limbs of one falling
//! character, characters falling side by side).

use crate::model::Model;

use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::dynamics::DynamicsData;
use crate::state::WorldState;
use crate::math::Motion;

mod broadphase;
mod convex;
mod cylinder;
mod ellipsoid;
mod data;
mod gaps;
mod narrowphase;
mod plane_walk;
mod prism;
pub mod ray;
mod shapes;
mod terrain;

use broadphase::{apart, arm_speed, fall, judge_groups, near_pairs, own_reach_of, relative_reach, relative_reach_end, test_margin};
pub use data::{CollisionData, Contact};
use data::{pose, posed, reach, fixed, GAP_TOLERANCE};
use gaps::{lower_and_test_gaps, quick_travel, test_lazily, travel};
pub use narrowphase::contact_friction;
use narrowphase::pair;

/// Clears the contacts and, when the model has pairs to test, starts a detection: decides the
/// plane groups with `reach` (see [`judge_groups`]), which becomes every moving geom's bound, and
/// forgets the last detection's poses and bounds (by its `stamp`). Unless every group is apart it
/// poses all moving geoms; else none (they are posed as pairs need them). None when there is
/// nothing to test, else whether every group is apart.
fn begin(m: &Model, kin: &KinData, out: &mut CollisionData, reach: f64) -> Option<bool> {
    out.contacts.clear();
    out.narrowed.clear();
    out.gap_skips = 0;
    out.scratch.kept.skips = 0;
    if !m.opt.contact || m.collision_pairs.is_empty() {
        return None;
    }
    out.stamp += 1;
    out.shared_reach = reach;
    judge_groups(m, kin, out, reach);
    let all_apart = out.group_apart.iter().all(|&a| a);
    if !all_apart {
        for g in (0..m.ngeom).filter(|&g| m.geom_body[g] != 0) {
            pose(m, kin, out, g);
        }
    }
    Some(all_apart)
}

/// Detects all contacts of the configuration `s.qpos`, whose kinematics are in `dy.kin`, with
/// `dy.aba` and `dy.qacc` holding the constraint-free accelerations of the same state (for how
/// far a geom can move within the step).
pub fn collide(m: &Model, dy: &DynamicsData, s: &WorldState<'_>, out: &mut CollisionData) {
    let (kin, aba, qacc, qpos, qvel) = (&dy.kin, &dy.aba, &dy.qacc, &*s.qpos, &*s.qvel);
    // the step's end velocity (each joint's at most |q̇ + h q̈|) moves a point by lever × its
    // speed: one bound for all moving geoms decides the plane groups (and the gaps); each geom's
    // own, usually tighter and dearer, serves the pair tests
    let h = m.opt.timestep;
    // the joints' arms bound it while the limited slides keep within their ranges
    out.arms_hold = m.arms_hold(qpos);
    let shared = if out.arms_hold { m.opt.lever() * arm_speed(m, qvel.iter().zip(qacc).map(|(v, a)| v.abs() + h * a.abs())) } else { f64::INFINITY };
    let Some(all_apart) = begin(m, kin, out, shared) else { return };
    out.gaps_current = all_apart;
    if all_apart {
        // the margin is at most p.margin + 2 shared: a larger gap spares the test
        let spare = 2.0 * shared + GAP_TOLERANCE;
        if !m.gap_pairs.is_empty() {
            let quick = quick_travel(m, qpos, out);
            let shrink = if out.least_slack - quick > spare { quick } else { travel(m, qpos, out) };
            if out.least_slack - shrink > spare {
                // every gap pair settled at once; the gaps stay those of `qpos_gap`
                out.shrink = shrink;
                out.gap_skips = m.gap_pairs.len();
            } else {
                lower_and_test_gaps(m, kin, aba, qpos, out, spare);
            }
        }
        for &k in &m.pairs_without_gap {
            test_lazily(m, kin, aba, out, k, f64::INFINITY);
        }
        // the gap pairs, then the rest, narrowed: in the pairs' order for `test_again`'s search
        out.narrowed.sort_unstable_by_key(|n| n.0);
        if !out.arms_hold {
            // travel measured from here would count arms that did not hold on the way
            out.forget_gaps();
        }
        return;
    }
    for g in 0..m.ngeom {
        own_reach_of(m, kin, aba, out, g);
    }
    let near = near_pairs(m, kin, out, reach);
    for &k in &near {
        let p = &m.collision_pairs[k];
        // speculative: pairs that could close within this step (which moves a point by
        // lever × (v + h a), lever = h for semi-implicit Euler) count as contacts, so a fast foot
        // is stopped at the surface instead of being found inside it one step later
        let margin = p.margin + reach(out, p.g1) + reach(out, p.g2);
        if apart(out, p, margin) {
            continue;
        }
        let tested = test_margin(m, kin, aba, out, k, margin);
        if tested < margin {
            if !apart(out, p, tested) {
                pair(m, kin, out, p, tested);
            }
            continue;
        }
        pair_narrowed(m, kin, aba, out, k, margin);
    }
    out.near = near;
}

/// Pair k's narrowphase within `margin`, its geoms' own reaches: where both geoms move, the
/// contacts found farther than their relative motion can close are dropped (bounded only where a
/// contact found lies farther than that could matter: two feet of a falling robot keep their
/// distance). Returns [`pair`]'s distance.
fn pair_narrowed(m: &Model, kin: &KinData, aba: &AbaData, out: &mut CollisionData, k: usize, margin: f64) -> f64 {
    let p = &m.collision_pairs[k];
    let before = out.contacts.len();
    let dist = pair(m, kin, out, p, margin);
    if p.both_move && out.contacts[before..].iter().any(|c| c.dist > p.margin + fall(m)) {
        narrow(out, k, before, (p.margin + relative_reach(m, kin, aba, out, p)).min(margin));
    }
    dist
}

/// Drops the contacts from `before` on (pair k's) farther than `margin`, and notes the pair's
/// narrower margin for [`reach_again`] if it dropped any.
fn narrow(out: &mut CollisionData, k: usize, before: usize, margin: f64) {
    if drop_beyond(&mut out.contacts, before, margin) {
        // in the pairs' order, as `near` is: [`test_again`] searches it by halves
        debug_assert!(out.narrowed.last().is_none_or(|n| n.0 < k));
        out.narrowed.push((k, margin));
    }
}

/// Drops the contacts from `before` on farther than `margin` (in order); whether any were.
fn drop_beyond(contacts: &mut Vec<Contact>, before: usize, margin: f64) -> bool {
    let mut kept = before;
    for i in before..contacts.len() {
        if contacts[i].dist <= margin {
            contacts[kept] = contacts[i];
            kept += 1;
        }
    }
    let dropped = kept < contacts.len();
    contacts.truncate(kept);
    dropped
}

/// Contacts of the configuration in `kin` that penetrate (dist < 0) — no speculative margin; for
/// checking a configuration after the step.
pub fn penetrations(m: &Model, kin: &KinData, out: &mut CollisionData) {
    let Some(all_apart) = begin(m, kin, out, 0.0) else { return };
    if !all_apart {
        let near = near_pairs(m, kin, out, |_, _| 0.0);
        for &k in &near {
            let p = &m.collision_pairs[k];
            if !apart(out, p, 0.0) {
                pair(m, kin, out, p, 0.0);
            }
        }
        out.near = near;
        return;
    }
    // the geoms posed as pairs need them
    let gapped = m.gap_pairs.iter().map(|gp| gp.pair);
    for k in gapped.chain(m.pairs_without_gap.iter().copied()) {
        let p = &m.collision_pairs[k];
        for g in [p.g1, p.g2] {
            if !posed(out, g) {
                pose(m, kin, out, g);
            }
        }
        if !apart(out, p, 0.0) {
            pair(m, kin, out, p, 0.0);
        }
    }
}

/// After the constraint solve: with the step's final joint velocities `qvel_end`, the pairs whose
/// reach lever·|v_end| now exceeds their first margin are tested again (same configuration) and
/// contacts not found before are appended. Returns whether there were any: constraint forces (a
/// body landing on another, say) can carry a geom further than its constraint-free motion. The
/// nodes' end velocities are computed into `v_end` only if a pair needs them.
pub fn reach_again(m: &Model, kin: &KinData, qvel_end: &[f64], v_end: &mut [Motion], out: &mut CollisionData) -> bool {
    if !m.opt.contact || m.collision_pairs.is_empty() {
        return false;
    }
    let lever = m.opt.lever();
    // one bound for every geom point decides the groups and settles most gap pairs (while the
    // arms hold at this configuration, the detection's)
    let reach = if out.arms_hold { lever * arm_speed(m, qvel_end.iter().map(|v| v.abs())) } else { f64::INFINITY };
    judge_groups(m, kin, out, reach);
    let mut found = false;
    if !out.group_apart.iter().all(|&a| a) {
        end_speeds(m, kin, qvel_end, v_end, out);
        // no geom reaching as far as the first detection looked (a millionth of a millionth to
        // spare for the pairs' sums): only the pairs narrowed to their relative motion can find
        // more, and each pair whose boxes no longer overlap finds nothing within its margin
        if (0..m.ngeom).all(|g| lever * out.geom_speed_end[g] <= data::reach(out, g) * (1.0 - 1e-12)) {
            for i in 0..out.narrowed.len() {
                let Some(more) = test_again(m, kin, v_end, out, out.narrowed[i].0, lever) else { break };
                found |= more;
            }
            return found;
        }
        let near = near_pairs(m, kin, out, |out, g| lever * out.geom_speed_end[g]);
        for &k in &near {
            let Some(more) = test_again(m, kin, v_end, out, k, lever) else { break };
            found |= more;
        }
        out.near = near;
        return found;
    }
    // every group apart: the gap pairs, whose gaps (when of this configuration) settle most, and
    // the rest outside groups
    let gaps = out.gaps_current;
    let mut speeds = false;
    let n = m.gap_pairs.len();
    // the reach of a pair is at most 2 reach: the least slack may settle them all
    let first = if gaps && out.least_slack - out.shrink > 2.0 * reach + GAP_TOLERANCE { n } else { 0 };
    for idx in first..n + m.pairs_without_gap.len() {
        let k = if idx < n {
            let gp = &m.gap_pairs[idx];
            if gaps && out.pair_gap[idx] - out.shrink > gp.margin + 2.0 * reach + GAP_TOLERANCE {
                continue;
            }
            gp.pair
        } else {
            m.pairs_without_gap[idx - n]
        };
        if !speeds {
            end_speeds(m, kin, qvel_end, v_end, out);
            speeds = true;
        }
        let Some(more) = test_again(m, kin, v_end, out, k, lever) else { break };
        found |= more;
    }
    found
}

/// The nodes' end velocities from `qvel_end` into `v_end`, and from them
/// [`CollisionData::geom_speed_end`] (posing the geoms not yet posed).
fn end_speeds(m: &Model, kin: &KinData, qvel_end: &[f64], v_end: &mut [Motion], out: &mut CollisionData) {
    crate::dynamics::kinematics::velocities(m, kin, qvel_end, v_end);
    for g in 0..m.ngeom {
        if !posed(out, g) {
            pose(m, kin, out, g);
        }
        out.geom_speed_end[g] = if fixed(m, g) {
            0.0
        } else {
            let v = &v_end[m.body_node[m.geom_body[g]]];
            v.point_velocity(out.geom_xpos[g] - kin.origin).length() + v.ang.length() * m.geom_rbound[g]
        };
    }
}

/// [`reach_again`]'s test of pair k: whether it added contacts, None when the list is full.
#[inline(always)]
fn test_again(m: &Model, kin: &KinData, v_end: &[Motion], out: &mut CollisionData, k: usize, lever: f64) -> Option<bool> {
    let p = &m.collision_pairs[k];
    let reach = lever * (out.geom_speed_end[p.g1] + out.geom_speed_end[p.g2]);
    // the first detection's margin: each geom's own bound, or the relative one it narrowed the
    // pair to, which then bounds this look too
    let narrowed = out.narrowed.binary_search_by_key(&k, |n| n.0).ok().map(|i| out.narrowed[i].1);
    let (first, margin) = match narrowed {
        Some(first) => (first, p.margin + reach.min(relative_reach_end(m, kin, v_end, out, p))),
        None => (p.margin + self::reach(out, p.g1) + self::reach(out, p.g2), p.margin + reach),
    };
    if margin <= first || apart(out, p, margin) {
        return Some(false);
    }
    let before = out.contacts.len();
    if before >= m.opt.max_contacts {
        // full: a replacement would change contacts the rows already refer to
        return None;
    }
    pair(m, kin, out, p, margin);
    if p.both_move && narrowed.is_none() && out.contacts[before..].iter().any(|c| c.dist > p.margin) {
        let relative = p.margin + relative_reach_end(m, kin, v_end, out, p);
        drop_beyond(&mut out.contacts, before, relative);
    }
    let mut found = false;
    let mut k = before;
    while k < out.contacts.len() {
        let c = out.contacts[k];
        if out.contacts[..before].iter().any(|o| (o.geom1, o.geom2, o.feature) == (c.geom1, c.geom2, c.feature)) {
            out.contacts.remove(k);
        } else {
            k += 1;
            found = true;
        }
    }
    Some(found)
}
