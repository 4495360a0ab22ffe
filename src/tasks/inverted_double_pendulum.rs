//! InvertedDoublePendulum-v5: keep the tip high, near (0, 2), and slow.

use glam::DVec3;

use super::{info_columns, Params, Reset, Spec, Task, Value, World, Writer};
use crate::model::Model;

/// InvertedDoublePendulum-v5's declaration (the twin defines a camera but passes none: the
/// viewer's defaults apply).
pub const SPEC: Spec = Spec {
    name: "InvertedDoublePendulum",
    xml: "inverted_double_pendulum.xml",
    frame_skip: 5,
    max_episode_steps: 1000,
    camera: &[],
    params: &[("healthy_reward", Value::Number(10.0)), ("reset_noise_scale", Value::Number(0.1))],
    reset: Reset::UniformNormal,
    reset_info: &[],
    make: |m, p| Ok(Box::new(InvertedDoublePendulum::new(m, p)?)),
};

info_columns! {
    /// InvertedDoublePendulum's info: its three reward terms.
    Info { rewards: [reward_survive, distance_penalty, velocity_penalty], others: [] }
}

/// Tip height above 1, near (0, 2), slow.
#[derive(Clone, Debug, PartialEq)]
pub struct InvertedDoublePendulum {
    /// Reward while the tip is above 1.
    pub healthy_reward: f64,
    /// Body and body-frame position of the tip site.
    pub tip: (usize, DVec3),
}

impl InvertedDoublePendulum {
    /// The task for `m` (a cart, two hinges and a tip site).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.site_body.is_empty() || m.nv < 3 {
            return Err("the model needs a tip site and three joints".into());
        }
        Ok(InvertedDoublePendulum { healthy_reward: p.weight("healthy_reward")?, tip: (m.site_body[0], m.site_pos[0]) })
    }
}

impl Task for InvertedDoublePendulum {
    fn obs_dim(&self, m: &Model) -> usize {
        1 + 2 * (m.nq - 1) + m.nv + 1
    }

    fn info_names(&self) -> &'static [&'static str] {
        Info::NAMES
    }

    fn reward_terms(&self) -> usize {
        Info::REWARD_TERMS
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer::new(obs);
        out.put(&w.qpos[..1]);
        out.map(&w.qpos[1..], f64::sin);
        out.map(&w.qpos[1..], f64::cos);
        out.map(w.qvel, |v| v.clamp(-10.0, 10.0));
        out.map(&w.qfrc_constraint[..1], |v| v.clamp(-10.0, 10.0));
        out.done();
    }

    fn evaluate(&self, _m: &Model, w: &World<'_>, _obs: &[f64], _before: [f64; 2], _dt: f64, info: &mut [f64]) -> bool {
        let (body, pos) = self.tip;
        let (p, r) = (&w.xpos[3 * body..3 * body + 3], &w.xmat[9 * body..9 * body + 9]);
        let x = p[0] + r[0] * pos.x + r[1] * pos.y + r[2] * pos.z;
        let y = p[2] + r[6] * pos.x + r[7] * pos.y + r[8] * pos.z;
        let terminated = y <= 1.0;
        let (v1, v2) = (w.qvel[1], w.qvel[2]);
        Info {
            reward_survive: if terminated { 0.0 } else { self.healthy_reward },
            distance_penalty: -(0.01 * x * x + (y - 2.0) * (y - 2.0)),
            velocity_penalty: -(1e-3 * v1 * v1 + 5e-3 * v2 * v2),
        }
        .write(info);
        terminated
    }
}
