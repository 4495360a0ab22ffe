//! ④ One simulation step. [`step`] reads as the pipeline; each stage lives in its own file.

pub mod aba;
pub mod forces;
pub mod integrate;
pub mod kinematics;

use crate::data::Data;
use crate::model::{Integrator, Model};

/// Forward dynamics at (qpos, qvel, ctrl): fills `data.qacc` with the true accelerations
/// (no implicit damping), as MuJoCo's `mj_forward`.
pub fn forward(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64]) {
    evaluate(m, data, qpos, qvel, ctrl, 0.0);
}

/// Stages 1 to 5 for one state; `h_damp` > 0 treats joint damping implicitly over that step.
fn evaluate(m: &Model, data: &mut Data, qpos: &[f64], qvel: &[f64], ctrl: &[f64], h_damp: f64) {
    // 1. poses, velocities, velocity-product terms
    kinematics::forward(m, qpos, qvel, &mut data.kin);
    // 2. applied joint forces: actuators, springs, dampers
    forces::applied(m, qpos, qvel, ctrl, &mut data.qfrc_applied);
    // 3. articulated inertias and bias forces (inward pass)
    aba::backward(m, &data.kin, &data.qfrc_applied, h_damp, &mut data.aba);
    // 4. joint accelerations (outward pass)
    aba::forward(m, &data.kin, &mut data.aba, &mut data.qacc);
}

/// Advances (qpos, qvel, time) by one time step under `ctrl`.
pub fn step(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &mut [f64], ctrl: &[f64], time: &mut f64) {
    let h = m.opt.timestep;
    match m.opt.integrator {
        Integrator::Euler => {
            evaluate(m, data, qpos, qvel, ctrl, h);
            integrate::euler(m, qpos, qvel, &data.qacc, h);
        }
        Integrator::Rk4 => rk4(m, data, qpos, qvel, ctrl, h),
    }
    *time += h;
}

/// Classical RK4 over the whole (qpos, qvel) state, quaternions composed on the manifold.
fn rk4(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &mut [f64], ctrl: &[f64], h: f64) {
    use integrate::{integrate_pos, RK4_A, RK4_B};
    let mut rk = std::mem::take(&mut data.rk4);
    evaluate(m, data, qpos, qvel, ctrl, 0.0);
    rk.kv[0].copy_from_slice(qvel);
    rk.ka[0].copy_from_slice(&data.qacc);
    for i in 1..4 {
        // stage state: X0 + h Σ_j A_ij F_j
        rk.qpos.copy_from_slice(qpos);
        rk.dv.fill(0.0);
        rk.qvel.copy_from_slice(qvel);
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
        evaluate(m, data, &rk.qpos, &rk.qvel, ctrl, 0.0);
        rk.kv[i].copy_from_slice(&rk.qvel);
        rk.ka[i].copy_from_slice(&data.qacc);
    }
    rk.dv.fill(0.0);
    for j in 0..4 {
        for k in 0..m.nv {
            rk.dv[k] += RK4_B[j] * rk.kv[j][k];
            qvel[k] += h * RK4_B[j] * rk.ka[j][k];
        }
    }
    integrate_pos(m, qpos, &rk.dv, h);
    // report the acceleration at the start of the step
    data.qacc.copy_from_slice(&rk.ka[0]);
    data.rk4 = rk;
}
