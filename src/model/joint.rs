//! Joint models: the joint transform X_J(q) and motion subspace S (Featherstone 2008, §4.4, Table 4.1),
//! in MuJoCo's conventions: hinge/slide coordinates are relative to `ref`; rotations turn about the
//! anchor `pos`; ball and free joints use (w, x, y, z) quaternions; free-joint qvel is world linear
//! velocity followed by body-frame angular velocity.

use glam::{DMat3, DVec3};

use crate::math::{quat_wxyz, Motion, Xform};
use crate::mjcf::JointType;

/// Pose (rotation, origin) of the node frame in its predecessor frame for joint coordinates `q`.
/// For free joints the predecessor frame is the world.
#[inline]
pub fn joint_pose(kind: JointType, anchor: DVec3, axis: DVec3, reference: f64, q: &[f64]) -> (DMat3, DVec3) {
    match kind {
        JointType::Hinge => {
            let r = DMat3::from_axis_angle(axis, q[0] - reference);
            (r, anchor - r * anchor)
        }
        JointType::Slide => (DMat3::IDENTITY, axis * (q[0] - reference)),
        JointType::Ball => {
            let r = DMat3::from_quat(quat_wxyz(q).normalize());
            (r, anchor - r * anchor)
        }
        JointType::Free => (DMat3::from_quat(quat_wxyz(&q[3..7]).normalize()), DVec3::new(q[0], q[1], q[2])),
    }
}

/// Constant motion-subspace columns in node coordinates (hinge, slide, ball); free joints get
/// theirs from [`free_subspace`] each step.
pub fn constant_subspace(kind: JointType, anchor: DVec3, axis: DVec3) -> [Motion; 6] {
    let mut s = [Motion::ZERO; 6];
    match kind {
        // rotation about the line through the anchor: v_O = anchor × ω
        JointType::Hinge => s[0] = Motion::new(axis, anchor.cross(axis)),
        JointType::Slide => s[0] = Motion::new(DVec3::ZERO, axis),
        JointType::Ball => {
            for (k, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
                s[k] = Motion::new(e, anchor.cross(e));
            }
        }
        JointType::Free => {}
    }
    s
}

/// Free-joint subspace for body rotation `rot` (body axes in world): the first three qvel are the
/// world-frame linear velocity (body-frame v = Rᵀ q̇), the last three the body-frame angular velocity.
#[inline]
pub fn free_subspace(rot: DMat3, s: &mut [Motion; 6]) {
    let rt = rot.transpose();
    for k in 0..3 {
        s[k] = Motion::new(DVec3::ZERO, rt.col(k));
        let mut e = DVec3::ZERO;
        e[k] = 1.0;
        s[k + 3] = Motion::new(e, DVec3::ZERO);
    }
}

/// `X_up` from the parent node frame to the node frame: the fixed tree transform, then the joint.
#[inline]
pub fn x_up(kind: JointType, xtree: &Xform, rot: DMat3, pos: DVec3) -> Xform {
    let xj = Xform::from_pose(rot, pos);
    match kind {
        JointType::Free => xj,
        _ => xtree.then(&xj),
    }
}
