//! Reacher-v5: a two-link arm reaching for a target body.

use glam::DVec3;

use super::{Params, Task, World, Writer, body, sum_sq};
use crate::model::Model;

/// Reward −‖fingertip − target‖ and −‖action‖², weighted.
#[derive(Clone, Debug, PartialEq)]
pub struct Reacher {
    /// Weight of −‖fingertip − target‖.
    pub dist_weight: f64,
    /// Weight of −‖action‖².
    pub ctrl_weight: f64,
    /// Fingertip and target bodies.
    pub bodies: (usize, usize),
}

impl Reacher {
    /// The task for `m` (two hinges, bodies `fingertip` and `target`).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.nq < 2 || m.nv < 2 {
            return Err("the model needs two joints".into());
        }
        let bodies = (body(m, "fingertip")?, body(m, "target")?);
        Ok(Reacher { dist_weight: p.weight("reward_dist_weight")?, ctrl_weight: p.weight("reward_control_weight")?, bodies })
    }
}

impl Task for Reacher {
    fn obs_dim(&self, _m: &Model) -> usize {
        10
    }

    fn info_names(&self) -> &'static [&'static str] {
        &["reward_dist", "reward_ctrl"]
    }

    fn reward_terms(&self) -> usize {
        2
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let (tip, target) = self.bodies;
        let mut out = Writer::new(obs);
        out.map(&w.qpos[..2], f64::cos);
        out.map(&w.qpos[..2], f64::sin);
        out.put(&w.qpos[2..]);
        out.put(&w.qvel[..2]);
        out.put(&[w.xipos[3 * tip] - w.xipos[3 * target], w.xipos[3 * tip + 1] - w.xipos[3 * target + 1]]);
        out.done();
    }

    fn evaluate(&self, _m: &Model, w: &World<'_>, _obs: &[f64], _before: [f64; 2], _dt: f64, info: &mut [f64]) -> bool {
        let (tip, target) = self.bodies;
        let d = DVec3::from_slice(&w.xipos[3 * tip..]) - DVec3::from_slice(&w.xipos[3 * target..]);
        info[0] = -d.length() * self.dist_weight;
        info[1] = -sum_sq(w.ctrl) * self.ctrl_weight;
        false
    }
}
