//! Ant-v5: a quadruped rewarded for running forward, charged for control and contact forces.

use super::{Locomotion, Params, PlaneInfo, Reset, Spec, Task, Value, World, Writer, progress};
use crate::model::Model;

/// Ant-v5's declaration.
pub const SPEC: Spec = Spec {
    name: "Ant",
    xml: "ant.xml",
    frame_skip: 5,
    max_episode_steps: 1000,
    camera: &[("distance", Value::Number(4.0))],
    params: &[
        ("forward_reward_weight", Value::Number(1.0)),
        ("ctrl_cost_weight", Value::Number(0.5)),
        ("contact_cost_weight", Value::Number(5e-4)),
        ("healthy_reward", Value::Number(1.0)),
        ("main_body", Value::Body(1)),
        ("terminate_when_unhealthy", Value::Flag(true)),
        ("healthy_z_range", Value::Range(0.2, 1.0)),
        ("contact_force_range", Value::Range(-1.0, 1.0)),
        ("reset_noise_scale", Value::Number(0.1)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
        ("include_cfrc_ext_in_observation", Value::Flag(true)),
    ],
    reset: Reset::UniformNormal,
    reset_info: &["x_position", "y_position", "distance_from_origin"],
    make: |m, p| Ok(Box::new(Ant::new(m, p)?)),
};

/// Forward progress of the main body, contact cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Ant {
    /// Weights, health, skipped positions.
    pub common: Locomotion,
    /// The body whose xy progress is rewarded.
    pub main: usize,
    /// Range cfrc_ext is clipped to.
    pub force_range: [f64; 2],
    /// Whether the clipped cfrc_ext of bodies 1.. is observed.
    pub cfrc: bool,
}

impl Ant {
    /// The task for `m` (a free root).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        let common = Locomotion::new(m, p)?;
        let main = p.index("main_body")?;
        if main >= m.nbody {
            return Err(format!("main_body {main} is not a body index (nbody = {})", m.nbody));
        }
        let (force_range, cfrc) = (p.range("contact_force_range")?, p.flag("include_cfrc_ext_in_observation")?);
        Ok(Ant { common, main, force_range, cfrc })
    }
}

impl Task for Ant {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq - self.common.skip + m.nv + if self.cfrc { 6 * (m.nbody - 1) } else { 0 }
    }

    fn info_names(&self) -> &'static [&'static str] {
        PlaneInfo::NAMES
    }

    fn reward_terms(&self) -> usize {
        PlaneInfo::REWARD_TERMS
    }

    fn position(&self, _m: &Model, w: &World<'_>) -> [f64; 2] {
        [w.xpos[3 * self.main], w.xpos[3 * self.main + 1]]
    }

    fn observe(&self, m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let [lo, hi] = self.force_range;
        let mut out = Writer::new(obs);
        out.put(&w.qpos[self.common.skip..]);
        out.put(w.qvel);
        if self.cfrc {
            out.map(&w.cfrc_ext[6..6 * m.nbody], |f| f.clamp(lo, hi));
        }
        out.done();
    }

    fn evaluate(&self, m: &Model, w: &World<'_>, _obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let v = progress(before, self.position(m, w), dt);
        let finite = w.qpos.iter().chain(w.qvel).all(|x| x.is_finite());
        let [z0, z1] = self.common.z;
        let ok = finite && z0 <= w.qpos[2] && w.qpos[2] <= z1;
        let [lo, hi] = self.force_range;
        let contact: f64 = w.cfrc_ext.iter().map(|f| f.clamp(lo, hi).powi(2)).sum();
        self.common.evaluate(w, v, self.common.contact_weight * contact, ok, info)
    }
}
