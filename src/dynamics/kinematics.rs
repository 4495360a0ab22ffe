//! Stage 1 — forward kinematics and velocities (Featherstone 2008, Table 7.1, pass 1 without the
//! inertia terms), in world coordinates: every spatial quantity is expressed in world axes about
//! one reference point per evaluation, `origin` (the first node's origin, so the numbers stay of
//! the model's size wherever it is), as MuJoCo evaluates its recursions; with all transforms
//! between nodes the identity, the dynamics passes carry nothing from node to node. Reads qpos,
//! qvel; writes node world poses, motion subspaces S, spatial velocities v, velocity-product
//! accelerations c, rigid inertias, and body world poses.

use glam::{DMat3, DVec3};

use crate::math::{quat_wxyz, Force, Motion, SpatialInertia, Xform};
use crate::model::{JointType, Model, WORLD};

/// Kinematics of a state computed ahead of the step that starts from it: post-stabilisation's
/// last check computes the end state's, the sensors read them, and the next step's stage 1
/// takes them instead of computing them again.
#[derive(Clone, Debug, Default)]
pub struct KinCache {
    /// The kinematics of (`qpos`, `qvel`) when `cached`.
    pub kin: KinData,
    cached: bool,
    qpos: Vec<f64>,
    qvel: Vec<f64>,
}

impl KinCache {
    /// Buffers sized for `m`, holding nothing.
    pub fn new(m: &Model) -> Self {
        KinCache { kin: KinData::new(m), ..Default::default() }
    }

    /// Holds nothing any more.
    pub fn forget(&mut self) {
        self.cached = false;
    }

    /// Whether `kin` is the kinematics of (`qpos`, `qvel`).
    pub fn holds(&self, qpos: &[f64], qvel: &[f64]) -> bool {
        self.cached && self.qpos == qpos && self.qvel == qvel
    }

    /// Marks `kin` as the kinematics of (`qpos`, `qvel`).
    pub fn keep(&mut self, qpos: &[f64], qvel: &[f64]) {
        self.cached = true;
        self.qpos.clear();
        self.qpos.extend_from_slice(qpos);
        self.qvel.clear();
        self.qvel.extend_from_slice(qvel);
    }

    /// The kinematics of (`qpos`, `qvel`): the cached ones when they are of this state, else
    /// computed here and kept.
    pub fn at(&mut self, m: &Model, qpos: &[f64], qvel: &[f64]) -> &KinData {
        if !self.holds(qpos, qvel) {
            forward(m, qpos, qvel, &mut self.kin);
            self.keep(qpos, qvel);
        }
        &self.kin
    }

    /// Stage 1: the kinematics of (`qpos`, `qvel`) into `kin`, taken from the cache when it
    /// holds them (the cache is then spent).
    pub fn take_into(&mut self, m: &Model, qpos: &[f64], qvel: &[f64], kin: &mut KinData) {
        if self.holds(qpos, qvel) {
            std::mem::swap(kin, &mut self.kin);
        } else {
            forward(m, qpos, qvel, kin);
        }
        self.cached = false;
    }
}

/// Kinematic quantities of one configuration and velocity.
#[derive(Clone, Debug, Default)]
pub struct KinData {
    /// Reference point of the spatial quantities below, world coordinates.
    pub origin: DVec3,
    /// Node frame axes in world (nnode).
    pub node_rot: Vec<DMat3>,
    /// Node frame origin in world (nnode).
    pub node_pos: Vec<DVec3>,
    /// Motion subspace columns S_i (nnode).
    pub s: Vec<[Motion; 6]>,
    /// Spatial velocity v_i (nnode).
    pub v: Vec<Motion>,
    /// Velocity-product acceleration c_i = Ṡ_i q̇_i (nnode).
    pub c: Vec<Motion>,
    /// Rigid inertia carried by each node (nnode).
    pub inertia: Vec<SpatialInertia>,
    /// Body frame axes in world (nbody), as MuJoCo's `xmat`.
    pub xmat: Vec<DMat3>,
    /// Body frame origin in world (nbody), as MuJoCo's `xpos`.
    pub xpos: Vec<DVec3>,
}

impl KinData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        KinData {
            origin: DVec3::ZERO,
            node_rot: vec![DMat3::IDENTITY; m.nnode],
            node_pos: vec![DVec3::ZERO; m.nnode],
            s: vec![[Motion::ZERO; 6]; m.nnode],
            v: vec![Motion::ZERO; m.nnode],
            c: vec![Motion::ZERO; m.nnode],
            inertia: vec![SpatialInertia::ZERO; m.nnode],
            xmat: vec![DMat3::IDENTITY; m.nbody],
            xpos: vec![DVec3::ZERO; m.nbody],
        }
    }

    /// Position relative to `origin` of the point with node coordinates `p` on node `n` (world
    /// coordinates for [`WORLD`]).
    #[inline]
    pub fn rel(&self, n: usize, p: DVec3) -> DVec3 {
        if n == WORLD { p - self.origin } else { self.node_rot[n] * p + self.node_pos[n] - self.origin }
    }
}

/// Computes all of [`KinData`] for (`qpos`, `qvel`).
pub fn forward(m: &Model, qpos: &[f64], qvel: &[f64], kin: &mut KinData) {
    forward_nodes(m, qpos, qvel, kin);
    body_poses(m, kin);
}

/// The nodes' part of [`KinData`] (poses, S, v, c, inertias): everything the dynamics reads,
/// without the bodies' world poses (RK4's inner stages).
pub fn forward_nodes(m: &Model, qpos: &[f64], qvel: &[f64], kin: &mut KinData) {
    for i in 0..m.nnode {
        let p = m.node_parent[i];
        let (prot, ppos) = if p == WORLD { (DMat3::IDENTITY, DVec3::ZERO) } else { (kin.node_rot[p], kin.node_pos[p]) };
        // node 0's columns are made about the world origin, then moved to its own, the origin
        let origin = if i == 0 { DVec3::ZERO } else { kin.origin };
        let (rot, pos) = node_pose(m, i, prot, ppos, origin, qpos, &mut kin.s[i]);
        if i == 0 {
            kin.origin = pos;
            for sc in kin.s[0].iter_mut().take(m.node_nv[0]) {
                sc.lin -= pos.cross(sc.ang);
            }
        }
        (kin.node_rot[i], kin.node_pos[i]) = (rot, pos);
        kin.inertia[i] = m.node_inertia[i].to_parent(rot, pos - kin.origin);
        let v_parent = if p == WORLD { Motion::ZERO } else { kin.v[p] };
        velocity(m, kin, i, v_parent, &qvel[m.node_dofadr[i]..]);
    }
}

/// World pose of node i from its parent's (`prot`, `ppos`), writing its subspace columns about
/// `origin` into `s`. The node's joints act in order, each about its own axis and anchor in the
/// frame the one before it left (Featherstone 2008, §4.2; MuJoCo's body kinematics): a rotation's
/// column is (ω, (c − origin) × ω) for its world axis ω through the world point c, a
/// translation's (0, world axis).
#[inline]
fn node_pose(m: &Model, i: usize, prot: DMat3, ppos: DVec3, origin: DVec3, qpos: &[f64], s: &mut [Motion; 6]) -> (DMat3, DVec3) {
    let j0 = m.node_jntadr[i];
    if m.jnt_type[j0] == JointType::Free {
        // a free joint moves from the world: world linear velocity, body-frame angular velocity
        let qa = m.jnt_qposadr[j0];
        let rot = DMat3::from_quat(quat_wxyz(&qpos[qa + 3..qa + 7]).normalize());
        let pos = DVec3::new(qpos[qa], qpos[qa + 1], qpos[qa + 2]);
        for k in 0..3 {
            s[k] = Motion::new(DVec3::ZERO, DVec3::AXES[k]);
            let w = rot.col(k);
            s[k + 3] = Motion::new(w, (pos - origin).cross(w));
        }
        return (rot, pos);
    }
    // the frame the first joint moves from
    let xt = &m.node_xtree[i];
    let (mut rot, mut pos) = if xt.e == DMat3::IDENTITY { (prot, ppos + prot * xt.r) } else { (prot * xt.e.transpose(), ppos + prot * xt.r) };
    let mut col = 0;
    for j in j0..j0 + m.node_jntnum[i] {
        let qa = m.jnt_qposadr[j];
        let (anchor, axis) = (m.jnt_pos[j], m.jnt_axis[j]);
        let c = if anchor == DVec3::ZERO { pos - origin } else { pos + rot * anchor - origin };
        match m.jnt_type[j] {
            JointType::Hinge => {
                let w = rot * axis;
                s[col] = Motion::new(w, c.cross(w));
                rot = turn(rot, axis, qpos[qa] - m.qpos0[qa]);
                if anchor != DVec3::ZERO {
                    pos = c + origin - rot * anchor;
                }
            }
            JointType::Slide => {
                let w = rot * axis;
                s[col] = Motion::new(DVec3::ZERO, w);
                pos += w * (qpos[qa] - m.qpos0[qa]);
            }
            JointType::Ball => {
                rot *= DMat3::from_quat(quat_wxyz(&qpos[qa..qa + 4]).normalize());
                for k in 0..3 {
                    let w = rot.col(k);
                    s[col + k] = Motion::new(w, c.cross(w));
                }
                if anchor != DVec3::ZERO {
                    pos = c + origin - rot * anchor;
                }
            }
            JointType::Free => unreachable!("a free joint is alone in its node"),
        }
        col += m.jnt_type[j].nv();
    }
    (rot, pos)
}

/// `rot` R_J: `rot` turned by `angle` about the unit `axis` given in its own frame. A coordinate
/// axis (most MJCF hinges) mixes two columns; any other uses Rodrigues' matrix.
#[inline]
fn turn(rot: DMat3, axis: DVec3, angle: f64) -> DMat3 {
    let (sin, cos) = angle.sin_cos();
    let (x, y, z) = (rot.x_axis, rot.y_axis, rot.z_axis);
    if axis.y == 0.0 && axis.z == 0.0 {
        let s = sin * axis.x;
        DMat3::from_cols(x, y * cos + z * s, z * cos - y * s)
    } else if axis.x == 0.0 && axis.z == 0.0 {
        let s = sin * axis.y;
        DMat3::from_cols(x * cos - z * s, y, x * s + z * cos)
    } else if axis.x == 0.0 && axis.y == 0.0 {
        let s = sin * axis.z;
        DMat3::from_cols(x * cos + y * s, y * cos - x * s, z)
    } else {
        rot * DMat3::from_axis_angle(axis, angle)
    }
}

/// Bodies' world poses from their nodes'.
fn body_poses(m: &Model, kin: &mut KinData) {
    for b in 1..m.nbody {
        let n = m.body_node[b];
        let (nrot, npos) = if n == WORLD { (DMat3::IDENTITY, DVec3::ZERO) } else { (kin.node_rot[n], kin.node_pos[n]) };
        // a body with joints is its node's frame; a welded one sits at an offset in it
        if m.body_offset[b] == Xform::IDENTITY {
            (kin.xmat[b], kin.xpos[b]) = (nrot, npos);
        } else {
            let (orot, opos) = m.body_offset[b].pose();
            kin.xmat[b] = nrot * orot;
            kin.xpos[b] = npos + nrot * opos;
        }
    }
}

/// v_i and c_i of node i from its parent's velocity and its dofs' velocities `qd`: v_i = v_λ + S q̇
/// and c_i = Σ_j v_j ×m v_Jj over the node's joints j (a column fixed in the frame joint j moves
/// has Ṡ = v_j × S), where v_j, that frame's velocity, is v_i less the joint velocities after j.
/// A free joint's linear columns are fixed in the world instead: its c is (0, ṗ × ω).
#[inline]
fn velocity(m: &Model, kin: &mut KinData, i: usize, v_parent: Motion, qd: &[f64]) {
    let s = &kin.s[i];
    let mut vj_all = Motion::ZERO;
    for k in 0..m.node_nv[i] {
        vj_all += s[k] * qd[k];
    }
    let v = v_parent + vj_all;
    let j0 = m.node_jntadr[i];
    let c = if m.node_jntnum[i] == 1 {
        match m.jnt_type[j0] {
            JointType::Free => Motion::new(DVec3::ZERO, DVec3::new(qd[0], qd[1], qd[2]).cross(v.ang)),
            _ => v.cross_motion(&vj_all),
        }
    } else {
        let (mut c, mut vj_frame, mut end) = (Motion::ZERO, v, m.node_nv[i]);
        for j in (j0..j0 + m.node_jntnum[i]).rev() {
            let start = end - m.jnt_type[j].nv();
            let mut vj = Motion::ZERO;
            for k in start..end {
                vj += s[k] * qd[k];
            }
            c += vj_frame.cross_motion(&vj);
            vj_frame -= vj;
            end = start;
        }
        c
    };
    kin.c[i] = c;
    kin.v[i] = v;
}

/// v and c for a new `qvel` on the configuration already in `kin` (after an impulse).
pub fn forward_velocity(m: &Model, qvel: &[f64], kin: &mut KinData) {
    for i in 0..m.nnode {
        let p = m.node_parent[i];
        let v_parent = if p == WORLD { Motion::ZERO } else { kin.v[p] };
        velocity(m, kin, i, v_parent, &qvel[m.node_dofadr[i]..]);
    }
}

/// Spatial velocities alone, for another `qvel` on the configuration already in `kin` (S).
pub fn velocities(m: &Model, kin: &KinData, qvel: &[f64], v: &mut [Motion]) {
    for i in 0..m.nnode {
        let da = m.node_dofadr[i];
        let p = m.node_parent[i];
        let mut vi = if p == WORLD { Motion::ZERO } else { v[p] };
        for k in 0..m.node_nv[i] {
            vi += kin.s[i][k] * qvel[da + k];
        }
        v[i] = vi;
    }
}

/// World classical acceleration of the point of node `n` at `r` (relative to `kin.origin`), from
/// the nodes' spatial accelerations `a`, plus `g` (the ABA's accelerations carry the base's
/// fictitious −g, which `g` adds back; the velocity products alone, J̇ q̇, take none).
#[inline]
pub fn point_accel(kin: &KinData, a: &[Motion], g: DVec3, n: usize, r: DVec3) -> DVec3 {
    if n == WORLD {
        return DVec3::ZERO;
    }
    let v = kin.v[n];
    a[n].point_velocity(r) + v.ang.cross(v.point_velocity(r)) + g
}

/// World velocity of the point of node `n` at `r` (relative to `kin.origin`).
pub fn point_vel(kin: &KinData, n: usize, r: DVec3) -> DVec3 {
    if n == WORLD { DVec3::ZERO } else { kin.v[n].point_velocity(r) }
}

/// Velocity-product accelerations a_i = a_λ + c_i (q̈ = 0, no gravity): J̇ q̇ of any point.
pub fn velocity_products(m: &Model, kin: &KinData, a_vp: &mut [Motion]) {
    for i in 0..m.nnode {
        let p = m.node_parent[i];
        let a_parent = if p == WORLD { Motion::ZERO } else { a_vp[p] };
        a_vp[i] = a_parent + kin.c[i];
    }
}

/// tau += Sᵀ f over the path from node `n` to the root: the joint forces of the spatial force `f`
/// (world coordinates about `kin.origin`) on node `n` (RNEA's inward force pass, Featherstone
/// 2008, Table 5.1).
pub fn add_joint_forces(m: &Model, kin: &KinData, mut n: usize, f: &Force, tau: &mut [f64]) {
    while n != WORLD {
        for k in 0..m.node_nv[n] {
            tau[m.node_dofadr[n] + k] += kin.s[n][k].dot(f);
        }
        n = m.node_parent[n];
    }
}
