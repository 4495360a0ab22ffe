//! What collision detection keeps per world: geom poses and bounds stamped by detection, the
//! pairs' gaps, the sweep's boxes and the contacts found.

use glam::{DMat3, DVec3};

use crate::dynamics::kinematics::KinData;
use crate::model::{GeomType, Model, PairFriction, WORLD};

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
    /// Friction: sliding, torsional and rolling, as the pair's condim asks.
    pub friction: PairFriction,
}

/// World poses of all geoms, the pairs' gaps, and the contact list.
#[derive(Clone, Debug, Default)]
pub struct CollisionData {
    /// Geom axes in world (ngeom); a moving geom's are current only where `axes_at` says so.
    pub geom_xmat: Vec<DMat3>,
    /// The detection (`stamp`) `geom_xmat[g]` was posed in (u64::MAX: a world geom, posed for
    /// good): the narrowphase poses the axes of the geoms it tests, so pairs the broadphase
    /// rejects cost no rotation.
    pub(super) axes_at: Vec<u64>,
    /// Geom centre in world (ngeom); a moving geom's is current only where `posed_at` says so.
    pub geom_xpos: Vec<DVec3>,
    /// The detection `geom_xpos[g]` (and a plane's axes) was posed in: while every plane group is
    /// apart, geoms are posed only for the pairs tested.
    pub(super) posed_at: Vec<u64>,
    /// Number of the current detection: a flag of the last one is forgotten by counting, not by
    /// clearing every geom's.
    pub(super) stamp: u64,
    /// Per [`crate::model::PlaneGroup`]: whether its subtree is apart from its plane.
    pub(super) group_apart: Vec<bool>,
    /// Geom g's own bound on how far any of its points can move within the step, from its speed
    /// and constraint-free acceleration (ngeom), taken with the bound shared by all moving geoms
    /// (the smaller): current where `reach_at` says so, else `shared_reach` holds ([`reach`]).
    /// Fixed geoms: 0.
    pub(super) geom_reach: Vec<f64>,
    /// The detection `geom_reach[g]` was computed in (u64::MAX: a fixed geom): it is computed for
    /// the geoms of the pairs that the shared bound does not settle.
    pub(super) reach_at: Vec<u64>,
    /// The bound shared by all moving geoms in the current detection.
    pub(super) shared_reach: f64,
    /// Bound on the speed of any point of each geom at the end of the step (ngeom).
    pub geom_speed_end: Vec<f64>,
    /// Per [`crate::model::GapPair`]: a lower bound on the distance between its geoms at
    /// `qpos_gap` (−∞ when unknown).
    pub(super) pair_gap: Vec<f64>,
    /// The configuration the gaps were last lowered to (nq).
    pub(super) qpos_gap: Vec<f64>,
    /// How far the joints from the world to each body have moved any geom point of the body's
    /// subtree since `qpos_gap`, summed along the chain (nbody).
    pub(super) body_travel: Vec<f64>,
    /// `body_travel` of the child of the world each body descends from (nbody).
    pub(super) top_travel: Vec<f64>,
    /// Whether `pair_gap` less `shrink` bounds the distances at the configuration of the last
    /// detection (which keeps the gaps only while every plane group is apart).
    pub(super) gaps_current: bool,
    /// The least of `pair_gap[i]` less the pair's margin: when it exceeds what the joints' travel
    /// since `qpos_gap` can take off any gap plus the largest margin, every gap pair is settled at
    /// once and the gaps stay those of `qpos_gap`.
    pub(super) least_slack: f64,
    /// How much any gap may have shrunk between `qpos_gap` and the last detection's configuration.
    pub(super) shrink: f64,
    /// Whether the joints' arms bound the geoms' motion at the last detection's configuration
    /// ([`Model::arms_hold`](crate::model::Model::arms_hold)).
    pub(super) arms_hold: bool,
    /// Pairs whose gap spared them a test in the last detection.
    pub gap_skips: usize,
    /// The boxes of [`Model::sweep_geoms`] by increasing `lo.x` (x: the sweep axis), as the last sweep left them
    /// (nearly sorted for the next).
    pub(super) sweep: Vec<SweepBox>,
    /// The axis the boxes are swept along (0: x, 1: y, 2: z); each box's coordinates are
    /// rotated to put it first.
    pub(super) sweep_axis: usize,
    /// The pairs of two trees whose boxes overlap, as the sweep finds them ([`near_pairs`]).
    pub(super) swept: Vec<usize>,
    /// The pairs the sweep leaves to test, in order ([`near_pairs`]).
    pub(super) near: Vec<usize>,
    /// Pairs the detection narrowed to their relative motion's margin, with that margin, in the
    /// pairs' order.
    pub(super) narrowed: Vec<(usize, f64)>,
    /// Per pair with a mesh, a cylinder or an ellipsoid, or of two boxes
    /// ([`crate::model::GeomPair::kept`]): what its last test found apart, which can settle its
    /// next test.
    pub(super) pair_kept: Vec<Separation>,
    /// The narrowphase's scratch.
    pub(super) scratch: Scratch,
    /// Contacts of this configuration.
    pub contacts: Vec<Contact>,
}

impl CollisionData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
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
            gaps_current: false,
            least_slack: f64::NEG_INFINITY,
            shrink: 0.0,
            arms_hold: true,
            gap_skips: 0,
            sweep: m.sweep_geoms.iter().map(|&g| SweepBox { lo: DVec3::ZERO, hi: DVec3::ZERO, geom: g }).collect(),
            sweep_axis: 0,
            swept: Vec::with_capacity(if m.collision_pairs.len() < SWEEP_PAIRS { 0 } else { m.collision_pairs.len() }),
            // a model of few pairs tests them all, listed once here
            near: if m.collision_pairs.len() < SWEEP_PAIRS { (0..m.collision_pairs.len()).collect() } else { Vec::with_capacity(m.collision_pairs.len()) },
            narrowed: Vec::new(),
            pair_kept: vec![Separation::Unknown; m.collision_pairs.iter().filter(|p| p.kept.is_some()).count()],
            scratch: Scratch::sized(m.meshes.iter().map(|mesh| mesh.hull.vert.len()).max().unwrap_or(0)),
            // grown to the most a step has found (at most `Options::max_contacts`)
            contacts: Vec::new(),
        }
    }

    /// Pair tests that a separation kept from the pair's last test settled in the last
    /// detection.
    pub fn kept_skips(&self) -> usize {
        self.scratch.kept.skips
    }

    /// Forgets the contacts, the pairs' gaps and their kept separations.
    pub fn forget(&mut self) {
        self.contacts.clear();
        self.pair_kept.fill(Separation::Unknown);
        self.forget_gaps();
    }

    /// Forgets the pairs' gaps.
    pub(super) fn forget_gaps(&mut self) {
        self.pair_gap.fill(f64::NEG_INFINITY);
        self.least_slack = f64::NEG_INFINITY;
    }
}

/// Gaps are compared with this much to spare (m): they are computed in floating point.
pub(super) const GAP_TOLERANCE: f64 = 1e-9;

/// Whether geom g's centre (and a plane's axes) is posed for the current detection.
#[inline(always)]
pub(super) fn posed(cd: &CollisionData, g: usize) -> bool {
    cd.posed_at[g] >= cd.stamp
}

/// Whether geom g's own bound is in [`CollisionData::geom_reach`] for the current detection.
#[inline(always)]
pub(super) fn has_own_reach(cd: &CollisionData, g: usize) -> bool {
    cd.reach_at[g] >= cd.stamp
}

/// Geom g's bound on how far its points move within the step: its own where computed, else the
/// shared one.
#[inline(always)]
pub(super) fn reach(cd: &CollisionData, g: usize) -> f64 {
    if has_own_reach(cd, g) { cd.geom_reach[g] } else { cd.shared_reach }
}

/// Poses geom g's centre (and a plane's axes) for the configuration in `kin`.
#[inline(always)]
pub(super) fn pose(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    let b = m.geom_body[g];
    cd.geom_xpos[g] = kin.xpos[b] + kin.xmat[b] * m.geom_pos[g];
    pose_plane(m, kin, cd, g);
    cd.posed_at[g] = cd.stamp;
}

/// The broadphase reads a plane's normal: its axes are posed with its centre (other geoms' when a
/// pair needs them).
#[inline(always)]
pub(super) fn pose_plane(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    if m.geom_type[g] == GeomType::Plane {
        cd.geom_xmat[g] = kin.xmat[m.geom_body[g]] * m.geom_mat[g];
        cd.axes_at[g] = cd.stamp;
    }
}

/// Poses the world axes of geom g for the configuration in `kin`, unless already done (a
/// sphere's orientation is never read).
pub(super) fn pose_axes(m: &Model, kin: &KinData, cd: &mut CollisionData, g: usize) {
    if cd.axes_at[g] < cd.stamp && m.geom_type[g] != GeomType::Sphere {
        cd.geom_xmat[g] = kin.xmat[m.geom_body[g]] * m.geom_mat[g];
        cd.axes_at[g] = cd.stamp;
    }
}

/// Whether geom g never moves (a world geom, or a plane: a plane's motion is not tracked).
pub(super) fn fixed(m: &Model, g: usize) -> bool {
    m.body_node[m.geom_body[g]] == WORLD || m.geom_type[g] == GeomType::Plane
}

/// A geom's box in the sweep ([`near_pairs`]): its corners and the geom.
#[derive(Clone, Copy, Debug)]
pub(super) struct SweepBox {
    pub(super) lo: DVec3,
    pub(super) hi: DVec3,
    pub(super) geom: usize,
}

/// Pairs fewer than this are all tested on their spheres; more are swept first ([`near_pairs`]).
pub(super) const SWEEP_PAIRS: usize = 256;

/// What a pair's test found that holds its shapes apart, kept to settle its next test: the same
/// axis, a touch farther than the margin, proves the pair apart without the test.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum Separation {
    /// Nothing kept.
    #[default]
    Unknown,
    /// GJK's separating axis (unit, from shape 2 to shape 1): in world while its pair is tested,
    /// in the first geom's frame while kept.
    Axis(DVec3),
    /// A face of the separating-axis test's first polytope (`false`) or second (`true`); of two
    /// boxes, the first's or second's axis.
    Face(bool, u32),
}

/// The separation of the pair under test, and the tests kept separations settled in the current
/// detection.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Kept {
    pub(super) sep: Separation,
    pub(super) skips: usize,
}

/// The narrowphase's scratch, kept from one detection to the next (grown once, then reused):
/// EPA's buffers, what the pair under test keeps apart (its kept [`Separation`] on the way in,
/// the test's on the way out), and the walk over a hull's vertices near a plane.
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) epa: parry3d_f64::query::epa::EPA,
    pub(super) kept: Kept,
    /// Per vertex of the largest hull: whether the walk has met it (all false between walks).
    pub(super) met: Vec<bool>,
    /// The vertices the walk has met, and those it has still to leave from.
    pub(super) walk: (Vec<u32>, Vec<u32>),
    /// A lower bound on the distance between the pair under test where their oriented boxes
    /// parted them before GJK ran, else −∞.
    pub(super) parted: f64,
}

impl Scratch {
    /// Scratch for hulls of at most `verts` vertices.
    pub(super) fn sized(verts: usize) -> Scratch {
        Scratch { met: vec![false; verts], walk: (Vec::with_capacity(verts), Vec::with_capacity(verts)), parted: f64::NEG_INFINITY, ..Scratch::default() }
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Scratch::sized(self.met.len())
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Scratch")
    }
}
