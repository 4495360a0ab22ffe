//! Stage 8 for RK4 models — classical fourth-order Runge–Kutta over (qpos, qvel) on a step
//! without constraint rows.

use super::*;

/// Classical RK4 over the whole (qpos, qvel) state, quaternions composed on the manifold.
pub(super) fn rk4(m: &Model, data: &mut Data, qpos: &mut [f64], qvel: &mut [f64], ctrl: &[f64], h: f64) {
    use integrate::{integrate_pos, RK4_A, RK4_B};
    let mut rk = std::mem::take(&mut data.rk4);
    // stage 1 is the step's own evaluation (without implicit damping)
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
        // the dynamics need the nodes only (the next step recomputes the kinematics)
        kinematics::forward_nodes(m, &rk.qpos, &rk.qvel, &mut data.kin);
        dynamics(m, data, &rk.qpos, &rk.qvel, ctrl, 0.0);
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
