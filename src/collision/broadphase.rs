//! The broadphase: plane groups, the sort-and-sweep of bounding boxes, bounding-sphere tests and
//! each geom's bound on how far it moves within the step.

use glam::{DMat3, DVec3};

use super::data::{has_own_reach, CollisionData, SweepBox, SWEEP_PAIRS};
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::math::{turned_box, Motion};
use crate::mjcf::GeomType;
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

/// Whether boxes (centre, rotation, half extents) lie farther apart than `margin` along one of
/// the 15 axes that can separate them ([`box_axes`]).
pub(super) fn boxes_apart(i: (DVec3, DMat3, DVec3), j: (DVec3, DMat3, DVec3), margin: f64) -> bool {
    // a round-off's slack on the edge axes (near zero length for parallel edges)
    let slack = 1e-12 * (i.2.max_element() + j.2.max_element());
    box_axes(i, j, |along, reach, len, edge| along > reach + margin * len + if edge { slack } else { 0.0 })
}

/// A lower bound on the distance between boxes (centre, rotation, half extents): the most they
/// lie apart along one of [`box_axes`] (each unit axis's separation is one; the edge pairs'
/// nearly parallel are left out), less a round-off's slack. Negative where they may overlap.
pub(super) fn boxes_separation(i: (DVec3, DMat3, DVec3), j: (DVec3, DMat3, DVec3)) -> f64 {
    let mut best = f64::NEG_INFINITY;
    box_axes(i, j, |along, reach, len, _| {
        if len >= 1e-3 {
            best = best.max((along - reach) / len);
        }
        false
    });
    best - 1e-12 * (1.0 + (j.0 - i.0).length() + i.2.max_element() + j.2.max_element())
}

/// The 15 axes that can separate two boxes (their faces' normals, then the cross products of
/// their edges; Gottschalk, Lin & Manocha 1996), each given to `visit` as (|centres' offset|
/// along it, the two boxes' reach along it, its length, whether it is an edge pair's) until
/// `visit` returns true; whether one did.
#[inline(always)]
fn box_axes((ci, ri, hi): (DVec3, DMat3, DVec3), (cj, rj, hj): (DVec3, DMat3, DVec3), mut visit: impl FnMut(f64, f64, f64, bool) -> bool) -> bool {
    // j's box in i's frame: centre t, axes the columns of r
    let t = ri.transpose() * (cj - ci);
    let r = ri.transpose() * rj;
    let a = [r.x_axis.abs(), r.y_axis.abs(), r.z_axis.abs()];
    let abs = |k: usize| DVec3::new(a[0][k], a[1][k], a[2][k]);
    // i's faces, then j's
    for k in 0..3 {
        if visit(t[k].abs(), hi[k] + hj.dot(abs(k)), 1.0, false) {
            return true;
        }
    }
    for k in 0..3 {
        if visit(r.col(k).dot(t).abs(), hj[k] + hi.dot(a[k]), 1.0, false) {
            return true;
        }
    }
    // edge pairs: axis e_p × col_k of r, of length √(1 − r_pk²)
    for p in 0..3 {
        let (u, v) = ((p + 1) % 3, (p + 2) % 3);
        for k in 0..3 {
            let (ku, kv) = ((k + 1) % 3, (k + 2) % 3);
            let along = (t[v] * r.col(k)[u] - t[u] * r.col(k)[v]).abs();
            let reach_i = hi[u] * a[k][v] + hi[v] * a[k][u];
            let reach_j = hj[ku] * a[kv][p] + hj[kv] * a[ku][p];
            let len = (1.0 - a[k][p] * a[k][p]).max(0.0).sqrt();
            if visit(along, reach_i + reach_j, len, true) {
                return true;
            }
        }
    }
    false
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

/// The margin pair k is tested within, `margin` from each geom's own bound: where both geoms move
/// and one is a mesh, a cylinder or an ellipsoid, whose test (GJK) costs far more than
/// [`relative_reach`], the narrower margin of their relative motion, noted in
/// [`CollisionData::narrowed`] (two links of a falling robot test their meshes and cylinders only
/// for what their joints can close).
#[inline(always)]
pub(super) fn test_margin(m: &Model, kin: &KinData, aba: &AbaData, out: &mut CollisionData, k: usize, margin: f64) -> f64 {
    let p = &m.collision_pairs[k];
    let dear = |g: usize| matches!(m.geom_type[g], GeomType::Mesh | GeomType::Cylinder | GeomType::Ellipsoid);
    if !(p.both_move && (dear(p.g1) || dear(p.g2))) {
        return margin;
    }
    let relative = p.margin + relative_reach(m, kin, aba, out, p);
    if relative < margin {
        out.narrowed.push((k, relative));
        relative
    } else {
        margin
    }
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
    use super::{boxes_apart, boxes_separation, pair_of};
    use glam::{DMat3, DVec3};
    use crate::Model;

    #[test]
    fn boxes_apart_only_where_the_boxes_are_apart() {
        // beside parry's exact distance of two cuboids: boxes declared apart are farther apart
        // than the margin, overlapping boxes never are, and most pairs farther apart than the
        // margin plus their size's tenth are found apart (the test reads 15 axes, not the
        // distance); the separation of boxes found apart lies between the margin and the distance
        use parry3d_f64::math::{Pose, Rotation, Vector};
        use parry3d_f64::shape::Cuboid;
        let mut x = 7u64;
        let mut rand = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut apart, mut overlap, mut far, mut far_found, mut tightest) = (0, 0, 0, 0, 0.0_f64);
        for _ in 0..4000 {
            let mut pose = || {
                let q = glam::DQuat::from_xyzw(rand() - 0.5, rand() - 0.5, rand() - 0.5, rand() - 0.5).normalize();
                let c = DVec3::new(rand(), rand(), rand()) * 2.0;
                (c, q, DVec3::new(0.1 + rand(), 0.1 + rand(), 0.1 + rand()) * 0.5)
            };
            let (a, b, margin) = (pose(), pose(), 0.1 * rand());
            let parry = |(c, q, h): (DVec3, glam::DQuat, DVec3)| {
                let pose = Pose::from_parts(Vector::new(c.x, c.y, c.z), Rotation::from_xyzw(q.x, q.y, q.z, q.w));
                (pose, Cuboid::new(Vector::new(h.x, h.y, h.z)))
            };
            let ((pa, ca), (pb, cb)) = (parry(a), parry(b));
            let dist = parry3d_f64::query::distance(&pa, &ca, &pb, &cb).unwrap().distance;
            let (ba, bb) = ((a.0, DMat3::from_quat(a.1), a.2), (b.0, DMat3::from_quat(b.1), b.2));
            let found = boxes_apart(ba, bb, margin);
            if found {
                assert!(dist > margin, "{a:?} {b:?} {margin} {dist}");
                apart += 1;
                // where they part, their separation bounds the distance from below, and beyond
                // the margin (the pair's gap, `collision::gaps`)
                let sep = boxes_separation(ba, bb);
                assert!(sep <= dist && sep > margin - 1e-12, "{a:?} {b:?} {margin}: {sep} against {dist}");
                tightest = tightest.max(sep / dist);
            }
            if dist == 0.0 {
                assert!(!found);
                overlap += 1;
            }
            if dist > margin + 0.1 * (a.2.length() + b.2.length()) {
                far += 1;
                far_found += usize::from(found);
            }
        }
        assert!(apart > 500 && overlap > 500, "{apart} {overlap}");
        assert!(far_found as f64 > 0.9 * far as f64, "{far_found} of {far}");
        assert!(tightest > 0.999, "the separations stay below the distances by {tightest}");
    }

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
