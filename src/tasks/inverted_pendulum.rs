//! InvertedPendulum-v5: keep the pole upright.

use super::{info_columns, Reset, Spec, Task, Value, World, Writer};
use crate::model::Model;

/// InvertedPendulum-v5's declaration.
pub const SPEC: Spec = Spec {
    name: "InvertedPendulum",
    xml: "inverted_pendulum.xml",
    frame_skip: 2,
    max_episode_steps: 1000,
    camera: &[("trackbodyid", Value::Body(0)), ("distance", Value::Number(2.04))],
    params: &[("reset_noise_scale", Value::Number(0.01))],
    reset: Reset::Uniform,
    reset_info: &[],
    make: |m, _| Ok(Box::new(InvertedPendulum::new(m)?)),
};

info_columns! {
    /// InvertedPendulum's info: its one reward term.
    Info { rewards: [reward_survive], others: [] }
}

/// Reward 1 while `|qpos[1]| ≤ 0.2`.
#[derive(Clone, Debug, PartialEq)]
pub struct InvertedPendulum;

impl InvertedPendulum {
    /// The task for `m` (a cart and a hinge).
    pub fn new(m: &Model) -> Result<Self, String> {
        if m.nq < 2 {
            return Err("the model needs two joints".into());
        }
        Ok(InvertedPendulum)
    }
}

impl Task for InvertedPendulum {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq + m.nv
    }

    fn info_names(&self) -> &'static [&'static str] {
        Info::NAMES
    }

    fn reward_terms(&self) -> usize {
        Info::REWARD_TERMS
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer::new(obs);
        out.put(w.qpos);
        out.put(w.qvel);
        out.done();
    }

    fn evaluate(&self, _m: &Model, w: &World<'_>, obs: &[f64], _before: [f64; 2], _dt: f64, info: &mut [f64]) -> bool {
        let terminated = !obs.iter().all(|x| x.is_finite()) || w.qpos[1].abs() > 0.2;
        Info { reward_survive: if terminated { 0.0 } else { 1.0 } }.write(info);
        terminated
    }
}
