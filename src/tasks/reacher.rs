//! Reacher-v5: a two-link arm reaching for a target body.

use glam::DVec3;

use super::{body, info_columns, sum_sq, Params, Reset, Spec, Task, Value, World, Writer};
use crate::model::Model;

/// Reacher-v5's declaration.
pub const SPEC: Spec = Spec {
    name: "Reacher",
    xml: "reacher.xml",
    frame_skip: 2,
    max_episode_steps: 50,
    camera: &[("trackbodyid", Value::Body(0))],
    params: &[("reward_dist_weight", Value::Number(1.0)), ("reward_control_weight", Value::Number(1.0))],
    reset: Reset::ReacherGoal,
    reset_info: &[],
    make: |m, p| Ok(Box::new(Reacher::new(m, p)?)),
};

info_columns! {
    /// Reacher's info: its two reward terms.
    Info { rewards: [reward_dist, reward_ctrl], others: [] }
}

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
        Info::NAMES
    }

    fn reward_terms(&self) -> usize {
        Info::REWARD_TERMS
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
        Info { reward_dist: -d.length() * self.dist_weight, reward_ctrl: -sum_sq(w.ctrl) * self.ctrl_weight }.write(info);
        false
    }
}
