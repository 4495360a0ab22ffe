//! InvertedPendulum-v5: keep the pole upright.

use super::{Task, World, Writer};
use crate::model::Model;

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
        &["reward_survive"]
    }

    fn reward_terms(&self) -> usize {
        1
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer::new(obs);
        out.put(w.qpos);
        out.put(w.qvel);
        out.done();
    }

    fn evaluate(&self, _m: &Model, w: &World<'_>, obs: &[f64], _before: [f64; 2], _dt: f64, info: &mut [f64]) -> bool {
        let terminated = !obs.iter().all(|x| x.is_finite()) || w.qpos[1].abs() > 0.2;
        info[0] = if terminated { 0.0 } else { 1.0 };
        terminated
    }
}
