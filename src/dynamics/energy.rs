//! Mechanical energy of a state, as MuJoCo's `mj_energyPos` and `mj_energyVel`: potential
//! (gravity, joint and tendon springs) and kinetic (½ q̇ᵀ M q̇, armature included), from the
//! kinematics of the state.

use super::kinematics::KinData;
use super::tendon::TendonData;
use crate::math::{quat_sub, quat_wxyz, DVec3};
use crate::model::{JointType, Model};

/// Gravity's potential energy −Σ m_b g·c_b over the bodies' centres of mass c_b (the world's
/// static bodies included, as MuJoCo counts them).
pub fn gravity_potential(m: &Model, kin: &KinData) -> f64 {
    let first_moment = (0..m.nbody).fold(DVec3::ZERO, |s, b| s + (kin.xpos[b] + kin.xmat[b] * m.body_ipos[b]) * m.body_mass[b]);
    -m.opt.gravity.dot(first_moment)
}

/// [`gravity_potential`] of the bodies that move (the nodes'), less the static bodies' constant:
/// for differences of U, without the bodies' poses.
pub fn moving_gravity_potential(m: &Model, kin: &KinData) -> f64 {
    let (first_moment, mass) = kin.inertia.iter().fold((DVec3::ZERO, 0.0), |(s, total), i| (s + i.com * i.mass, total + i.mass));
    -m.opt.gravity.dot(first_moment + kin.origin * mass)
}

/// The springs' potential energy: ½ k d² per joint (d the displacement from `qpos_spring`, a
/// ball's or free joint's rotation as its rotation vector) and per tendon beyond its rest
/// deadband.
pub fn spring_potential(m: &Model, ten: &TendonData, qpos: &[f64]) -> f64 {
    let mut e = 0.0;
    for j in (0..m.njnt).filter(|&j| m.jnt_stiffness[j] != 0.0) {
        let (qa, rest) = (m.jnt_qposadr[j], &m.qpos_spring[m.jnt_qposadr[j]..]);
        let turn = |q: &[f64], r: &[f64]| quat_sub(quat_wxyz(q).normalize(), quat_wxyz(r)).length_squared();
        let squared = match m.jnt_type[j] {
            JointType::Hinge | JointType::Slide => (qpos[qa] - rest[0]).powi(2),
            JointType::Ball => turn(&qpos[qa..], rest),
            JointType::Free => (0..3).map(|r| (qpos[qa + r] - rest[r]).powi(2)).sum::<f64>() + turn(&qpos[qa + 3..], &rest[3..]),
        };
        e += 0.5 * m.jnt_stiffness[j] * squared;
    }
    for t in (0..m.ntendon).filter(|&t| m.tendon_stiffness[t] != 0.0) {
        let ([lo, hi], l) = (m.tendon_springlength[t], ten.length[t]);
        let stretch = if l > hi { l - hi } else if l < lo { l - lo } else { 0.0 };
        e += 0.5 * m.tendon_stiffness[t] * stretch * stretch;
    }
    e
}

/// Kinetic energy ½ q̇ᵀ M q̇ = ½ Σ vᵢ·(Iᵢ vᵢ) + ½ Σ armature q̇², and gravity's power g·P (P the
/// bodies' total linear momentum), from the node velocities in `kin` (those of `qvel`).
pub fn kinetic_and_gravity_power(m: &Model, kin: &KinData, qvel: &[f64]) -> (f64, f64) {
    // per node: m |v_c|² + ωᵀ I_c ω, v_c the centre of mass's velocity
    let (mut bodies, mut momentum) = (0.0, DVec3::ZERO);
    for (v, i) in kin.v.iter().zip(&kin.inertia) {
        let vc = v.lin + v.ang.cross(i.com);
        bodies += i.mass * vc.length_squared() + v.ang.dot(i.ic * v.ang);
        momentum += vc * i.mass;
    }
    let armature: f64 = qvel.iter().zip(&m.dof_armature).map(|(v, a)| a * v * v).sum();
    (0.5 * (bodies + armature), m.opt.gravity.dot(momentum))
}
