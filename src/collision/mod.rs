//! Stage 3 — collision detection: contact points for the current configuration.
//!
//! Pairs: plane–{sphere, capsule, box}, sphere–sphere, sphere–capsule, capsule–capsule, sphere–box
//! (exact), capsule–box (the segment's ends and its point nearest the box, as spheres) and box–box
//! (separating axes: face contacts clipped to the overlap of the faces, or one edge–edge point).
//! Cylinders collide as capsules of the same radius and half-length, ellipsoids as spheres of their
//! largest semi-axis (documented approximations). Filtering follows MuJoCo: contype/conaffinity
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
//! step yields a (separated, dist > 0) contact, whose row only stops it at the surface.

use glam::{DMat3, DVec3};

use crate::math::quat_wxyz;
use crate::model::{GeomPair, GeomType, JointType, Model, PairTest, WORLD};

use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
use crate::dynamics::DynamicsData;
use crate::state::WorldState;
use crate::math::Motion;

mod narrowphase;
mod shapes;

pub use narrowphase::contact_friction;
use narrowphase::*;
use shapes::*;

/// One contact point. The normal points from geom2 to geom1: pushing body1 along +n and body2
/// along −n separates them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// First geom.
    pub geom1: usize,
    /// Second geom.
    pub geom2: usize,
    /// Feature index within the pair (capsule end, box corner, clipped face vertex, edge pair), for
    /// identity across steps.
    pub feature: usize,
    /// Contact point in world coordinates (midway between the surfaces).
    pub pos: DVec3,
    /// Unit normal in world coordinates.
    pub normal: DVec3,
    /// Signed distance: negative when penetrating.
    pub dist: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Whether friction applies (condim > 1 for both geoms).
    pub friction: bool,
}

/// World poses of all geoms, the pairs' gaps, and the contact list.
#[derive(Clone, Debug, Default)]
pub struct CollisionData {
    /// Geom axes in world (ngeom); a moving geom's are current only where `axes_at` says so.
    pub geom_xmat: Vec<DMat3>,
    /// The detection (`stamp`) `geom_xmat[g]` was posed in (u64::MAX: a world geom, posed for
    /// good): the narrowphase poses the axes of the geoms it tests, so pairs the broadphase
    /// rejects cost no rotation.
    axes_at: Vec<u64>,
    /// Geom centre in world (ngeom); a moving geom's is current only where `posed_at` says so.
    pub geom_xpos: Vec<DVec3>,
    /// The detection `geom_xpos[g]` (and a plane's axes) was posed in: while every plane group is
    /// apart, geoms are posed only for the pairs tested.
    posed_at: Vec<u64>,
    /// Number of the current detection: a flag of the last one is forgotten by counting, not by
    /// clearing every geom's.
    stamp: u64,
    /// Per [`crate::model::PlaneGroup`]: whether its subtree is apart from its plane.
    group_apart: Vec<bool>,
    /// Geom g's own bound on how far any of its points can move within the step, from its speed
    /// and constraint-free acceleration (ngeom), taken with the bound shared by all moving geoms
    /// (the smaller): current where `reach_at` says so, else `shared_reach` holds ([`reach`]).
    /// Fixed geoms: 0.
    geom_reach: Vec<f64>,
    /// The detection `geom_reach[g]` was computed in (u64::MAX: a fixed geom): it is computed for
    /// the geoms of the pairs that the shared bound does not settle.
    reach_at: Vec<u64>,
    /// The bound shared by all moving geoms in the current detection.
    shared_reach: f64,
    /// Bound on the speed of any point of each geom at the end of the step (ngeom).
    pub geom_speed_end: Vec<f64>,
    /// Per [`crate::model::GapPair`]: a lower bound on the distance between its geoms at
    /// `qpos_gap` (−∞ when unknown).
    pair_gap: Vec<f64>,
    /// The configuration the gaps were last lowered to (nq).
    qpos_gap: Vec<f64>,
    /// How far the joints from the world to each body have moved any geom point of the body's
    /// subtree since `qpos_gap`, summed along the chain (nbody).
    body_travel: Vec<f64>,
    /// `body_travel` of the child of the world each body descends from (nbody).
    top_travel: Vec<f64>,
    /// Whether every gap pair's common ancestor is below the world, so that the joints above a
    /// child of the world move both its geoms alike.
    gaps_within_trees: bool,
    /// (qpos address, arm) of each joint that can move a gap pair's geoms relative to each other
    /// (with `gaps_within_trees`, those below the children of the world), when all are hinges or
    /// slides: [`quick_travel`] then bounds how far the gaps shrank in one pass over them.
    quick_arms: Option<Vec<(usize, f64)>>,
    /// Whether `pair_gap` less `shrink` bounds the distances at the configuration of the last
    /// detection (which keeps the gaps only while every plane group is apart).
    gaps_current: bool,
    /// The least of `pair_gap[i]` less the pair's margin: when it exceeds what the joints' travel
    /// since `qpos_gap` can take off any gap plus the largest margin, every gap pair is settled at
    /// once and the gaps stay those of `qpos_gap`.
    least_slack: f64,
    /// How much any gap may have shrunk between `qpos_gap` and the last detection's configuration.
    shrink: f64,
    /// Pairs whose gap spared them a test in the last detection.
    pub gap_skips: usize,
    /// The boxes of [`Model::sweep_geoms`] by increasing `lo.x`, as the last sweep left them
    /// (nearly sorted for the next).
    sweep: Vec<SweepBox>,
    /// The pairs of two trees whose boxes overlap, as the sweep finds them ([`near_pairs`]).
    swept: Vec<usize>,
    /// The pairs the sweep leaves to test, in order ([`near_pairs`]).
    near: Vec<usize>,
    /// Contacts of this configuration.
    pub contacts: Vec<Contact>,
}

impl CollisionData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        let gaps_within_trees = m.gap_pairs.iter().all(|gp| gp.ancestor != 0);
        CollisionData {
            // world geoms never move: their poses are set here once (the world frame is the identity)
            geom_xmat: m.geom_mat.clone(),
            axes_at: (0..m.ngeom).map(|g| if m.geom_body[g] == 0 { u64::MAX } else { 0 }).collect(),
            geom_xpos: m.geom_pos.clone(),
            posed_at: (0..m.ngeom).map(|g| if m.geom_body[g] == 0 { u64::MAX } else { 0 }).collect(),
            stamp: 0,
            group_apart: vec![false; m.plane_groups.len()],
            geom_reach: vec![0.0; m.ngeom],
            // a fixed geom's bound is 0 for good
            reach_at: (0..m.ngeom).map(|g| if fixed(m, g) { u64::MAX } else { 0 }).collect(),
            shared_reach: 0.0,
            geom_speed_end: vec![0.0; m.ngeom],
            pair_gap: vec![f64::NEG_INFINITY; m.gap_pairs.len()],
            qpos_gap: m.qpos0.clone(),
            body_travel: vec![0.0; m.nbody],
            top_travel: vec![0.0; m.nbody],
            gaps_within_trees,
            quick_arms: quick_arms(m, gaps_within_trees),
            gaps_current: false,
            least_slack: f64::NEG_INFINITY,
            shrink: 0.0,
            gap_skips: 0,
            sweep: m.sweep_geoms.iter().map(|&g| SweepBox { lo: DVec3::ZERO, hi: DVec3::ZERO, geom: g, tree: crate::model::geom_tree(m, g) }).collect(),
            swept: Vec::with_capacity(if m.collision_pairs.len() < SWEEP_PAIRS { 0 } else { m.collision_pairs.len() }),
            // a model of few pairs tests them all, listed once here
            near: if m.collision_pairs.len() < SWEEP_PAIRS { (0..m.collision_pairs.len()).collect() } else { Vec::with_capacity(m.collision_pairs.len()) },
            contacts: Vec::with_capacity(MAX_CONTACTS),
        }
    }

    /// Forgets the contacts and the pairs' gaps.
    pub fn forget(&mut self) {
        self.contacts.clear();
        self.pair_gap.fill(f64::NEG_INFINITY);
        self.least_slack = f64::NEG_INFINITY;
    }
}

/// Gaps are compared with this much to spare (m): they are computed in floating point.
const GAP_TOLERANCE: f64 = 1e-9;

/// Contacts kept per step; beyond it, a deeper contact replaces the least deep.
pub const MAX_CONTACTS: usize = 128;

/// Clears the contacts and, when the model has pairs to test, starts a detection: decides the
/// plane groups with `reach` (see [`judge_groups`]), which becomes every moving geom's bound, and
/// forgets the last detection's poses and bounds (by its `stamp`). Unless every group is apart it
/// poses all moving geoms; else none (they are posed as pairs need them). None when there is
/// nothing to test, else whether every group is apart.
fn begin(m: &Model, kin: &KinData, out: &mut CollisionData, reach: f64) -> Option<bool> {
    out.contacts.clear();
    out.gap_skips = 0;
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

/// Whether geom g's centre (and a plane's axes) is posed for the current detection.
#[inline(always)]
fn posed(cd: &CollisionData, g: usize) -> bool {
    cd.posed_at[g] >= cd.stamp
}

/// Whether geom g's own bound is in [`CollisionData::geom_reach`] for the current detection.
#[inline(always)]
fn has_own_reach(cd: &CollisionData, g: usize) -> bool {
    cd.reach_at[g] >= cd.stamp
}

/// Geom g's bound on how far its points move within the step: its own where computed, else the
/// shared one.
#[inline(always)]
fn reach(cd: &CollisionData, g: usize) -> f64 {
    if has_own_reach(cd, g) { cd.geom_reach[g] } else { cd.shared_reach }
}

/// Computes geom g's own bound (with the shared one) unless it already is.
#[inline(always)]
fn own_reach_of(m: &Model, kin: &KinData, aba: &AbaData, cd: &mut CollisionData, g: usize) {
    if !has_own_reach(cd, g) {
        cd.geom_reach[g] = cd.shared_reach.min(own_reach(m, kin, aba, cd, g));
        cd.reach_at[g] = cd.stamp;
    }
}

/// Decides each plane group: apart when its subtree's sphere stays farther above the plane than
/// its radius and `reach` (a bound on how far any of its points moves).
fn judge_groups(m: &Model, kin: &KinData, out: &mut CollisionData, reach: f64) {
    for (apart, g) in out.group_apart.iter_mut().zip(&m.plane_groups) {
        let height = (kin.xpos[g.body] - out.geom_xpos[g.plane]).dot(out.geom_xmat[g.plane].col(2));
        *apart = height > g.radius + reach;
    }
}

/// Poses geom g's centre (and a plane's axes) for the configuration in `kin`.
#[inline(always)]
fn pose(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    let b = m.geom_body[g];
    cd.geom_xpos[g] = kin.xpos[b] + kin.xmat[b] * m.geom_pos[g];
    pose_plane(m, kin, cd, g);
    cd.posed_at[g] = cd.stamp;
}

/// The broadphase reads a plane's normal: its axes are posed with its centre (other geoms' when a
/// pair needs them).
#[inline(always)]
fn pose_plane(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    if m.geom_type[g] == GeomType::Plane {
        cd.geom_xmat[g] = kin.xmat[m.geom_body[g]] * m.geom_mat[g];
        cd.axes_at[g] = cd.stamp;
    }
}

/// Poses the world axes of geom g for the configuration in `kin`, unless already done (a
/// sphere's orientation is never read).
fn pose_axes(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    if cd.axes_at[g] < cd.stamp && !matches!(m.geom_type[g], GeomType::Sphere | GeomType::Ellipsoid) {
        cd.geom_xmat[g] = kin.xmat[m.geom_body[g]] * m.geom_mat[g];
        cd.axes_at[g] = cd.stamp;
    }
}

/// Whether geom g never moves (a world geom, or a plane: a plane's motion is not tracked).
fn fixed(m: &Model, g: usize) -> bool {
    m.body_node[m.geom_body[g]] == WORLD || m.geom_type[g] == GeomType::Plane
}

/// Bound on the speed of any point of any moving geom whose joint speeds are at most `speeds`
/// (nv), from [`Model::dof_arm`]: O(nv), no kinematics; ∞ when an arm is unbounded (0 · ∞ gives
/// NaN, taken as ∞ too).
fn arm_speed(m: &Model, speeds: impl Iterator<Item = f64>) -> f64 {
    let s: f64 = m.dof_arm.iter().zip(speeds).map(|(c, v)| c * v).sum();
    if s.is_nan() { f64::INFINITY } else { s }
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
    let shared = m.opt.lever() * arm_speed(m, qvel.iter().zip(qacc).map(|(v, a)| v.abs() + h * a.abs()));
    let Some(all_apart) = begin(m, kin, out, shared) else { return };
    out.gaps_current = all_apart;
    if all_apart {
        // the margin is at most p.margin + 2 shared: a larger gap spares the test
        let spare = 2.0 * shared + GAP_TOLERANCE;
        if !m.gap_pairs.is_empty() {
            let quick = quick_travel(qpos, out);
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
        return;
    }
    for g in 0..m.ngeom {
        own_reach_of(m, kin, aba, out, g);
    }
    let near = near_pairs(m, out, reach);
    for &k in &near {
        let p = &m.collision_pairs[k];
        // speculative: pairs that could close within this step (which moves a point by
        // lever × (v + h a), lever = h for semi-implicit Euler) count as contacts, so a fast foot
        // is stopped at the surface instead of being found inside it one step later
        let margin = p.margin + reach(out, p.g1) + reach(out, p.g2);
        if !apart(out, p, margin) {
            pair(m, kin, out, p.g1, p.g2, margin);
        }
    }
    out.near = near;
}

/// Pairs fewer than this are all tested on their spheres; more are swept first ([`near_pairs`]).
const SWEEP_PAIRS: usize = 256;

/// The pairs a detection with every geom posed tests on their bounds, in order, taken from
/// `out.near` (the caller puts it back): every pair of a model with fewer than [`SWEEP_PAIRS`],
/// else [`Model::pairs_unswept`] and the sphere pairs of two trees whose boxes overlap.
/// Each geom's box holds its bounding sphere grown by its margin and `reach(out, g)`; a sphere
/// pair that is not apart has overlapping boxes, so the tests that follow find the contacts the
/// test of every pair finds. The boxes are swept along x (sort and sweep, Baraff 1992, §6.2),
/// from the last sweep's order: an insertion sort then costs little. Geoms of non-finite boxes
/// (a diverging world) send every pair to its test.
fn near_pairs(m: &Model, out: &mut CollisionData, reach: impl Fn(&CollisionData, usize) -> f64) -> Vec<usize> {
    let mut near = std::mem::take(&mut out.near);
    if m.collision_pairs.len() < SWEEP_PAIRS {
        return near;
    }
    near.clear();
    let mut finite = true;
    let mut sweep = std::mem::take(&mut out.sweep);
    for b in sweep.iter_mut() {
        let g = b.geom;
        let e = m.geom_rbound[g] + m.geom_margin[g] + reach(out, g);
        let c = out.geom_xpos[g];
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
            if overlap && (a.tree != b.tree || a.tree == WORLD) && let Some(k) = pair_of(m, a.geom.min(b.geom), a.geom.max(b.geom)) {
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

/// A geom's box in the sweep ([`near_pairs`]): its corners, the geom and its tree
/// ([`Model::node_tree`] of its body's node, or [`WORLD`]).
#[derive(Clone, Copy, Debug)]
struct SweepBox {
    lo: DVec3,
    hi: DVec3,
    geom: usize,
    tree: usize,
}

/// The index in `m.collision_pairs` of the pair of geoms i < j, if they make one.
fn pair_of(m: &Model, i: usize, j: usize) -> Option<usize> {
    let bit = i * m.ngeom + j;
    if !m.pair_bits.is_empty() && m.pair_bits[bit / 64] & (1 << (bit % 64)) == 0 {
        return None;
    }
    let first = m.geom_first_pair[i];
    let partners = &m.pair_partner[first..m.geom_first_pair[i + 1]];
    partners.binary_search(&(j as u32)).ok().map(|k| first + k)
}

/// Each gap pair: its gap lowered by the joints' travel since `qpos_gap` (only the joints below
/// the common ancestor change the pair's distance), the pair tested where the gap does not exceed
/// its margin plus `spare`, and the gaps made those of `qpos`.
fn lower_and_test_gaps(m: &Model, kin: &KinData, aba: &AbaData, qpos: &[f64], out: &mut CollisionData, spare: f64) {
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
fn travel(m: &Model, qpos: &[f64], out: &mut CollisionData) -> f64 {
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
        let own = if out.gaps_within_trees { t - out.top_travel[b] } else { t };
        most = most.max(own);
        unbounded |= own.is_nan();
    }
    // NaN (an unbounded arm times no change) is no bound
    if unbounded { f64::INFINITY } else { 2.0 * most }
}

/// The joints [`quick_travel`] sums over, or None when one of them is a ball or free joint.
fn quick_arms(m: &Model, within_trees: bool) -> Option<Vec<(usize, f64)>> {
    let counted = (0..m.njnt).filter(|&j| !(within_trees && m.body_parent[m.jnt_body[j]] == 0));
    counted
        .map(|j| matches!(m.jnt_type[j], JointType::Hinge | JointType::Slide).then(|| (m.jnt_qposadr[j], m.dof_arm[m.jnt_dofadr[j]])))
        .collect()
}

/// A bound on how much any gap shrank since `qpos_gap`, without the bodies' travel: Σ arm |Δq|
/// over [`CollisionData::quick_arms`] (a pair's distance changes only through the joints on the
/// paths from its common ancestor to its two bodies, disjoint sets among them); ∞ when there is
/// no such list.
fn quick_travel(qpos: &[f64], out: &CollisionData) -> f64 {
    let Some(arms) = &out.quick_arms else { return f64::INFINITY };
    let s: f64 = arms.iter().map(|&(qa, arm)| arm * (qpos[qa] - out.qpos_gap[qa]).abs()).sum();
    if s.is_nan() { f64::INFINITY } else { s }
}

/// Collision pair k while every plane group is apart: its geoms posed and bounded as needed, the
/// pair tested. Returns a lower bound on the distance between its geoms where it exceeds `spare`
/// (where it can spare the next test of a [`PairTest::Spheres`] pair), else −∞ or less.
fn test_lazily(m: &Model, kin: &KinData, aba: &AbaData, out: &mut CollisionData, k: usize, spare: f64) -> f64 {
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
    if apart(out, p, margin) { spheres_gap(out, p, spare) } else { pair(m, kin, out, p.g1, p.g2, margin) }
}

/// The distance between a pair's bounding spheres where it exceeds `spare`, else −∞ (also for
/// a pair that is not [`PairTest::Spheres`]): the square root only where it pays.
#[inline(always)]
fn spheres_gap(out: &CollisionData, p: &GeomPair, spare: f64) -> f64 {
    if p.test != PairTest::Spheres {
        return f64::NEG_INFINITY;
    }
    let d2 = out.geom_xpos[p.g1].distance_squared(out.geom_xpos[p.g2]);
    let far = p.radii + spare;
    if d2 > far * far { d2.sqrt() - p.radii } else { f64::NEG_INFINITY }
}

/// Geom g's own bound on how far its points move within the step.
#[inline(always)]
fn own_reach(m: &Model, kin: &KinData, aba: &AbaData, out: &CollisionData, g: usize) -> f64 {
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

/// Contacts of the configuration in `kin` that penetrate (dist < 0) — no speculative margin; for
/// checking a configuration after the step.
pub fn penetrations(m: &Model, kin: &KinData, out: &mut CollisionData) {
    let Some(all_apart) = begin(m, kin, out, 0.0) else { return };
    if !all_apart {
        let near = near_pairs(m, out, |_, _| 0.0);
        for &k in &near {
            let p = &m.collision_pairs[k];
            if !apart(out, p, 0.0) {
                pair(m, kin, out, p.g1, p.g2, 0.0);
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
            pair(m, kin, out, p.g1, p.g2, 0.0);
        }
    }
}

/// Broadphase: the pair's plane group apart, or bounding spheres farther apart than `margin`, or a
/// bounding sphere that far above a plane.
#[inline(always)]
fn apart(cd: &CollisionData, p: &GeomPair, margin: f64) -> bool {
    let reach = p.radii + margin;
    match p.test {
        PairTest::Spheres => cd.geom_xpos[p.g1].distance_squared(cd.geom_xpos[p.g2]) > reach * reach,
        PairTest::Plane { plane, other, group } => {
            group.is_some_and(|g| cd.group_apart[g]) || (cd.geom_xpos[other] - cd.geom_xpos[plane]).dot(cd.geom_xmat[plane].col(2)) > reach
        }
        PairTest::Always => false,
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
    // one bound for every geom point decides the groups and settles most gap pairs
    let reach = lever * arm_speed(m, qvel_end.iter().map(|v| v.abs()));
    judge_groups(m, kin, out, reach);
    let mut found = false;
    if !out.group_apart.iter().all(|&a| a) {
        end_speeds(m, kin, qvel_end, v_end, out);
        let near = near_pairs(m, out, |out, g| lever * out.geom_speed_end[g]);
        for &k in &near {
            let Some(more) = test_again(m, kin, out, k, lever) else { break };
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
        let Some(more) = test_again(m, kin, out, k, lever) else { break };
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
fn test_again(m: &Model, kin: &KinData, out: &mut CollisionData, k: usize, lever: f64) -> Option<bool> {
    let p = &m.collision_pairs[k];
    let (i, j) = (p.g1, p.g2);
    let reach = lever * (out.geom_speed_end[i] + out.geom_speed_end[j]);
    let margin = p.margin + reach;
    if reach <= self::reach(out, i) + self::reach(out, j) || apart(out, p, margin) {
        return Some(false);
    }
    let before = out.contacts.len();
    if before >= MAX_CONTACTS {
        // full: a replacement would change contacts the rows already refer to
        return None;
    }
    pair(m, kin, out, i, j, margin);
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
