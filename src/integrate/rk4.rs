//! Stage 8 for RK4 models — classical fourth-order Runge–Kutta over (qpos, qvel, act) on a step
//! without constraint rows; ball and free rotations by Runge–Kutta–Munthe-Kaas, which keeps the
//! fourth order on SO(3) (Munthe-Kaas 1998; Hairer, Lubich & Wanner 2006, §IV.8.2).

use glam::DVec3;

use super::{integrate_pos, Rk4Scratch, RK4_A, RK4_B};
use crate::dynamics::{self, activation, kinematics, DynamicsData};
use crate::model::{JointType, Model};
use crate::state::WorldState;

/// The activations of RK4 stage i (1..4) into `rk.act`: act + h Σⱼ A_ij kactⱼ.
fn activation_stage(m: &Model, act: &[f64], rk: &mut Rk4Scratch, i: usize, h: f64) {
    rk.act.copy_from_slice(act);
    for (j, &a) in RK4_A[i - 1][..i].iter().enumerate().filter(|(_, a)| **a != 0.0) {
        for k in 0..m.na {
            rk.act[k] += h * a * rk.kact[j][k];
        }
    }
}

/// act advanced over h by RK4's weighted stage rates `rk.kact` (MuJoCo's `mj_advance`).
fn advance_activations(m: &Model, act: &mut [f64], rk: &mut Rk4Scratch, h: f64) {
    rk.act.fill(0.0);
    for j in 0..4 {
        for k in 0..m.na {
            rk.act[k] += RK4_B[j] * rk.kact[j][k];
        }
    }
    activation::advance(m, act, &rk.act, h);
}

/// The activations alone advanced over h by RK4, at controls `ctrl`: their rates read ctrl and
/// act only, so a step whose (qpos, qvel) advance otherwise (a constrained step of an RK4 model)
/// still advances them exactly as MuJoCo's RK4 does.
pub fn rk4_activations(m: &Model, ctrl: &[f64], act: &mut [f64], rk: &mut Rk4Scratch, h: f64) {
    activation::rates(m, ctrl, act, &mut rk.kact[0]);
    for i in 1..4 {
        activation_stage(m, act, rk, i, h);
        let (stage, kact) = (&rk.act, &mut rk.kact[i]);
        activation::rates(m, ctrl, stage, kact);
    }
    advance_activations(m, act, rk, h);
}

/// Classical RK4 over the whole (qpos, qvel) state. A rotation's stage state is `q₀ exp(uᵢ)`
/// with `uᵢ = h Σⱼ Aᵢⱼ Kⱼ` and `Kⱼ = dexp⁻¹(ωⱼ)` at `uⱼ`: adding body-frame angular
/// velocities taken at different orientations as if they were one vector would be second order.
pub fn rk4(m: &Model, dy: &mut DynamicsData, rk: &mut Rk4Scratch, s: &mut WorldState<'_>, h: f64) {
    let (qpos, qvel, ctrl, act) = (&mut *s.qpos, &mut *s.qvel, s.ctrl, &mut *s.act);
    // stage 1 is the step's own evaluation (without implicit damping)
    rk.kv[0].copy_from_slice(qvel);
    rk.ka[0].copy_from_slice(&dy.qacc);
    let acts = m.na > 0;
    if acts {
        activation::rates(m, ctrl, act, &mut rk.kact[0]);
    }
    for i in 1..4 {
        // stage state: X0 + h Σ_j A_ij F_j
        rk.qpos.copy_from_slice(qpos);
        rk.dv.fill(0.0);
        rk.qvel.copy_from_slice(qvel);
        activation_stage(m, act, rk, i, h);
        for j in 0..i {
            let a = RK4_A[i - 1][j];
            if a == 0.0 {
                continue;
            }
            for k in 0..m.nv {
                rk.dv[k] += a * rk.kv[j][k];
                rk.qvel[k] += h * a * rk.ka[j][k];
            }
        }
        integrate_pos(m, &mut rk.qpos, &rk.dv, h);
        // the dynamics need the nodes, and the bodies' poses where spatial tendons or fluid
        // forces read them (the next step recomputes the kinematics)
        if m.forces_read_bodies() {
            kinematics::forward(m, &rk.qpos, &rk.qvel, &mut dy.kin);
        } else {
            kinematics::forward_nodes(m, &rk.qpos, &rk.qvel, &mut dy.kin);
        }
        dynamics::accelerations(m, dy, &rk.qpos, &rk.qvel, ctrl, &rk.act, 0.0);
        rk.kv[i].copy_from_slice(&rk.qvel);
        rk.ka[i].copy_from_slice(&dy.qacc);
        if acts {
            activation::rates(m, ctrl, &rk.act, &mut rk.kact[i]);
        }
        lie_algebra_velocity(m, &mut rk.kv[i], &rk.dv, h);
    }
    rk.dv.fill(0.0);
    for j in 0..4 {
        for k in 0..m.nv {
            rk.dv[k] += RK4_B[j] * rk.kv[j][k];
            qvel[k] += h * RK4_B[j] * rk.ka[j][k];
        }
    }
    integrate_pos(m, qpos, &rk.dv, h);
    // the activations by the weighted rates (MuJoCo's mj_advance)
    if acts {
        advance_activations(m, act, rk, h);
    }
    // report the acceleration at the start of the step
    dy.qacc.copy_from_slice(&rk.ka[0]);
}

/// Replaces each ball or free rotation's body-frame angular velocity ω in `kv` by the rate of
/// its rotation vector u = h·`dv` (q = q₀ exp(u)): u̇ = dexp⁻¹₋ᵤ(ω) = ω + ½ u×ω + ¹⁄₁₂ u×(u×ω),
/// truncated after the terms RK4's order needs (Hairer, Lubich & Wanner 2006, Lemma III.4.2).
fn lie_algebra_velocity(m: &Model, kv: &mut [f64], dv: &[f64], h: f64) {
    for j in 0..m.njnt {
        let da = match m.jnt_type[j] {
            JointType::Ball => m.jnt_dofadr[j],
            JointType::Free => m.jnt_dofadr[j] + 3,
            JointType::Hinge | JointType::Slide => continue,
        };
        let u = h * DVec3::new(dv[da], dv[da + 1], dv[da + 2]);
        let w = DVec3::new(kv[da], kv[da + 1], kv[da + 2]);
        let k = w + 0.5 * u.cross(w) + u.cross(u.cross(w)) / 12.0;
        kv[da..da + 3].copy_from_slice(&k.to_array());
    }
}
