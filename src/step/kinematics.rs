//! Stage 1 — forward kinematics and velocities (Featherstone 2008, Table 7.1, pass 1 without the
//! inertia terms). Reads qpos, qvel; writes node transforms X_up, world poses, motion subspaces S,
//! spatial velocities v and velocity-product accelerations c, and body world poses.

use glam::{DMat3, DVec3};

use crate::math::{Motion, Xform};
use crate::model::joint::{free_subspace, joint_bias, joint_pose, x_up};
use crate::model::{JointType, Model, WORLD};

/// Kinematic quantities of one configuration and velocity.
#[derive(Clone, Debug, Default)]
pub struct KinData {
    /// ^iX_λ(i): parent node frame → node frame (nnode).
    pub x_up: Vec<Xform>,
    /// Node frame axes in world (nnode).
    pub node_rot: Vec<DMat3>,
    /// Node frame origin in world (nnode).
    pub node_pos: Vec<DVec3>,
    /// Motion subspace columns S_i in node coordinates (nnode).
    pub s: Vec<[Motion; 6]>,
    /// Spatial velocity v_i in node coordinates (nnode).
    pub v: Vec<Motion>,
    /// Velocity-product acceleration c_i = c_J + v_i ×m S_i q̇_i (nnode).
    pub c: Vec<Motion>,
    /// Body frame axes in world (nbody), as MuJoCo's `xmat`.
    pub xmat: Vec<DMat3>,
    /// Body frame origin in world (nbody), as MuJoCo's `xpos`.
    pub xpos: Vec<DVec3>,
}

impl KinData {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        KinData {
            x_up: vec![Xform::IDENTITY; m.nnode],
            node_rot: vec![DMat3::IDENTITY; m.nnode],
            node_pos: vec![DVec3::ZERO; m.nnode],
            s: m.node_s.clone(),
            v: vec![Motion::ZERO; m.nnode],
            c: vec![Motion::ZERO; m.nnode],
            xmat: vec![DMat3::IDENTITY; m.nbody],
            xpos: vec![DVec3::ZERO; m.nbody],
        }
    }
}

/// Computes all of [`KinData`] for (`qpos`, `qvel`).
pub fn forward(m: &Model, qpos: &[f64], qvel: &[f64], kin: &mut KinData) {
    forward_nodes(m, qpos, qvel, kin);
    body_poses(m, kin);
}

/// The nodes' part of [`KinData`] (X_up, poses, S, v, c): everything the dynamics reads, without
/// the bodies' world poses (RK4's inner stages).
pub fn forward_nodes(m: &Model, qpos: &[f64], qvel: &[f64], kin: &mut KinData) {
    for i in 0..m.nnode {
        let xu = node_transform(m, i, qpos, &mut kin.s[i]);
        // world pose and velocity, from the parent's
        let (lrot, lpos) = xu.pose();
        let p = m.node_parent[i];
        let (v_parent, (prot, ppos)) = if p == WORLD {
            (Motion::ZERO, (DMat3::IDENTITY, DVec3::ZERO))
        } else {
            (kin.v[p], (kin.node_rot[p], kin.node_pos[p]))
        };
        kin.node_rot[i] = prot * lrot;
        kin.node_pos[i] = ppos + prot * lpos;
        kin.x_up[i] = xu;
        velocity(m, kin, i, v_parent, &qvel[m.node_dofadr[i]..]);
    }
}

/// X_up of node i, writing its q-dependent subspace columns into `s`. A node of several joints
/// composes them in order (Featherstone 2008, §4.2): each earlier column is carried into the frame
/// the later joint moves to, so S ends in node coordinates.
#[inline]
fn node_transform(m: &Model, i: usize, qpos: &[f64], s: &mut [Motion; 6]) -> Xform {
    let j0 = m.node_jntadr[i];
    if m.node_jntnum[i] == 1 {
        let kind = m.jnt_type[j0];
        let qa = m.jnt_qposadr[j0];
        let (rot, pos) = joint_pose(kind, m.jnt_pos[j0], m.jnt_axis[j0], m.qpos0[qa], &qpos[qa..]);
        if kind == JointType::Free {
            free_subspace(rot, s);
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

/// v_i and c_i of node i from its parent's velocity and its dofs' velocities `qd`.
/// c_i = c_J + Σ_j v_j ×m v_Jj over the node's joints j, where v_j, the velocity of the frame joint
/// j moves, is v_i less the joint velocities after j (Featherstone 2008, eq. 4.29 per joint).
#[inline]
fn velocity(m: &Model, kin: &mut KinData, i: usize, v_parent: Motion, qd: &[f64]) {
    let s = &kin.s[i];
    let mut v = kin.x_up[i].apply_motion(&v_parent);
    let mut vj_all = Motion::ZERO;
    for k in 0..m.node_nv[i] {
        vj_all += s[k] * qd[k];
    }
    v += vj_all;
    let j0 = m.node_jntadr[i];
    let c = if m.node_jntnum[i] == 1 {
        joint_bias(m.jnt_type[j0], &vj_all) + v.cross_motion(&vj_all)
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

/// Spatial velocities alone, for another `qvel` on the configuration already in `kin` (X_up, S).
pub fn velocities(m: &Model, kin: &KinData, qvel: &[f64], v: &mut [Motion]) {
    for i in 0..m.nnode {
        let da = m.node_dofadr[i];
        let p = m.node_parent[i];
        let mut vi = if p == WORLD { Motion::ZERO } else { kin.x_up[i].apply_motion(&v[p]) };
        for k in 0..m.node_nv[i] {
            vi += kin.s[i][k] * qvel[da + k];
        }
        v[i] = vi;
    }
}
