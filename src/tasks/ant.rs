//! Ant-v5: a quadruped rewarded for running forward, charged for control and contact forces.

use super::{PLANE_INFO, Params, Task, World, Writer, plane_info, progress, skip, sum_sq};
use crate::model::Model;

/// Forward progress of the main body, contact cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Ant {
    /// Weight of the forward velocity.
    pub forward_weight: f64,
    /// Weight of −‖action‖².
    pub ctrl_weight: f64,
    /// Weight of −Σ clip(cfrc_ext)².
    pub contact_weight: f64,
    /// Reward per healthy step.
    pub healthy_reward: f64,
    /// The body whose xy progress is rewarded.
    pub main: usize,
    /// Range of the torso height `qpos[2]` (closed).
    pub z: [f64; 2],
    /// Range cfrc_ext is clipped to.
    pub force_range: [f64; 2],
    /// Whether an unhealthy state ends the episode.
    pub terminate: bool,
    /// Leading qpos entries left out of the observation.
    pub skip: usize,
    /// Whether the clipped cfrc_ext of bodies 1.. is observed.
    pub cfrc: bool,
}

impl Ant {
    /// The task for `m` (a free root).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.nq < 7 || m.nv < 6 {
            return Err("the model needs a free root joint".into());
        }
        let (forward_weight, ctrl_weight) = (p.weight("forward_reward_weight")?, p.weight("ctrl_cost_weight")?);
        let (contact_weight, healthy_reward) = (p.weight("contact_cost_weight")?, p.weight("healthy_reward")?);
        let (z, terminate, skip) = (p.range("healthy_z_range")?, p.flag("terminate_when_unhealthy")?, skip(m, p, 2)?);
        let main = p.index("main_body")?;
        if main >= m.nbody {
            return Err(format!("main_body {main} is not a body index (nbody = {})", m.nbody));
        }
        let (force_range, cfrc) = (p.range("contact_force_range")?, p.flag("include_cfrc_ext_in_observation")?);
        Ok(Ant { forward_weight, ctrl_weight, contact_weight, healthy_reward, main, z, force_range, terminate, skip, cfrc })
    }
}

impl Task for Ant {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq - self.skip + m.nv + if self.cfrc { 6 * (m.nbody - 1) } else { 0 }
    }

    fn info_names(&self) -> &'static [&'static str] {
        PLANE_INFO
    }

    fn reward_terms(&self) -> usize {
        4
    }

    fn position(&self, _m: &Model, w: &World<'_>) -> [f64; 2] {
        [w.xpos[3 * self.main], w.xpos[3 * self.main + 1]]
    }

    fn observe(&self, m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let [lo, hi] = self.force_range;
        let mut out = Writer::new(obs);
        out.put(&w.qpos[self.skip..]);
        out.put(w.qvel);
        if self.cfrc {
            out.map(&w.cfrc_ext[6..6 * m.nbody], |f| f.clamp(lo, hi));
        }
        out.done();
    }

    fn evaluate(&self, m: &Model, w: &World<'_>, _obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let v = progress(before, self.position(m, w), dt);
        let finite = w.qpos.iter().chain(w.qvel).all(|x| x.is_finite());
        let ok = finite && self.z[0] <= w.qpos[2] && w.qpos[2] <= self.z[1];
        let [lo, hi] = self.force_range;
        let contact: f64 = w.cfrc_ext.iter().map(|f| f.clamp(lo, hi).powi(2)).sum();
        let survive = if ok { self.healthy_reward } else { 0.0 };
        plane_info(w, v, [self.forward_weight * v[0], -self.ctrl_weight * sum_sq(w.ctrl), -self.contact_weight * contact, survive], info);
        !ok && self.terminate
    }
}
