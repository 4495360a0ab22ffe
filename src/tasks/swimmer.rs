//! Swimmer-v5: a three-link swimmer in a viscous fluid (MuJoCo's inertia-box fluid forces),
//! rewarded for swimming forward along x, charged for control.

use super::{info_columns, progress, skip, sum_sq, Params, Reset, Spec, Task, Value, World, Writer};
use crate::model::Model;

/// Swimmer-v5's declaration.
pub const SPEC: Spec = Spec {
    name: "Swimmer",
    xml: "swimmer.xml",
    frame_skip: 4,
    max_episode_steps: 1000,
    camera: &[],
    params: &[
        ("forward_reward_weight", Value::Number(1.0)),
        ("ctrl_cost_weight", Value::Number(1e-4)),
        ("reset_noise_scale", Value::Number(0.1)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
    ],
    reset: Reset::Uniform,
    reset_info: &["x_position", "y_position", "distance_from_origin"],
    make: |m, p| Ok(Box::new(Swimmer::new(m, p)?)),
};

info_columns! {
    /// Swimmer's info.
    Info { rewards: [reward_forward, reward_ctrl], others: [x_position, y_position, distance_from_origin, x_velocity, y_velocity] }
}

/// Forward progress of the root's slides `qpos[0..2]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Swimmer {
    /// Weight of the forward velocity.
    pub forward_weight: f64,
    /// Weight of −‖action‖².
    pub ctrl_weight: f64,
    /// Leading qpos entries left out of the observation.
    pub skip: usize,
}

impl Swimmer {
    /// The task for `m` (a root on two slides and a hinge).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.nq < 3 {
            return Err("the model needs a planar root (three joints)".into());
        }
        Ok(Swimmer { forward_weight: p.weight("forward_reward_weight")?, ctrl_weight: p.weight("ctrl_cost_weight")?, skip: skip(m, p, 2)? })
    }
}

impl Task for Swimmer {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq - self.skip + m.nv
    }

    fn info_names(&self) -> &'static [&'static str] {
        Info::NAMES
    }

    fn reward_terms(&self) -> usize {
        Info::REWARD_TERMS
    }

    fn position(&self, _m: &Model, w: &World<'_>) -> [f64; 2] {
        [w.qpos[0], w.qpos[1]]
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer::new(obs);
        out.put(&w.qpos[self.skip..]);
        out.put(w.qvel);
        out.done();
    }

    fn evaluate(&self, _m: &Model, w: &World<'_>, _obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let [xv, yv] = progress(before, [w.qpos[0], w.qpos[1]], dt);
        Info {
            reward_forward: self.forward_weight * xv,
            reward_ctrl: -self.ctrl_weight * sum_sq(w.ctrl),
            x_position: w.qpos[0],
            y_position: w.qpos[1],
            distance_from_origin: (w.qpos[0] * w.qpos[0] + w.qpos[1] * w.qpos[1]).sqrt(),
            x_velocity: xv,
            y_velocity: yv,
        }
        .write(info);
        false
    }
}
