//! The rows of a step, `a = K f + b` (Kokkevis 2004, eq. 11), as a struct of arrays: what each
//! row constrains, where it acts and its Jacobian, with the row geometry the other stages share.

use glam::DVec3;

use crate::dynamics::kinematics::{point_accel, KinData};
use crate::math::{Force, Motion};
use crate::model::{Model, WORLD};

/// What a row constrains.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowKind {
    /// Contact normal: f ≥ 0, separation acceleration ≥ desired.
    Normal,
    /// Friction along one direction (seed eqs. 20–21); `normal` is its contact's normal row, whose
    /// λ it shares with the contact's other friction rows.
    Tangent {
        /// Index of the contact's normal row.
        normal: usize,
    },
    /// Friction against the contact's relative turning about `dir` (MuJoCo's condim 4 and 6):
    /// torsional about the normal, rolling about a tangent. One of a ± pair of couples, bounded
    /// with its group's other rows by μ f_n (μ the torsional or rolling coefficient, a length)
    /// through the λ owned by row `cone`, the group's first row, as the sliding rows are by the
    /// normal's (seed eqs. 20–21 with a λ per group).
    Spin {
        /// Index of the contact's normal row.
        normal: usize,
        /// The row owning the group's λ.
        cone: usize,
    },
    /// A joint's limit (source: the joint) or a tendon's (source: njnt + the tendon, its J the
    /// row's `terms`): the force pushes away from the limit.
    Limit,
    /// Motion control (trajectory following): one of a ± pair of rows on an actuated joint that
    /// together make its acceleration equal the desired one, the torque bounded by the motor's
    /// limit when `bounded` (Kokkevis 2004, §8.3).
    Motion {
        /// Whether |torque| ≤ the actuator's limit.
        bounded: bool,
    },
    /// Dry friction of a dof (MuJoCo's `frictionloss`): one of a ± pair of rows that together hold
    /// the dof at rest, each force at most its friction loss, as a contact's friction rows hold a
    /// contact with μ f_n: below the breakaway force the dof does not move at all. A tendon's
    /// (source: nv + the tendon, its J the row's `terms`) holds its length so.
    DryFriction,
    /// A joint or tendon equality: one of a ± pair of rows on its dofs (the row's `terms`) that
    /// together hold x₁ − x₁⁰ − poly(x₂ − x₂⁰) at zero, the force free in sign.
    Equality,
    /// A connect or weld equality along one world axis: one of a ± pair of rows that together
    /// hold the two bodies' points together along it (a point row like a contact's, its sides'
    /// points `arm` and `arm2`), or, `angular`, a weld's bodies' relative rotation about it at
    /// zero (a pure couple); the force free in sign.
    Connect {
        /// A rotation row.
        angular: bool,
    },
}

impl RowKind {
    /// Contact rows (normal and friction), as opposed to joint rows (limits, motion control).
    pub fn is_contact(self) -> bool {
        matches!(self, RowKind::Normal | RowKind::Tangent { .. } | RowKind::Spin { .. })
    }

    /// Contact friction rows: sliding, torsional and rolling.
    pub fn is_friction(self) -> bool {
        matches!(self, RowKind::Tangent { .. } | RowKind::Spin { .. })
    }

    /// Rows whose Jacobian is a pure couple (a weld's rotation rows, torsional and rolling
    /// friction): their measure is the sides' relative angular acceleration.
    pub fn is_couple(self) -> bool {
        matches!(self, RowKind::Connect { angular: true } | RowKind::Spin { .. })
    }

    /// Rows whose Jacobian is a spatial force at each side's node (contacts and connects), as
    /// opposed to torques on dofs.
    pub fn is_point(self) -> bool {
        matches!(self, RowKind::Normal | RowKind::Tangent { .. } | RowKind::Spin { .. } | RowKind::Connect { .. })
    }
}

/// Least approach speed of an impact (m/s); see [`impact_speed`].
pub const IMPACT_SPEED: f64 = 1e-3;

/// Approach speed above which a contact or limit closing within the step triggers the impact solve
/// (needImpact, Kokkevis 2004, §8.1) and gets restitution: a few steps' worth of gravity (4 h g),
/// at least [`IMPACT_SPEED`]. Slower approaches, such as a resting contact's jitter, are stopped
/// at the surface by the acceleration-level solve itself, whose desired acceleration
/// (−d/h − v)/h ends the step at the gap: the same plastic outcome, one LCP instead of two.
pub fn impact_speed(h: f64, gravity: f64) -> f64 {
    (4.0 * h * gravity).max(IMPACT_SPEED)
}
/// Time over which a violation (penetration, limit overshoot) is removed: the desired velocity is
/// −d / T. A time, not a fraction per step, so that the motion converges as the step shrinks; at
/// least 5 steps, so a coarse step does not overshoot. Penetration beyond the post-stabilisation
/// slop is removed at the step's end instead.
pub fn correction_velocity(dist: f64, h: f64) -> f64 {
    -dist / (5.0 * h).max(CORRECTION_TIME)
}

/// End-of-step velocity a row at gap `dist` asks for without restitution: the velocity that just
/// closes a gap over `lever` ([`crate::model::Options::lever`]), or the correction of the
/// penetration `dist_start` the step began with ([`ConstraintData::dist_start`]; under leapfrog
/// the gap is the midpoint's, and a penetration its opening drift made gets no correcting
/// velocity, which would rebound a plastic impact: post-stabilisation moves it out).
pub fn closing_velocity(dist: f64, dist_start: f64, h: f64, lever: f64) -> f64 {
    if dist > 0.0 {
        -dist / lever
    } else {
        correction_velocity(dist_start.min(0.0), h)
    }
}

/// See [`correction_velocity`] (s).
pub const CORRECTION_TIME: f64 = 0.05;
/// Slip speed (`constraint::rows`) above which friction takes the direction opposite the slip.
pub const SLIDING_SPEED: f64 = 1e-6;

/// The rows of one step and their K, b and desired values, with scratch for the test forces.
/// The rows are a struct of arrays (row j is entry j of each per-row vector), grown by one
/// `push` and emptied by one `clear`.
#[derive(Clone, Debug, Default)]
pub struct ConstraintData {
    /// Row kinds.
    pub kind: Vec<RowKind>,
    /// Node of side 1 (or [`WORLD`]), side 2 for contacts.
    pub node: Vec<[usize; 2]>,
    /// Tree of each side ([`Model::node_tree`], or [`WORLD`]): a joint row's in side 1. Rows of
    /// separate trees have zero K entries.
    pub tree: Vec<[usize; 2]>,
    /// Point of application in each side's node coordinates.
    pub point: Vec<[DVec3; 2]>,
    /// Jacobian row per side, as the spatial force a unit row force applies to that side's node
    /// (world coordinates about `KinData::origin`): the row's velocity is Σ v_n · jac and a test force is −jac.
    pub jac: Vec<[Force; 2]>,
    /// Force direction in world coordinates (contacts).
    pub dir: Vec<DVec3>,
    /// Contact point relative to `KinData::origin`, world coordinates (contacts): where `jac`
    /// applies `dir` on both sides.
    pub arm: Vec<DVec3>,
    /// Side 2's point relative to `KinData::origin` where it differs from `arm` (connects).
    pub arm2: Vec<DVec3>,
    /// Dof and sign (limits).
    pub dof: Vec<(usize, f64)>,
    /// A joint row's Jacobian as (dof, coefficient) terms where it has more than its `dof`
    /// (equalities, tendon limits and friction): `terms[start..start + len]` with (start, len) =
    /// `term_span[j]` (empty for the other rows).
    pub terms: Vec<(usize, f64)>,
    /// See `terms`.
    pub term_span: Vec<(usize, usize)>,
    /// J̇ q̇ of a row with terms whose J varies with the configuration (a spatial tendon's), else 0.
    pub jdot: Vec<f64>,
    /// Friction coefficient (tangent rows).
    pub mu: Vec<f64>,
    /// Relative velocity along the row.
    pub vel: Vec<f64>,
    /// Desired acceleration along the row (motion-control rows).
    pub desired: Vec<f64>,
    /// Largest force of a bounded motion-control row.
    pub cap: Vec<f64>,
    /// Signed distance (normal and limit rows).
    pub dist: Vec<f64>,
    /// The distance before leapfrog's opening drift, dist − (h − lever)·(the row's velocity at the
    /// step's starting q̇), which an impact does not change; = dist for the other integrators.
    pub dist_start: Vec<f64>,
    /// Velocity added to a normal row's end-of-step target so that the gap after q ← q ⊕ lever q̇⁺
    /// is at least the row's linear prediction (`arc_lift`); to an equality's or connect's, the
    /// error's second-order change over that drift (`rows::second_order_lift`); zero for the
    /// other rows.
    pub lift: Vec<f64>,
    /// Per side, the point whose motion the gap follows, in node coordinates (normal rows): a
    /// sphere's or capsule's centre of curvature, else the contact point itself.
    pub centre: Vec<[DVec3; 2]>,
    /// Source contact index (contacts) or joint (limits).
    pub source: Vec<usize>,
    /// Row whose force direction is the negation of this one's (pyramid ±t), or usize::MAX: its
    /// K column and Δq̈ are that row's, negated, with no test force pushed.
    pub mirror: Vec<usize>,
    /// K by blocks: the rows of trees that rows link (a character and what touches it) make one
    /// block, K being zero between blocks; each block is kept whole, row-major over its rows in
    /// row order ([`k_index`](Self::k_index)). `K_jk` = acceleration of row j per unit force of
    /// row k = `K_kj` (K is symmetric). Row k is written, between rows that share a tree, when
    /// row k's test force is pushed ([`column_done`](Self::column_done)): the row of a row not
    /// pushed is read as its column, and is never read itself. In a block of several trees a row
    /// is zeroed as its test force is pushed, so that its entries at rows of no shared tree read
    /// zero.
    pub k: Vec<f64>,
    /// Block of each row in `k`.
    pub k_block: Vec<usize>,
    /// Place of each row among its block's rows.
    pub k_pos: Vec<usize>,
    /// Per block: where it starts in `k`, and its number of rows.
    pub k_start: Vec<usize>,
    /// See `k_start`.
    pub k_size: Vec<usize>,
    /// Constraint acceleration with zero constraint force.
    pub b: Vec<f64>,
    /// Δq̈ per unit force of each row (m × nv), meaningful on the dofs of the row's trees only
    /// ([`tree_dofs`](super::test_forces::tree_dofs); it is zero elsewhere and those entries are not kept).
    pub dqdd: Vec<f64>,
    /// The change per unit force of each row of the torque holding each joint held still
    /// (`AbaData::locked`), at its dof (m × nv), meaningful at the held dofs of the row's trees.
    pub held_torque: Vec<f64>,
    /// Whether `k`, `dqdd` and `column_done` are sized for the current rows.
    pub assembled: bool,
    /// Whether column k of K and Δq̈ of row k hold row k's test-force response (computed only
    /// for the rows a solve needs: [`responses`](super::test_forces::responses)).
    pub column_done: Vec<bool>,
    /// The test forces' delta pass.
    pub(super) delta: super::delta_pass::DeltaScratch,
    /// Per node: spatial acceleration with q̈ = 0 and no gravity (velocity products alone).
    pub(super) a_vp: Vec<Motion>,
    /// The rows of each tree (by its root node; a row touching two trees is in both lists):
    /// `tree_rows[tree_row_start[t]..tree_row_start[t + 1]]`, built with K.
    pub(super) tree_row_start: Vec<usize>,
    pub(super) tree_rows: Vec<usize>,
    /// Per node: the block of the rows whose trees are rooted in its union–find set (scratch for
    /// [`prepare`]), and the union–find forest itself.
    pub(super) block_of_root: Vec<usize>,
    pub(super) tree_link: Vec<usize>,
    /// Per block: its first row's tree, and whether a row of another tree is in it (scratch for
    /// [`prepare`]).
    pub(super) block_tree: Vec<(usize, bool)>,
}

impl ConstraintData {
    /// Empty rows, scratch sized for `m`.
    pub fn new(m: &Model) -> Self {
        ConstraintData {
            delta: super::delta_pass::DeltaScratch::new(m),
            a_vp: vec![Motion::ZERO; m.nnode],
            ..Default::default()
        }
    }

    /// Row j's (dof, coefficient) terms: its `terms`, or a joint row's one dof and sign.
    pub fn joint_terms(&self, j: usize) -> &[(usize, f64)] {
        match self.term_span[j] {
            (_, 0) => std::slice::from_ref(&self.dof[j]),
            (start, len) => &self.terms[start..start + len],
        }
    }

    /// Joint row j's rate over its terms: a single dof's, signed, or Σ coef · x\[dof\].
    #[inline]
    pub fn joint_rate(&self, j: usize, x: &[f64]) -> f64 {
        match self.term_span[j].1 {
            0 => self.dof[j].1 * x[self.dof[j].0],
            _ => self.joint_terms(j).iter().map(|&(dof, c)| c * x[dof]).sum(),
        }
    }

    /// Appends a term to the last row's Jacobian; a term on a second tree becomes the row's
    /// second tree.
    pub(super) fn add_term(&mut self, m: &Model, dof: usize, coef: f64) {
        let j = self.len() - 1;
        self.terms.push((dof, coef));
        self.term_span[j].1 += 1;
        let tree = m.node_tree[m.jnt_node[m.dof_jnt[dof]]];
        if self.tree[j][0] != tree && self.tree[j][1] == WORLD {
            self.tree[j][1] = tree;
        }
    }

    /// Index in [`k`](Self::k) of `K_jk`, for rows j and k of one block.
    #[inline(always)]
    pub fn k_index(&self, j: usize, k: usize) -> usize {
        let b = self.k_block[j];
        self.k_start[b] + self.k_pos[j] * self.k_size[b] + self.k_pos[k]
    }

    /// `K_jk` (zero between blocks).
    #[inline]
    pub fn k_at(&self, j: usize, k: usize) -> f64 {
        if self.k_block[j] == self.k_block[k] { self.k[self.k_index(j, k)] } else { 0.0 }
    }

    /// Row j of K over its block's rows (in row order).
    #[inline]
    pub fn k_row(&self, j: usize) -> &[f64] {
        let (b, pos) = (self.k_block[j], self.k_pos[j]);
        let start = self.k_start[b] + pos * self.k_size[b];
        &self.k[start..start + self.k_size[b]]
    }

    /// K whole (rows × rows, row-major), for inspection.
    pub fn k_dense(&self) -> Vec<f64> {
        let nr = self.len();
        (0..nr * nr).map(|i| self.k_at(i / nr, i % nr)).collect()
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.kind.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.kind.is_empty()
    }

    /// The least and the greatest row that shares a tree with row j (K_jk is zero for every k
    /// outside them); valid once [`prepare`](super::test_forces::prepare)d.
    pub fn sharing_span(&self, j: usize) -> (usize, usize) {
        let (first, second, _) = tree_lists(self, self.tree[j]);
        let ends = |l: &[usize]| (l.first().copied().unwrap_or(usize::MAX), l.last().copied().unwrap_or(0));
        let ((lo1, hi1), (lo2, hi2)) = (ends(first), ends(second));
        (lo1.min(lo2), hi1.max(hi2))
    }

    /// Removes all rows.
    pub fn clear(&mut self) {
        self.assembled = false;
        self.kind.clear();
        self.node.clear();
        self.tree.clear();
        self.point.clear();
        self.jac.clear();
        self.dir.clear();
        self.arm.clear();
        self.arm2.clear();
        self.dof.clear();
        self.terms.clear();
        self.term_span.clear();
        self.jdot.clear();
        self.mu.clear();
        self.vel.clear();
        self.desired.clear();
        self.cap.clear();
        self.dist.clear();
        self.dist_start.clear();
        self.lift.clear();
        self.centre.clear();
        self.source.clear();
        self.mirror.clear();
    }

    /// Appends a row: every per-row vector grows by one here, and only here.
    pub(super) fn push(&mut self, m: &Model, row: NewRow) {
        let NewRow { kind, node, point, dir, dof, mu, source } = row;
        let tree_of = |n: usize| if n == WORLD { WORLD } else { m.node_tree[n] };
        self.kind.push(kind);
        self.node.push(node);
        self.tree.push(match kind {
            RowKind::Normal | RowKind::Tangent { .. } | RowKind::Spin { .. } | RowKind::Connect { .. } => node.map(tree_of),
            RowKind::Limit | RowKind::Motion { .. } | RowKind::DryFriction | RowKind::Equality => [tree_of(m.jnt_node[m.dof_jnt[dof.0]]), WORLD],
        });
        self.term_span.push((self.terms.len(), 0));
        self.jdot.push(0.0);
        self.point.push(point);
        self.jac.push([Force::ZERO; 2]);
        self.dir.push(dir);
        self.arm.push(DVec3::ZERO);
        self.arm2.push(DVec3::ZERO);
        self.dof.push(dof);
        self.mu.push(mu);
        self.vel.push(0.0);
        self.desired.push(0.0);
        self.cap.push(f64::INFINITY);
        self.dist.push(0.0);
        self.dist_start.push(0.0);
        self.lift.push(0.0);
        self.centre.push(point);
        self.source.push(source);
        self.mirror.push(usize::MAX);
    }
}

/// What a row's builder decides; the rest of the row starts at its default.
pub(super) struct NewRow {
    pub(super) kind: RowKind,
    pub(super) node: [usize; 2],
    pub(super) point: [DVec3; 2],
    pub(super) dir: DVec3,
    pub(super) dof: (usize, f64),
    pub(super) mu: f64,
    pub(super) source: usize,
}

impl NewRow {
    /// A contact row of contact `source` along `dir` between `point`s on `node`s.
    pub(super) fn contact(kind: RowKind, node: [usize; 2], point: [DVec3; 2], dir: DVec3, mu: f64, source: usize) -> NewRow {
        NewRow { kind, node, point, dir, dof: (0, 0.0), mu, source }
    }

    /// A joint row (limit or motion control) of `source` on dof `dof.0` in direction `dof.1`.
    pub(super) fn joint(kind: RowKind, dof: (usize, f64), source: usize) -> NewRow {
        NewRow { kind, node: [WORLD, WORLD], point: [DVec3::ZERO; 2], dir: DVec3::ZERO, dof, mu: 0.0, source }
    }
}

pub(super) fn node_of_geom(m: &Model, g: usize) -> usize {
    m.body_node[m.geom_body[g]]
}

/// The end-of-step target's lift of normal row j. The row predicts the gap after
/// q ← q ⊕ lever q̇⁺ linearly, counting the contact point's velocity-product acceleration J̇_p q̇·n
/// for a time h; the gap follows the centres (`ConstraintData::centre`), which move on arcs of
/// second order ½ lever² J̇_c q̇·n. The difference, h J̇_p q̇·n − ½ lever J̇_c q̇·n as a velocity, is
/// added to the target where positive (a point on a turning sphere, whose centripetal
/// acceleration J̇_p adds to the centre's, would otherwise let the sphere sink by ½ h² r ω²).
pub(super) fn arc_lift(kin: &KinData, out: &ConstraintData, j: usize, h: f64, lever: f64) -> f64 {
    let [arc_point, arc_centre] = arcs(kin, out, j);
    (h * arc_point - 0.5 * lever * arc_centre).max(0.0)
}

/// J̇ q̇ · n of normal row j's contact points and of its centres, relative (side 1 − side 2).
pub fn arcs(kin: &KinData, out: &ConstraintData, j: usize) -> [f64; 2] {
    let n = out.node[j];
    let vp = |side: usize, p: DVec3| point_accel(kin, &out.a_vp, DVec3::ZERO, n[side], kin.rel(n[side], p));
    let arc = |p: [DVec3; 2]| out.dir[j].dot(vp(0, p[0]) - vp(1, p[1]));
    let at_point = arc(out.point[j]);
    // a centre is the point itself but on a sphere or capsule
    [at_point, if out.centre[j] == out.point[j] { at_point } else { arc(out.centre[j]) }]
}

/// The contact row's spatial forces on its two nodes per unit force along world direction `dir`
/// (+dir on side 1, −dir on side 2) at the points `r` (relative to the kinematics' origin, in
/// whose coordinates the forces are).
pub fn jacobian(nodes: [usize; 2], r: [DVec3; 2], dir: [DVec3; 2]) -> [Force; 2] {
    let mut jac = [Force::ZERO; 2];
    for side in 0..2 {
        if nodes[side] != WORLD {
            let sgn = if side == 0 { 1.0 } else { -1.0 };
            jac[side] = Force::at_point(r[side], dir[side] * sgn);
        }
    }
    jac
}

/// The rows of the trees `trees` ([`WORLD`]: none): the first tree's list, the second's (empty
/// when the same), and the first tree, whose rows the second list repeats (a row of both trees is
/// in both lists).
#[inline(always)]
pub(super) fn tree_lists(out: &ConstraintData, trees: [usize; 2]) -> (&[usize], &[usize], usize) {
    let list = |t: usize| if t == WORLD { &[][..] } else { &out.tree_rows[out.tree_row_start[t]..out.tree_row_start[t + 1]] };
    let [a, b] = trees;
    (list(a), if b == a { &[][..] } else { list(b) }, a)
}
