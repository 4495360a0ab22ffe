//! Applied joint forces: actuators (gear · ctrl, ctrl clamped to ctrlrange and force to forcerange
//! when limited, as MuJoCo's `motor`; or a PD servo to ctrl as position target, see
//! [`Actuation`]) and passive springs and dampers (MuJoCo's `qfrc_passive`).

use crate::math::{quat_sub, quat_wxyz, DVec3};
use crate::model::{Actuation, JointType, Model};

/// Writes the total applied generalised force into `tau` (nv).
pub fn applied(m: &Model, qpos: &[f64], qvel: &[f64], ctrl: &[f64], tau: &mut [f64]) {
    // passive: damping on every dof, springs per joint
    for (t, (&v, &b)) in tau.iter_mut().zip(qvel.iter().zip(&m.dof_damping)) {
        *t = -b * v;
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
    // actuators
    for a in 0..m.nu {
        let dof = m.jnt_dofadr[m.actuator_jnt[a]];
        let mut u = match m.opt.actuation {
            Actuation::Motor => ctrl[a],
            Actuation::Pd { kp, kd } => kp * (ctrl[a] - qpos[m.jnt_qposadr[m.actuator_jnt[a]]]) - kd * qvel[dof],
            // the motion-control rows supply the torque
            Actuation::Trajectory { .. } => continue,
        };
        if m.actuator_ctrllimited[a] {
            let [lo, hi] = m.actuator_ctrlrange[a];
            u = u.clamp(lo, hi);
        }
        if m.actuator_forcelimited[a] {
            let [lo, hi] = m.actuator_forcerange[a];
            u = u.clamp(lo, hi);
        }
        tau[dof] += m.actuator_gear[a] * u;
    }
}
