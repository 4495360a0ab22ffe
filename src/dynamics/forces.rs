//! Applied joint forces: actuators (MuJoCo's general actuator with affine gain and bias:
//! force = (g₀ + g₁ · length + g₂ · velocity) · u + b₀ + b₁ · length + b₂ · velocity, u the
//! activation of an actuator with dynamics, else ctrl clamped to ctrlrange, the force clamped to
//! forcerange when limited, through the joint or tendon times gear; or a PD servo to ctrl as
//! position target, see [`Actuation`]) and passive springs and dampers of joints and tendons
//! (MuJoCo's `qfrc_passive`). A joint's `actuatorfrcrange` clamps the total of its actuators.

use super::tendon::TendonData;
use crate::math::{quat_sub, quat_wxyz, DVec3};
use crate::model::{Actuation, JointType, Model, Transmission, Wrap};

/// Writes the total applied generalised force into `tau` (nv), the tendons' from `ten` (of this
/// configuration).
pub fn applied(m: &Model, ten: &TendonData, qpos: &[f64], qvel: &[f64], ctrl_act: (&[f64], &[f64]), tau: &mut [f64]) {
    if m.dof_actfrcrange.is_empty() {
        passive(m, ten, qpos, qvel, tau, false);
        actuators(m, ten, qpos, qvel, ctrl_act, tau);
        return;
    }
    // a joint's actuator force is clamped as a total, then the passive forces join it (MuJoCo's
    // qfrc_actuator, mj_fwdActuation)
    tau.fill(0.0);
    actuators(m, ten, qpos, qvel, ctrl_act, tau);
    for &(d, [lo, hi]) in &m.dof_actfrcrange {
        tau[d] = tau[d].clamp(lo, hi);
    }
    passive(m, ten, qpos, qvel, tau, true);
}

/// Passive forces into `tau` (added to it when `add`, else written): damping on every dof,
/// springs per joint, tendons' springs and dampers.
fn passive(m: &Model, ten: &TendonData, qpos: &[f64], qvel: &[f64], tau: &mut [f64], add: bool) {
    for (t, (&v, &b)) in tau.iter_mut().zip(qvel.iter().zip(&m.dof_damping)) {
        *t = if add { *t - b * v } else { -b * v };
    }
    for j in 0..m.njnt {
        let k = m.jnt_stiffness[j];
        if k == 0.0 {
            continue;
        }
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        let rest = &m.qpos_spring[qa..];
        match m.jnt_type[j] {
            JointType::Hinge | JointType::Slide => tau[da] -= k * (qpos[qa] - rest[0]),
            JointType::Ball => {
                let d = quat_sub(quat_wxyz(&qpos[qa..]).normalize(), quat_wxyz(rest));
                for r in 0..3 {
                    tau[da + r] -= k * d[r];
                }
            }
            JointType::Free => {
                let d = DVec3::new(qpos[qa] - rest[0], qpos[qa + 1] - rest[1], qpos[qa + 2] - rest[2]);
                let w = quat_sub(quat_wxyz(&qpos[qa + 3..]).normalize(), quat_wxyz(&rest[3..]));
                for r in 0..3 {
                    tau[da + r] -= k * d[r];
                    tau[da + 3 + r] -= k * w[r];
                }
            }
        }
    }
    tendon_forces(m, ten, qvel, tau);
}

/// The actuators' forces, added to `tau`.
fn actuators(m: &Model, ten: &TendonData, qpos: &[f64], qvel: &[f64], (ctrl, act): (&[f64], &[f64]), tau: &mut [f64]) {
    for a in 0..m.nu {
        let mut u = match (m.opt.actuation, m.actuator_joint(a)) {
            (Actuation::Motor, _) => ctrl[a],
            (Actuation::Pd { kp, kd }, Some(j)) => kp * (ctrl[a] - qpos[m.jnt_qposadr[j]]) - kd * qvel[m.jnt_dofadr[j]],
            // the motion-control rows supply a joint actuator's torque (the servos need joints:
            // `Model` refuses them with tendon actuators)
            (Actuation::Trajectory { .. }, _) | (Actuation::Pd { .. }, None) => continue,
        };
        if m.actuator_ctrllimited[a] {
            let [lo, hi] = m.actuator_ctrlrange[a];
            u = u.clamp(lo, hi);
        }
        if m.actuator_plain[a] {
            u *= m.actuator_gain[a][0];
        } else {
            u = general_force(m, ten, a, u, (qpos, qvel), act);
        }
        if m.actuator_forcelimited[a] {
            let [lo, hi] = m.actuator_forcerange[a];
            u = u.clamp(lo, hi);
        }
        match m.actuator_trn[a] {
            Transmission::Joint(_) => {
                for w in m.moment(a) {
                    tau[w.dof] += w.coef * u;
                }
            }
            Transmission::Tendon(t) => ten.apply(m, t, m.actuator_gear[a] * u, tau),
        }
    }
}

/// A general actuator's force at control `u`: gain · (u, or its activation) + bias, gain and bias
/// affine in its length and rate (gear times its joint's or tendon's).
fn general_force(m: &Model, ten: &TendonData, a: usize, u: f64, (qpos, qvel): (&[f64], &[f64]), act: &[f64]) -> f64 {
    // an actuator with dynamics is driven by its activation
    let u = m.actuator_actadr[a].map_or(u, |i| act[i]);
    let ([g0, g1, g2], [b0, b1, b2]) = (m.actuator_gain[a], m.actuator_bias[a]);
    let (length, rate) = match m.actuator_trn[a] {
        Transmission::Joint(_) => (Wrap::length(m.moment(a), qpos), Wrap::rate(m.moment(a), qvel)),
        Transmission::Tendon(t) => (m.actuator_gear[a] * ten.length[t], m.actuator_gear[a] * ten.rate(m, t, qvel)),
    };
    if let Some(mu) = &m.actuator_muscle[a] {
        return u * super::muscle::gain(mu, length, rate) + super::muscle::bias(mu, length);
    }
    let gain = if [g1, g2] == [0.0; 2] { g0 } else { g0 + g1 * length + g2 * rate };
    let force = u * gain;
    if [b0, b1, b2] == [0.0; 3] { force } else { force + (b0 + b1 * length + b2 * rate) }
}

/// Tendons' springs (zero force within the rest deadband) and dampers, through their J.
fn tendon_forces(m: &Model, ten: &TendonData, qvel: &[f64], tau: &mut [f64]) {
    for t in 0..m.ntendon {
        let (k, b) = (m.tendon_stiffness[t], m.tendon_damping[t]);
        if k == 0.0 && b == 0.0 {
            continue;
        }
        let (length, velocity) = (ten.length[t], ten.rate(m, t, qvel));
        let [lo, hi] = m.tendon_springlength[t];
        let stretch = if length > hi { length - hi } else if length < lo { length - lo } else { 0.0 };
        ten.apply(m, t, -k * stretch - b * velocity, tau);
    }
}
