//! Stage 8 — time integration: semi-implicit Euler (MuJoCo's `Euler`), leapfrog (position
//! Verlet) and classical RK4 (MuJoCo's `RK4`, same tableau). Quaternions move on the manifold and
//! stay unit. A step with contacts closes with its energy bound (`energy_bound`).

pub mod energy_bound;
pub mod rk4;

use crate::math::{quat_integrate, quat_wxyz, DVec3};
use crate::model::{JointType, Model};

/// qpos ← qpos ⊕ h·qvel, joint by joint (MuJoCo's `mj_integratePos`).
pub fn integrate_pos(m: &Model, qpos: &mut [f64], qvel: &[f64], h: f64) {
    for j in 0..m.njnt {
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        match m.jnt_type[j] {
            JointType::Hinge | JointType::Slide => qpos[qa] += h * qvel[da],
            JointType::Ball => write_quat(&mut qpos[qa..qa + 4], h, DVec3::new(qvel[da], qvel[da + 1], qvel[da + 2])),
            JointType::Free => {
                for r in 0..3 {
                    qpos[qa + r] += h * qvel[da + r];
                }
                write_quat(&mut qpos[qa + 3..qa + 7], h, DVec3::new(qvel[da + 3], qvel[da + 4], qvel[da + 5]));
            }
        }
    }
}

fn write_quat(q: &mut [f64], h: f64, omega: DVec3) {
    let n = quat_integrate(quat_wxyz(q).normalize(), omega, h);
    q.copy_from_slice(&[n.w, n.x, n.y, n.z]);
}

/// qvel += h·qacc, then qpos ← qpos ⊕ lever·qvel: semi-implicit Euler with lever = h, the
/// closing kick and drift of leapfrog with lever = h/2.
pub fn kick_drift(m: &Model, qpos: &mut [f64], qvel: &mut [f64], qacc: &[f64], h: f64, lever: f64) {
    for (v, a) in qvel.iter_mut().zip(qacc) {
        *v += h * a;
    }
    integrate_pos(m, qpos, qvel, lever);
}

/// Scratch for RK4: the stage velocities and accelerations and the stage state.
#[derive(Clone, Debug, Default)]
pub struct Rk4Scratch {
    /// Stage velocities k_i (4 × nv).
    pub kv: [Vec<f64>; 4],
    /// Stage accelerations (4 × nv).
    pub ka: [Vec<f64>; 4],
    /// Stage position.
    pub qpos: Vec<f64>,
    /// Stage velocity.
    pub qvel: Vec<f64>,
    /// Combined increment.
    pub dv: Vec<f64>,
    /// Stage activation rates (4 × na).
    pub kact: [Vec<f64>; 4],
    /// Stage activations (na).
    pub act: Vec<f64>,
}

impl Rk4Scratch {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        let v = || vec![0.0; m.nv];
        let a = || vec![0.0; m.na];
        Rk4Scratch { kv: [v(), v(), v(), v()], ka: [v(), v(), v(), v()], qpos: vec![0.0; m.nq], qvel: v(), dv: v(), kact: [a(), a(), a(), a()], act: a() }
    }
}

/// Butcher tableau of classical RK4 (MuJoCo's `mj_RungeKutta`).
pub const RK4_A: [[f64; 3]; 3] = [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]];
/// RK4 weights.
pub const RK4_B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
