//! Stage 1 — forward kinematics and velocities (Featherstone 2008, Table 7.1, pass 1 without the
//! inertia terms), in world coordinates: every spatial quantity is expressed in world axes about
//! one reference point per evaluation, `origin` (the first node's origin, so the numbers stay of
//! the model's size wherever it is), as MuJoCo evaluates its recursions; with all transforms
//! between nodes the identity, the dynamics passes carry nothing from node to node. Reads qpos,
//! qvel; writes node world poses, motion subspaces S, spatial velocities v, velocity-product
//! accelerations c, rigid inertias, and body world poses.

use glam::{DMat3, DVec3};

use crate::math::{Motion, SpatialInertia, Xform};
use crate::model::joint::{free_subspace, joint_pose, x_up};
use crate::model::{JointType, Model, WORLD};

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
    let mut s_local = [Motion::ZERO; 6];
    for i in 0..m.nnode {
        let xu = node_transform(m, i, qpos, &mut s_local);
        // world pose, from the parent's
        let (lrot, lpos) = xu.pose();
        let p = m.node_parent[i];
        let (prot, ppos) = if p == WORLD { (DMat3::IDENTITY, DVec3::ZERO) } else { (kin.node_rot[p], kin.node_pos[p]) };
        let (rot, pos) = (prot * lrot, ppos + prot * lpos);
        if i == 0 {
            kin.origin = pos;
        }
        (kin.node_rot[i], kin.node_pos[i]) = (rot, pos);
        // S and the rigid inertia from node coordinates to world about the origin
        let r = pos - kin.origin;
        for (sw, sl) in kin.s[i].iter_mut().zip(&s_local).take(m.node_nv[i]) {
            let ang = rot * sl.ang;
            *sw = Motion::new(ang, rot * sl.lin + r.cross(ang));
        }
        kin.inertia[i] = m.node_inertia[i].to_parent(rot, r);
        let v_parent = if p == WORLD { Motion::ZERO } else { kin.v[p] };
        velocity(m, kin, i, v_parent, &qvel[m.node_dofadr[i]..]);
    }
}

/// X_up of node i (node coordinates), writing its subspace columns in node coordinates into `s`.
/// A node of several joints composes them in order (Featherstone 2008, §4.2): each earlier column
/// is carried into the frame the later joint moves to, so S ends in node coordinates.
#[inline]
fn node_transform(m: &Model, i: usize, qpos: &[f64], s: &mut [Motion; 6]) -> Xform {
    let j0 = m.node_jntadr[i];
    if m.node_jntnum[i] == 1 {
        let kind = m.jnt_type[j0];
        let qa = m.jnt_qposadr[j0];
        let (rot, pos) = joint_pose(kind, m.jnt_pos[j0], m.jnt_axis[j0], m.qpos0[qa], &qpos[qa..]);
        if kind == JointType::Free {
            free_subspace(rot, s);
        } else {
            s[..kind.nv()].copy_from_slice(&m.node_s[i][..kind.nv()]);
        }
        return x_up(kind, &m.node_xtree[i], rot, pos);
    }
    let mut xu = m.node_xtree[i];
    let mut col = 0;
    for j in j0..j0 + m.node_jntnum[i] {
        let qa = m.jnt_qposadr[j];
        let (rot, pos) = joint_pose(m.jnt_type[j], m.jnt_pos[j], m.jnt_axis[j], m.qpos0[qa], &qpos[qa..]);
        let xj = Xform::from_pose(rot, pos);
        for sc in &mut s[..col] {
            *sc = xj.apply_motion(sc);
        }
        let k = m.jnt_type[j].nv();
        s[col..col + k].copy_from_slice(&m.node_s[i][col..col + k]);
        col += k;
        xu = xu.then(&xj);
    }
    xu
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
