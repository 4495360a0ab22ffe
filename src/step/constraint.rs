//! Stage 3 — constraint rows `a = K f + b` (Kokkevis 2004): contact normals (unilateral), friction in
//! the seed's one-tangent λ form (eqs. 19–21), and joint limits. Column k of K is measured by pushing
//! a unit test force of row k through the ABA quantities kept from the inward pass (I^A, U, D⁻¹):
//! a delta inward pass and a delta outward pass, no 6×6 work, O(n) per column, O(mn + m²) in all.

use glam::DVec3;

use crate::math::{Force, Motion};
use crate::model::{Actuation, FrictionModel, GeomType, Model, WORLD};

use super::aba::AbaData;
use super::collision::Contact;
use super::kinematics::KinData;

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
    /// Joint limit: torque pushes away from the limit.
    Limit,
    /// Motion control (trajectory following): one of a ± pair of rows on an actuated joint that
    /// together make its acceleration equal the desired one, the torque bounded by the motor's
    /// limit when `bounded` (Kokkevis 2004, §8.3).
    Motion {
        /// Whether |torque| ≤ the actuator's limit.
        bounded: bool,
    },
}

impl RowKind {
    /// Contact rows (normal and friction), as opposed to joint rows (limits, motion control).
    pub fn is_contact(self) -> bool {
        matches!(self, RowKind::Normal | RowKind::Tangent { .. })
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
/// Slip speed (`step::rows`) above which friction takes the direction opposite the slip.
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
    /// Dof and sign (limits).
    pub dof: Vec<(usize, f64)>,
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
    /// Velocity added to a normal row's end-of-step target (zero for the other rows) so that the
    /// gap after q ← q ⊕ lever q̇⁺ is at least the row's linear prediction (`arc_lift`).
    pub lift: Vec<f64>,
    /// Per side, the point whose motion the gap follows, in node coordinates (normal rows): a
    /// sphere's or capsule's centre of curvature, else the contact point itself.
    pub centre: Vec<[DVec3; 2]>,
    /// Source contact index (contacts) or joint (limits).
    pub source: Vec<usize>,
    /// Row whose force direction is the negation of this one's (pyramid ±t), or usize::MAX: its
    /// K column and Δq̈ are that row's, negated, with no test force pushed.
    pub mirror: Vec<usize>,
    /// K, row-major (m × m): `K[j][k]` = acceleration of row j per unit force of row k = `K[k][j]`
    /// (K is symmetric). Row k is written, between rows that share a tree, when row k's test force
    /// is pushed ([`column_done`](Self::column_done)): the row of a row not pushed is read as its
    /// column. Zero between rows of no shared tree once their block is cleared
    /// ([`clear_k_block`]; [`assemble`] clears all).
    pub k: Vec<f64>,
    /// Constraint acceleration with zero constraint force.
    pub b: Vec<f64>,
    /// Δq̈ per unit force of each row (m × nv), meaningful on the dofs of the row's trees only
    /// ([`tree_dofs`]; it is zero elsewhere and those entries are not kept).
    pub dqdd: Vec<f64>,
    /// Whether `k`, `dqdd` and `column_done` are sized for the current rows.
    pub assembled: bool,
    /// Whether column k of K and Δq̈ of row k hold row k's test-force response (computed only
    /// for the rows a solve needs: [`responses`]).
    pub column_done: Vec<bool>,
    dpa: Vec<Force>,
    du: Vec<[f64; 6]>,
    da: Vec<Motion>,
    /// Per node: spatial acceleration with q̈ = 0 and no gravity (velocity products alone).
    a_vp: Vec<Motion>,
    /// The rows of each tree (by its root node; a row touching two trees is in both lists):
    /// `tree_rows[tree_row_start[t]..tree_row_start[t + 1]]`, built with K.
    tree_row_start: Vec<usize>,
    tree_rows: Vec<usize>,
    /// The rows' trees when K was last zeroed whole ([`clear_k_block`]), or empty: test forces
    /// write K only between rows that share a tree, so for the same trees the rest is still zero.
    zeroed_trees: Vec<[usize; 2]>,
}

impl ConstraintData {
    /// Empty rows, scratch sized for `m`.
    pub fn new(m: &Model) -> Self {
        ConstraintData {
            dpa: vec![Force::ZERO; m.nnode],
            du: vec![[0.0; 6]; m.nnode],
            da: vec![Motion::ZERO; m.nnode],
            a_vp: vec![Motion::ZERO; m.nnode],
            ..Default::default()
        }
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
    /// outside them); valid once [`prepare`]d.
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
        self.dof.clear();
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
    fn push(&mut self, m: &Model, row: NewRow) {
        let NewRow { kind, node, point, dir, dof, mu, source } = row;
        let tree_of = |n: usize| if n == WORLD { WORLD } else { m.node_tree[n] };
        self.kind.push(kind);
        self.node.push(node);
        self.tree.push(match kind {
            RowKind::Normal | RowKind::Tangent { .. } => node.map(tree_of),
            RowKind::Limit | RowKind::Motion { .. } => [tree_of(m.jnt_node[m.dof_jnt[dof.0]]), WORLD],
        });
        self.point.push(point);
        self.jac.push([Force::ZERO; 2]);
        self.dir.push(dir);
        self.arm.push(DVec3::ZERO);
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
struct NewRow {
    kind: RowKind,
    node: [usize; 2],
    point: [DVec3; 2],
    dir: DVec3,
    dof: (usize, f64),
    mu: f64,
    source: usize,
}

impl NewRow {
    /// A contact row of contact `source` along `dir` between `point`s on `node`s.
    fn contact(kind: RowKind, node: [usize; 2], point: [DVec3; 2], dir: DVec3, mu: f64, source: usize) -> NewRow {
        NewRow { kind, node, point, dir, dof: (0, 0.0), mu, source }
    }

    /// A joint row (limit or motion control) of `source` on dof `dof.0` in direction `dof.1`.
    fn joint(kind: RowKind, dof: (usize, f64), source: usize) -> NewRow {
        NewRow { kind, node: [WORLD, WORLD], point: [DVec3::ZERO; 2], dir: DVec3::ZERO, dof, mu: 0.0, source }
    }
}

fn node_of_geom(m: &Model, g: usize) -> usize {
    m.body_node[m.geom_body[g]]
}

/// World classical acceleration of the point of node `n` at `r` (relative to `kin.origin`), from
/// the nodes' spatial accelerations `a`, plus `g` (the ABA's accelerations carry the base's
/// fictitious −g, which `g` adds back; the velocity products alone, J̇ q̇, take none).
#[inline]
fn point_accel(kin: &KinData, a: &[Motion], g: DVec3, n: usize, r: DVec3) -> DVec3 {
    if n == WORLD {
        return DVec3::ZERO;
    }
    let v = kin.v[n];
    a[n].point_velocity(r) + v.ang.cross(v.point_velocity(r)) + g
}

/// World velocity of the point of node `n` at `r` (relative to `kin.origin`).
fn point_vel(kin: &KinData, n: usize, r: DVec3) -> DVec3 {
    if n == WORLD { DVec3::ZERO } else { kin.v[n].point_velocity(r) }
}

/// Velocity-product accelerations a_i = a_λ + c_i (q̈ = 0, no gravity): J̇ q̇ of any point.
fn velocity_products(m: &Model, kin: &KinData, a_vp: &mut [Motion]) {
    for i in 0..m.nnode {
        let p = m.node_parent[i];
        let a_parent = if p == WORLD { Motion::ZERO } else { a_vp[p] };
        a_vp[i] = a_parent + kin.c[i];
    }
}

/// The end-of-step target's lift of normal row j. The row predicts the gap after
/// q ← q ⊕ lever q̇⁺ linearly, counting the contact point's velocity-product acceleration J̇_p q̇·n
/// for a time h; the gap follows the centres (`ConstraintData::centre`), which move on arcs of
/// second order ½ lever² J̇_c q̇·n. The difference, h J̇_p q̇·n − ½ lever J̇_c q̇·n as a velocity, is
/// added to the target where positive (a point on a turning sphere, whose centripetal
/// acceleration J̇_p adds to the centre's, would otherwise let the sphere sink by ½ h² r ω²).
fn arc_lift(kin: &KinData, out: &ConstraintData, j: usize, h: f64, lever: f64) -> f64 {
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

/// Builds the rows for `contacts`, limits active or reachable within the step (`qacc0`: the
/// constraint-free accelerations) or marked in `forced` (2 per joint: lower, upper) and, when the actuation is trajectory following,
/// motion control of every actuated joint toward `ctrl` (position targets) with feed-forward
/// velocity and acceleration `feedforward` (2 × nu). `tangent_for(i, n, v_t, a_t)` picks the
/// friction direction of contact i from its tangential velocity and constraint-free tangential
/// acceleration (the caller handles sliding, persistence and the seeded random choice).
#[allow(clippy::too_many_arguments)]
pub fn rows(
    m: &Model,
    kin: &KinData,
    aba: &AbaData,
    qpos: &[f64],
    qvel: &[f64],
    qacc0: &[f64],
    forced: &[bool],
    ctrl: &[f64],
    feedforward: &[f64],
    contacts: &[Contact],
    mut tangent_for: impl FnMut(usize, DVec3, DVec3, DVec3) -> DVec3,
    out: &mut ConstraintData,
) {
    out.clear();
    let (h, lever) = (m.opt.timestep, m.opt.lever());
    if !contacts.is_empty() {
        velocity_products(m, kin, &mut out.a_vp);
    }
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
        out.push(m, NewRow::contact(RowKind::Normal, nodes, pts, c.normal, c.mu, ci));
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
        if c.friction && c.mu > 0.0 {
            let vt = vrel - c.normal * c.normal.dot(vrel);
            let at = arel - c.normal * c.normal.dot(arel);
            let t = tangent_for(ci, c.normal, vt, at);
            // in a planar model a normal in the plane leaves one tangent line that motion can
            // use: the tangent is turned onto it, and the pyramid's rows across the plane, which
            // no force could move, are not built
            let line = m.motion_plane.filter(|p| p.dot(c.normal).abs() < 1e-9).map(|p| p.cross(c.normal).normalize());
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
                out.push(m, NewRow::contact(RowKind::Tangent { normal: normal_row }, nodes, pts, d, c.mu, ci));
                out.vel[row] = d.dot(vrel);
                out.jac[row] = jacobian(nodes, [r; 2], [d; 2]);
                out.arm[row] = r;
                if k % 2 == 1 {
                    out.mirror[row] = row - 1;
                }
            }
        }
    }
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
    if let Actuation::Trajectory { kp, kd } = m.opt.actuation {
        for a in 0..m.nu {
            let da = m.jnt_dofadr[m.actuator_jnt[a]];
            let ad = motion_target(m, a, kp, kd, qpos, qvel, ctrl, feedforward);
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
        if !out.kind[j].is_contact() {
            row[out.dof[j].0] = out.dof[j].1;
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
#[allow(clippy::too_many_arguments)]
fn motion_target(m: &Model, a: usize, kp: f64, kd: f64, qpos: &[f64], qvel: &[f64], ctrl: &[f64], feedforward: &[f64]) -> f64 {
    let j = m.actuator_jnt[a];
    let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
    feedforward[m.nu + a] + kd * (feedforward[a] - qvel[da]) + kp * (ctrl[a] - qpos[qa])
}

/// Row j's velocity J_j q̇, from the nodes' spatial velocities `v` of that `qvel`.
pub fn row_velocity(out: &ConstraintData, j: usize, v: &[Motion], qvel: &[f64]) -> f64 {
    match out.kind[j] {
        RowKind::Normal | RowKind::Tangent { .. } => {
            let side = |s: usize| if out.node[j][s] == WORLD { 0.0 } else { v[out.node[j][s]].dot(&out.jac[j][s]) };
            side(0) + side(1)
        }
        RowKind::Limit | RowKind::Motion { .. } => out.dof[j].1 * qvel[out.dof[j].0],
    }
}

/// After an impulse has changed the velocities but not the configuration: the rows' velocities,
/// motion-control targets and b at the new velocities, with the ABA of the new state. K and Δq̈
/// depend on the configuration only and are kept.
#[allow(clippy::too_many_arguments)]
pub fn refresh(m: &Model, kin: &KinData, aba: &AbaData, qpos: &[f64], qvel: &[f64], ctrl: &[f64], feedforward: &[f64], qacc0: &[f64], out: &mut ConstraintData) {
    if out.kind.contains(&RowKind::Normal) {
        velocity_products(m, kin, &mut out.a_vp);
    }
    let mut point = PointAccel::NONE;
    for j in 0..out.len() {
        if out.kind[j] == RowKind::Normal {
            out.lift[j] = arc_lift(kin, out, j, m.opt.timestep, m.opt.lever());
        }
        out.vel[j] = row_velocity(out, j, &kin.v, qvel);
        if let (RowKind::Motion { .. }, Actuation::Trajectory { kp, kd }) = (out.kind[j], m.opt.actuation) {
            out.desired[j] = out.dof[j].1 * motion_target(m, out.source[j], kp, kd, qpos, qvel, ctrl, feedforward);
        }
        out.b[j] = measure(m, kin, aba, qacc0, out, j, &mut point);
    }
}

/// Fills K (every entry: zero between rows of separate trees; by test forces), Δq̈ per unit
/// force, and b from the ABA outward-pass accelerations `aba.a` and `qacc0` of the same state.
pub fn assemble(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], out: &mut ConstraintData) {
    bias(m, kin, aba, qacc0, out);
    out.assembled = false;
    out.k.clear();
    responses(m, kin, aba, out, |_, _| true);
}

/// b alone: each row's acceleration with zero constraint force.
pub fn bias(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], out: &mut ConstraintData) {
    out.b.clear();
    let mut point = PointAccel::NONE;
    for j in 0..out.len() {
        let b = measure(m, kin, aba, qacc0, out, j, &mut point);
        out.b.push(b);
    }
}

/// K's columns and Δq̈ of the rows `needed` (by index and kind) not yet computed, by test forces (they depend on the
/// configuration, not on velocities). Each column is measured at every row, so a row left out
/// still has its accelerations under the forces of the rows computed.
pub fn responses(m: &Model, kin: &KinData, aba: &AbaData, out: &mut ConstraintData, needed: impl Fn(usize, RowKind) -> bool) {
    prepare(m, out);
    for k in 0..out.len() {
        if out.column_done[k] || !needed(k, out.kind[k]) {
            continue;
        }
        // a mirror row's column comes with its mirrored row's
        let pushed = if out.mirror[k] == usize::MAX { k } else { out.mirror[k] };
        if !out.column_done[pushed] {
            push_test_force(m, kin, aba, out, pushed);
        }
    }
}

/// Column k of K and Δq̈ of row k, from a unit test force of row k (Kokkevis 2004; δp^A = −f at
/// the point's node), and those of the row mirroring k (the next row, if it is k's mirror), their
/// negations.
fn push_test_force(m: &Model, kin: &KinData, aba: &AbaData, out: &mut ConstraintData, k: usize) {
    let (nr, nv) = (out.len(), m.nv);
    let mirrored = k + 1 < nr && out.mirror[k + 1] == k;
    // the force moves only the nodes of the row's trees
    let trees = out.tree[k];
    for range in tree_ranges(m, trees) {
        out.dpa[range].fill(Force::ZERO);
    }
    let mut dtau = None;
    match out.kind[k] {
        RowKind::Limit | RowKind::Motion { .. } => dtau = Some(out.dof[k]),
        _ => {
            for side in 0..2 {
                let n = out.node[k][side];
                if n != WORLD {
                    out.dpa[n] -= out.jac[k][side];
                }
            }
        }
    }
    delta_pass(m, kin, aba, trees, dtau, &mut out.dpa, &mut out.du, &mut out.da, &mut out.dqdd[k * nv..(k + 1) * nv]);
    // K is symmetric (J M⁻¹ Jᵀ): this force's measures at the rows of its trees are row k (and
    // its mirror's, negated), written whole (contiguous); a row pushed before holds its own
    // measure of this force; rows of other trees are not written (zero, once their block is
    // cleared: `clear_k_block`)
    let mut kk = std::mem::take(&mut out.k);
    let dqdd = &out.dqdd[k * nv..(k + 1) * nv];
    let (first, second, a) = tree_lists(out, trees);
    let mut point = PointAccel::NONE;
    // a row of both trees is in both lists: read once
    for &j in first.iter().chain(second.iter().filter(|&&j| a == WORLD || !out.tree[j].contains(&a))) {
        let v = k_entry(out, &kk, trees, dqdd, j, k, &mut point);
        kk[k * nr + j] = v;
        if mirrored {
            // (−d)·a = −(d·a) exactly: the mirror row's own measure
            kk[(k + 1) * nr + j] = -v;
        }
    }
    out.k = kk;
    out.column_done[k] = true;
    if mirrored {
        let (done, rest) = out.dqdd.split_at_mut((k + 1) * nv);
        for r in tree_dofs(m, trees) {
            for (d, s) in rest[r.clone()].iter_mut().zip(&done[k * nv + r.start..k * nv + r.end]) {
                *d = -s;
            }
        }
        out.column_done[k + 1] = true;
    }
}

/// Sizes K and Δq̈ for the rows and lists each tree's rows, once per set of rows. Test forces
/// write K only between rows that share a tree (and Δq̈ on the row's trees' dofs); the other
/// entries keep what they held: a reader of a block of K zeroes it first ([`clear_k_block`]).
pub fn prepare(m: &Model, out: &mut ConstraintData) {
    if out.assembled {
        return;
    }
    let (nr, nv) = (out.len(), m.nv);
    out.k.resize(nr * nr, 0.0);
    if out.dqdd.len() < nr * nv {
        out.dqdd.resize(nr * nv, 0.0);
    }
    out.column_done.clear();
    out.column_done.resize(nr, false);
    list_tree_rows(m.nnode, out);
    out.assembled = true;
}

/// Zeroes K between the rows `rows` (an island's, increasing), unless a column of theirs is
/// computed already (they were zeroed for an earlier solve of the same rows), or they are every
/// row, with the trees K was last zeroed whole for (K between rows of no shared tree is still
/// zero: test forces write only between rows that share one). K is then zero between those of
/// separate trees, and the row of each row pushed holds its measures.
pub fn clear_k_block(out: &mut ConstraintData, rows: &[usize]) {
    let (Some(&first), Some(&last)) = (rows.first(), rows.last()) else { return };
    if rows.iter().any(|&j| out.column_done[j]) {
        return;
    }
    let nr = out.len();
    let whole = rows.len() == nr;
    if whole && out.zeroed_trees == out.tree {
        return;
    }
    out.zeroed_trees.clear();
    if whole {
        out.zeroed_trees.extend_from_slice(&out.tree);
    }
    for &j in rows {
        let row = &mut out.k[j * nr..(j + 1) * nr];
        if last - first + 1 == rows.len() {
            row[first..=last].fill(0.0);
        } else {
            for &jj in rows {
                row[jj] = 0.0;
            }
        }
    }
}

/// [`ConstraintData`]'s lists of each tree's rows (counted, then filled: O(nnode + rows)).
fn list_tree_rows(nnode: usize, out: &mut ConstraintData) {
    let start = &mut out.tree_row_start;
    start.clear();
    start.resize(nnode + 1, 0);
    // a row's distinct trees (WORLD: none)
    let sides = |[a, b]: [usize; 2]| [a, if b == a { WORLD } else { b }];
    for &trees in &out.tree {
        for t in sides(trees) {
            if t != WORLD {
                start[t + 1] += 1;
            }
        }
    }
    for t in 0..nnode {
        start[t + 1] += start[t];
    }
    out.tree_rows.clear();
    out.tree_rows.resize(start[nnode], 0);
    // filled from each list's end, rows in reverse: each list ends up in row order
    for (j, &trees) in out.tree.iter().enumerate().rev() {
        for t in sides(trees) {
            if t != WORLD {
                start[t + 1] -= 1;
                out.tree_rows[start[t + 1]] = j;
            }
        }
    }
    // each count was taken back once per row: start[t + 1] is now where tree t's list starts,
    // so the array is shifted by one
    start.rotate_left(1);
    start[nnode] = out.tree_rows.len();
}

/// The rows of the trees `trees` ([`WORLD`]: none): the first tree's list, the second's (empty
/// when the same), and the first tree, whose rows the second list repeats (a row of both trees is
/// in both lists).
#[inline(always)]
fn tree_lists(out: &ConstraintData, trees: [usize; 2]) -> (&[usize], &[usize], usize) {
    let list = |t: usize| if t == WORLD { &[][..] } else { &out.tree_rows[out.tree_row_start[t]..out.tree_row_start[t + 1]] };
    let [a, b] = trees;
    (list(a), if b == a { &[][..] } else { list(b) }, a)
}

/// K_jk, with K's rows so far in `kk`, the test force of row k on the trees `trees` having
/// left its responses in `cd.da` and `dqdd`; `point` carries the last contact's point
/// acceleration from row to row.
#[inline(always)]
fn k_entry(cd: &ConstraintData, kk: &[f64], trees: [usize; 2], dqdd: &[f64], j: usize, k: usize, point: &mut PointAccel) -> f64 {
    if cd.column_done[j] { kk[j * cd.len() + k] } else { delta_accel(cd, trees, dqdd, j, point) }
}

/// The relative acceleration of a contact's point (side 1's less side 2's), under a test force
/// ([`delta_accel`]) or with no constraint force ([`measure`]), kept while the rows of that contact
/// (its normal row `normal` and the friction rows after it) are read in turn.
struct PointAccel {
    normal: usize,
    accel: DVec3,
}

impl PointAccel {
    /// No contact's yet.
    const NONE: PointAccel = PointAccel { normal: usize::MAX, accel: DVec3::ZERO };

    /// Row j's acceleration: a joint row's from `qacc` (its dof's, signed), a contact row's along
    /// its direction from its contact's point acceleration, `accel()` unless kept from the
    /// contact's row before.
    #[inline(always)]
    fn row(&mut self, cd: &ConstraintData, j: usize, qacc: &[f64], accel: impl FnOnce() -> DVec3) -> f64 {
        let normal = match cd.kind[j] {
            RowKind::Normal => j,
            RowKind::Tangent { normal } => normal,
            RowKind::Limit | RowKind::Motion { .. } => {
                let (dof, sign) = cd.dof[j];
                return sign * qacc[dof];
            }
        };
        if self.normal != normal {
            *self = PointAccel { normal, accel: accel() };
        }
        cd.dir[j].dot(self.accel)
    }
}

/// Whether tree `t` is one of the trees `trees` a test force moved.
#[inline]
fn moves(trees: [usize; 2], t: usize) -> bool {
    t != WORLD && (t == trees[0] || t == trees[1])
}

/// Acceleration of row j under the test force on the trees `trees` whose responses are in
/// `cd.da` and `dqdd` (a K entry): a contact's delta point acceleration (δa_n's at the point, over
/// the sides in those trees: the others do not move) along its direction, the point's computed
/// once for the rows of a contact (`point`), or a joint row's δq̈.
#[inline(always)]
fn delta_accel(cd: &ConstraintData, trees: [usize; 2], dqdd: &[f64], j: usize, point: &mut PointAccel) -> f64 {
    point.row(cd, j, dqdd, || {
        let ([n0, n1], [t0, t1], r) = (cd.node[j], cd.tree[j], cd.arm[j]);
        let mut accel = DVec3::ZERO;
        if moves(trees, t0) {
            accel += cd.da[n0].point_velocity(r);
        }
        if moves(trees, t1) {
            accel -= cd.da[n1].point_velocity(r);
        }
        accel
    })
}

/// Acceleration of row j with zero constraint force (its b): from the actual accelerations, with
/// velocity-product and gravity terms.
/// `point` carries the point's acceleration from a contact's row to its next ones.
fn measure(m: &Model, kin: &KinData, aba: &AbaData, qacc0: &[f64], cd: &ConstraintData, j: usize, point: &mut PointAccel) -> f64 {
    point.row(cd, j, qacc0, || {
        let ([n0, n1], [p0, p1]) = (cd.node[j], cd.point[j]);
        let g = m.opt.gravity;
        point_accel(kin, &aba.a, g, n0, kin.rel(n0, p0)) - point_accel(kin, &aba.a, g, n1, kin.rel(n1, p1))
    })
}

/// The node ranges of the trees `trees` ([`Model::node_tree`]; [`WORLD`] and a repeat name
/// none), first node first.
pub fn tree_ranges(m: &Model, trees: [usize; 2]) -> [std::ops::Range<usize>; 2] {
    let [a, b] = trees;
    let (a, b) = if a == WORLD || (b != WORLD && b < a) { (b, a) } else { (a, b) };
    let range = |t: usize| if t == WORLD { 0..0 } else { t..m.node_end[t] };
    [range(a), if b == a { 0..0 } else { range(b) }]
}

/// target += f · Δq̈ of a row on the trees `trees`, whose Δq̈ (`dqdd`, nv long) is zero, and not
/// kept, off their dofs.
pub fn add_response(m: &Model, trees: [usize; 2], f: f64, dqdd: &[f64], target: &mut [f64]) {
    for r in tree_dofs(m, trees) {
        for (t, d) in target[r.clone()].iter_mut().zip(&dqdd[r]) {
            *t += f * d;
        }
    }
}

/// The dof ranges of the trees `trees`, as [`tree_ranges`].
pub fn tree_dofs(m: &Model, trees: [usize; 2]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    tree_ranges(m, trees).into_iter().filter(|r| !r.is_empty()).map(|r| m.node_dofadr[r.start]..m.node_dofadr[r.end - 1] + m.node_nv[r.end - 1])
}

/// Response of the articulated system to the test forces in `dpa` (world coordinates) or the unit
/// joint torque `dtau` = (dof, value) on the nodes of the trees `trees` (the others do not move):
/// a delta ABA with the inertias of the main pass (velocity terms cancel). Writes Δq̈ of those
/// trees' dofs into `dqdd` and spatial Δa of their nodes into `da`; leaves `dpa` modified.
#[allow(clippy::too_many_arguments)]
pub fn delta_pass(
    m: &Model,
    kin: &KinData,
    aba: &AbaData,
    trees: [usize; 2],
    dtau: Option<(usize, f64)>,
    dpa: &mut [Force],
    du: &mut [[f64; 6]],
    da: &mut [Motion],
    dqdd: &mut [f64],
) {
    // inward: δu_i = δτ_i − S_iᵀ δp^A_i;  δp^A_λ += δp^A_i + U_i D_i⁻¹ δu_i; nodes off the
    // test force's path to the root have δp^A = 0 and δu = 0
    let ranges = tree_ranges(m, trees);
    for part in [1, 0] {
        for i in ranges[part].clone().rev() {
            let k = m.node_nv[i];
            let d0 = m.node_dofadr[i];
            let torqued = matches!(dtau, Some((dof, _)) if dof >= d0 && dof < d0 + k);
            if !torqued && dpa[i] == Force::ZERO {
                du[i] = [0.0; 6];
                continue;
            }
            for r in 0..k {
                let t = match dtau {
                    Some((dof, v)) if dof == d0 + r => v,
                    _ => 0.0,
                };
                du[i][r] = t - kin.s[i][r].dot(&dpa[i]);
            }
            let p = m.node_parent[i];
            if p == WORLD {
                continue;
            }
            let mut pa = dpa[i];
            let mut w = du[i];
            super::aba::solve_d(k, &aba.d_inv[i], &mut w);
            for r in 0..k {
                pa += aba.u_mat[i][r] * w[r];
            }
            dpa[p] += pa;
        }
    }
    // outward: δa'_i = δa_λ;  δq̈_i = D⁻¹(δu_i − Uᵀ δa'_i);  δa_i = δa'_i + S δq̈_i
    for part in [0, 1] {
        for i in ranges[part].clone() {
            let p = m.node_parent[i];
            let a = if p == WORLD { Motion::ZERO } else { da[p] };
            da[i] = super::aba::joint_accel(m, kin, aba, i, &du[i], a, dqdd);
        }
    }
}
