//! Cartesian forces on bodies: those applied from outside (MuJoCo's `xfrc_applied`: per body a
//! force at its centre of mass and a torque, both in world axes) and gravity compensation
//! (MuJoCo's `gravcomp`), mapped to joint forces along each body's path to the root
//! (Featherstone 2008, Table 5.1's inward pass).

use glam::DVec3;

use super::kinematics::{add_joint_forces, KinData};
use crate::math::Force;
use crate::model::{Model, WORLD};

/// Adds the joint forces of the body forces `xfrc` (nbody × 6: force, then torque; empty: none)
/// at the configuration in `kin` to `tau`.
#[inline]
pub fn add_forces(m: &Model, kin: &KinData, xfrc: &[f64], tau: &mut [f64]) {
    if xfrc.is_empty() {
        return;
    }
    for (b, f) in xfrc.chunks_exact(6).enumerate().skip(1) {
        let n = m.body_node[b];
        if n == WORLD || f.iter().all(|&x| x == 0.0) {
            continue;
        }
        let (force, torque) = (DVec3::new(f[0], f[1], f[2]), DVec3::new(f[3], f[4], f[5]));
        let r = kin.xpos[b] + kin.xmat[b] * m.body_ipos[b] - kin.origin;
        add_joint_forces(m, kin, n, &Force { ang: torque + r.cross(force), lin: force }, tau);
    }
}

/// Adds the joint forces that hold up the compensated bodies' weight (`Model::body_gravcomp`: a
/// force of −fraction · mass · gravity at each one's centre of mass, MuJoCo's `mj_gravcomp`) at
/// the configuration in `kin` to `tau`.
#[inline]
pub fn add_gravcomp(m: &Model, kin: &KinData, tau: &mut [f64]) {
    for &(b, fraction) in &m.body_gravcomp {
        let n = m.body_node[b];
        if n == WORLD {
            continue;
        }
        let force = -fraction * m.body_mass[b] * m.opt.gravity;
        let r = kin.xpos[b] + kin.xmat[b] * m.body_ipos[b] - kin.origin;
        add_joint_forces(m, kin, n, &Force { ang: r.cross(force), lin: force }, tau);
    }
}
