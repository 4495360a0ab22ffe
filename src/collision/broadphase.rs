//! The broadphase: plane groups, the sort-and-sweep of bounding boxes, bounding-sphere tests and
//! each geom's bound on how far it moves within the step.

use glam::DVec3;

use super::data::{has_own_reach, CollisionData, SweepBox, SWEEP_PAIRS};
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::math::{turned_box, Motion};
use crate::model::{GeomPair, Model, PairTest};

/// Decides each plane group: apart when its subtree's sphere stays farther above the plane than
/// its radius and `reach` (a bound on how far any of its points moves).
pub(super) fn judge_groups(m: &Model, kin: &KinData, out: &mut CollisionData, reach: f64) {
    for (apart, g) in out.group_apart.iter_mut().zip(&m.plane_groups) {
        let height = (kin.xpos[g.body] - out.geom_xpos[g.plane]).dot(out.geom_xmat[g.plane].col(2));
        *apart = height > g.radius + reach;
    }
}

/// The pairs a detection with every geom posed tests on their bounds, in order, taken from
/// `out.near` (the caller puts it back): every pair of a model with fewer than [`SWEEP_PAIRS`],
/// else [`Model::pairs_unswept`] and the sphere pairs whose boxes overlap.
/// Each geom's box holds the geom grown by its margin and `reach(out, g)` (the box of its bounding
/// sphere, cut to [`Model::geom_body_box`] turned into world axes); boxes that do not overlap are
/// farther apart than the pair's margin, so the tests that follow find the contacts the test of
/// every pair finds. The boxes are swept along the axis their centres spread most along
/// (sort and sweep, Baraff 1992, §6.2; [`sweep_axis`]), from the last sweep's order: an
/// insertion sort then costs little. Geoms of non-finite boxes (a diverging world) send every pair
/// to its test.
pub(super) fn near_pairs(m: &Model, kin: &KinData, out: &mut CollisionData, reach: impl Fn(&CollisionData, usize) -> f64) -> Vec<usize> {
    let mut near = std::mem::take(&mut out.near);
    if m.collision_pairs.len() < SWEEP_PAIRS {
        return near;
    }
    near.clear();
    let mut finite = true;
    let mut sweep = std::mem::take(&mut out.sweep);
    out.sweep_axis = sweep_axis(out, &sweep);
    // the boxes' coordinates rotated so that the sweep's axis is x
    let axis = out.sweep_axis;
    let rotate = |v: DVec3| match axis {
        0 => v,
        1 => DVec3::new(v.y, v.z, v.x),
        _ => DVec3::new(v.z, v.x, v.y),
    };
    for b in sweep.iter_mut() {
        let g = b.geom;
        // the box of the geom's bounding sphere, cut down to its own box turned into world axes
        let grow = m.geom_margin[g] + reach(out, g);
        let sphere = DVec3::splat(m.geom_rbound[g]);
        let e = m.geom_body_box[g].map_or(sphere, |half| sphere.min(turned_box(kin.xmat[m.geom_body[g]], half))) + grow;
        let (c, e) = (rotate(out.geom_xpos[g]), rotate(e));
        (b.lo, b.hi) = (c - e, c + e);
        finite &= c.is_finite() && e.is_finite();
    }
    if !finite {
        out.sweep = sweep;
        near.extend(0..m.collision_pairs.len());
        return near;
    }
    for i in 1..sweep.len() {
        let mut j = i;
        while j > 0 && sweep[j - 1].lo.x > sweep[j].lo.x {
            sweep.swap(j - 1, j);
            j -= 1;
        }
    }
    // each box against the boxes that start within its x interval
    let swept = &mut out.swept;
    swept.clear();
    for (i, b) in sweep.iter().enumerate() {
        for a in &sweep[i + 1..] {
            if a.lo.x > b.hi.x {
                break;
            }
            // one branch on the four comparisons (each alone is unpredictable)
            let overlap = (a.hi.y >= b.lo.y) & (b.hi.y >= a.lo.y) & (a.hi.z >= b.lo.z) & (b.hi.z >= a.lo.z);
            if overlap && let Some(k) = pair_of(m, a.geom.min(b.geom), a.geom.max(b.geom)) {
                swept.push(k);
            }
        }
    }
    out.sweep = sweep;
    // in the model's order: the swept pairs sorted, merged with the unswept ones (sorted already)
    swept.sort_unstable();
    let unswept = &m.pairs_unswept;
    let (mut i, mut j) = (0, 0);
    while i < swept.len() || j < unswept.len() {
        if j == unswept.len() || (i < swept.len() && swept[i] < unswept[j]) {
            near.push(swept[i]);
            i += 1;
        } else {
            near.push(unswept[j]);
            j += 1;
        }
    }
    near
}

/// The axis to sweep along: the one the boxes' centres spread most along (their variance), kept
/// until another spreads twice as much, so that the last sweep's order stays nearly sorted.
/// Two rows of characters side by side along y overlap all along x: swept along x, every box
/// meets half the others.
fn sweep_axis(out: &CollisionData, sweep: &[SweepBox]) -> usize {
    let n = sweep.len() as f64;
    let (sum, sq) = sweep.iter().map(|b| out.geom_xpos[b.geom]).fold((DVec3::ZERO, DVec3::ZERO), |(s, q), c| (s + c, q + c * c));
    let spread = (sq - sum * sum / n).to_array();
    let widest = (0..3).max_by(|&a, &b| spread[a].total_cmp(&spread[b])).unwrap_or(0);
    if spread[widest] > 2.0 * spread[out.sweep_axis] { widest } else { out.sweep_axis }
}

/// The index in `m.collision_pairs` of the pair of geoms i < j, if they make one.
pub(super) fn pair_of(m: &Model, i: usize, j: usize) -> Option<usize> {
    let bit = i * m.ngeom + j;
    if !m.pair_bits.is_empty() {
        let (word, mask) = (m.pair_bits[bit / 64], 1u64 << (bit % 64));
        if word & mask == 0 {
            return None;
        }
        if let Some(&before) = m.pair_rank.get(bit / 64) {
            return Some(before as usize + (word & (mask - 1)).count_ones() as usize);
        }
    }
    let first = m.geom_first_pair[i];
    let partners = &m.pair_partner[first..m.geom_first_pair[i + 1]];
    partners.binary_search(&(j as u32)).ok().map(|k| first + k)
}

/// Broadphase: the pair's plane group apart, or bounding spheres farther apart than `margin`, or a
/// bounding sphere that far above a plane.
#[inline(always)]
pub(super) fn apart(cd: &CollisionData, p: &GeomPair, margin: f64) -> bool {
    let reach = p.radii + margin;
    match p.test {
        PairTest::Spheres => cd.geom_xpos[p.g1].distance_squared(cd.geom_xpos[p.g2]) > reach * reach,
        PairTest::Plane { plane, other, group } => {
            group.is_some_and(|g| cd.group_apart[g]) || (cd.geom_xpos[other] - cd.geom_xpos[plane]).dot(cd.geom_xmat[plane].col(2)) > reach
        }
        PairTest::Always => false,
    }
}

/// Computes geom g's own bound (with the shared one) unless it already is.
#[inline(always)]
pub(super) fn own_reach_of(m: &Model, kin: &KinData, aba: &AbaData, cd: &mut CollisionData, g: usize) {
    if !has_own_reach(cd, g) {
        cd.geom_reach[g] = cd.shared_reach.min(own_reach(m, kin, aba, cd, g));
        cd.reach_at[g] = cd.stamp;
    }
}

/// Geom g's own bound on how far its points move within the step.
#[inline(always)]
pub(super) fn own_reach(m: &Model, kin: &KinData, aba: &AbaData, out: &CollisionData, g: usize) -> f64 {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    // bounds over the geom's points: centre value + angular part × bounding radius,
    // |v_c| + h|a_c| + r (|ω| + h(|α| + |ω|²)); ABA's accelerations carry the base's fictitious
    // −g, added back. Two square roots instead of four, by x + y ≤ √(2(x² + y²)) over each pair
    // (within √2, and tight when the h-term is small, as it usually is)
    let n = m.body_node[m.geom_body[g]];
    let (v, a, centre, rb) = (kin.v[n], aba.a[n], out.geom_xpos[g] - kin.origin, m.geom_rbound[g]);
    let vc = v.point_velocity(centre);
    let ac = a.point_velocity(centre) + v.ang.cross(vc) + m.opt.gravity;
    let w2 = v.ang.length_squared();
    let linear = (2.0 * (vc.length_squared() + h * h * ac.length_squared())).sqrt();
    let angular = (2.0 * (w2 + h * h * a.ang.length_squared())).sqrt() + h * w2;
    lever * (linear + angular * rb)
}

/// A bound on how far two moving geoms i and j can approach each other within the step, from
/// their bodies' relative motion (two limbs of a falling character, or two characters falling
/// side by side, keep their distance however fast they fall). Seen from j's body, a point p of
/// i moves at u(p) = (v_i − v_j)(p), which changes at (a_i − a_j)(p) + Ω × v_i(p) − ω_j × u(p),
/// Ω = ω_i − ω_j (ABA's fictitious −g cancels in a_i − a_j); bounded over i's bounding sphere as
/// [`own_reach`] bounds a point's own motion. i is the pair's geom of the smaller bounding radius.
/// The accelerations are constraint-free, and a body resting on another lacks its support there
/// while both fall alike: one step's fall, h|g|, is added to the relative speed.
#[inline(always)]
pub(super) fn relative_reach(m: &Model, kin: &KinData, aba: &AbaData, out: &CollisionData, p: &GeomPair) -> f64 {
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    let (i, ni, nj) = smaller_first(m, p);
    let (vi, vj) = (kin.v[ni], kin.v[nj]);
    let (dv, da) = (vi - vj, aba.a[ni] - aba.a[nj]);
    let (centre, rb) = (out.geom_xpos[i] - kin.origin, m.geom_rbound[i]);
    let u = dv.point_velocity(centre);
    let du = da.point_velocity(centre) + dv.ang.cross(vi.point_velocity(centre)) - vj.ang.cross(u);
    let w = dv.ang.length();
    let linear = u.length() + h * du.length();
    let angular = w + h * (da.ang.length() + w * (vi.ang.length() + vj.ang.length()));
    lever * (linear + angular * rb) + fall(m)
}

/// One step's fall, lever · h|g|: what [`relative_reach`] adds for the support a body resting on
/// another lacks in the constraint-free accelerations.
#[inline(always)]
pub(super) fn fall(m: &Model) -> f64 {
    m.opt.lever() * m.opt.timestep * m.opt.gravity.length()
}

/// [`relative_reach`] at the step's end velocities `v_end` (per node), without acceleration terms.
#[inline(always)]
pub(super) fn relative_reach_end(m: &Model, kin: &KinData, v_end: &[Motion], out: &CollisionData, p: &GeomPair) -> f64 {
    let (i, ni, nj) = smaller_first(m, p);
    let dv = v_end[ni] - v_end[nj];
    m.opt.lever() * (dv.point_velocity(out.geom_xpos[i] - kin.origin).length() + dv.ang.length() * m.geom_rbound[i])
}

/// The pair's geom of the smaller bounding radius, its node and the other geom's node.
#[inline(always)]
fn smaller_first(m: &Model, p: &GeomPair) -> (usize, usize, usize) {
    let (i, j) = if m.geom_rbound[p.g1] <= m.geom_rbound[p.g2] { (p.g1, p.g2) } else { (p.g2, p.g1) };
    (i, m.body_node[m.geom_body[i]], m.body_node[m.geom_body[j]])
}

/// Bound on the speed of any point of any moving geom whose joint speeds are at most `speeds`
/// (nv), from [`Model::dof_arm`]: O(nv), no kinematics; ∞ when an arm is unbounded (0 · ∞ gives
/// NaN, taken as ∞ too).
pub(super) fn arm_speed(m: &Model, speeds: impl Iterator<Item = f64>) -> f64 {
    let s: f64 = m.dof_arm.iter().zip(speeds).map(|(c, v)| c * v).sum();
    if s.is_nan() { f64::INFINITY } else { s }
}

#[cfg(test)]
mod tests {
    use super::pair_of;
    use crate::Model;

    /// A pair's index by its bit's rank is its index in the pairs, and geoms that make no pair
    /// (a body and its parent's) have none: six capsule–sphere chains on a plane.
    #[test]
    fn pair_of_finds_each_pair_by_rank() {
        let mut bodies = String::new();
        for c in 0..6 {
            bodies += &format!(
                "<body pos='{c} 0 1'><freejoint/><geom type='capsule' size='.05 .2'/>\
                 <body pos='0 0 .5'><joint type='hinge'/><geom type='sphere' size='.1'/></body></body>"
            );
        }
        let xml = format!("<mujoco><worldbody><geom type='plane' size='5 5 .1'/>{bodies}</worldbody></mujoco>");
        let m = Model::from_mjcf(&xml).expect("the scene compiles");
        assert!(!m.pair_rank.is_empty());
        for i in 0..m.ngeom {
            for j in i + 1..m.ngeom {
                let k = m.collision_pairs.iter().position(|p| (p.g1, p.g2) == (i, j));
                assert_eq!(pair_of(&m, i, j), k, "geoms {i}, {j}");
            }
        }
    }
}
