//! Ant-v5: a quadruped rewarded for running forward, charged for control and contact forces.

use super::{Locomotion, PLANE_INFO, Params, Task, World, Writer, progress};
use crate::model::Model;

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
