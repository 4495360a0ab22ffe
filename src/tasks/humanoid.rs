//! Humanoid-v5: a humanoid rewarded for moving its centre of mass forward, charged for control
//! and contact forces.

use super::{Locomotion, Params, PlaneInfo, Reset, Spec, Task, Value, World, Writer, progress, sum_sq};
use crate::model::Model;

/// Humanoid-v5's declaration.
pub const SPEC: Spec = Spec {
    name: "Humanoid",
    xml: "humanoid.xml",
    frame_skip: 5,
    max_episode_steps: 1000,
    camera: &[("trackbodyid", Value::Body(1)), ("distance", Value::Number(4.0)), ("lookat", Value::Point([0.0, 0.0, 2.0])), ("elevation", Value::Number(-20.0))],
    params: &[
        ("forward_reward_weight", Value::Number(1.25)),
        ("ctrl_cost_weight", Value::Number(0.1)),
        ("contact_cost_weight", Value::Number(5e-7)),
        ("contact_cost_range", Value::Range(f64::NEG_INFINITY, 10.0)),
        ("healthy_reward", Value::Number(5.0)),
        ("terminate_when_unhealthy", Value::Flag(true)),
        ("healthy_z_range", Value::Range(1.0, 2.0)),
        ("reset_noise_scale", Value::Number(1e-2)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
        ("include_cinert_in_observation", Value::Flag(true)),
        ("include_cvel_in_observation", Value::Flag(true)),
        ("include_qfrc_actuator_in_observation", Value::Flag(true)),
        ("include_cfrc_ext_in_observation", Value::Flag(true)),
    ],
    reset: Reset::Uniform,
    reset_info: &["x_position", "y_position", "distance_from_origin"],
    make: |m, p| Ok(Box::new(Humanoid::new(m, p)?)),
};

/// Forward progress of the centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub struct Humanoid {
    /// Weights, health, skipped positions.
    pub common: Locomotion,
    /// Range the contact cost is clipped to.
    pub cost_range: [f64; 2],
    /// Which of cinert, cvel, qfrc_actuator, cfrc_ext are observed.
    pub parts: [bool; 4],
}

impl Humanoid {
    /// The task for `m` (a free root).
    pub fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        let common = Locomotion::new(m, p)?;
        let parts = [
            p.flag("include_cinert_in_observation")?,
            p.flag("include_cvel_in_observation")?,
            p.flag("include_qfrc_actuator_in_observation")?,
            p.flag("include_cfrc_ext_in_observation")?,
        ];
        Ok(Humanoid { common, cost_range: p.range("contact_cost_range")?, parts })
    }
}

impl Task for Humanoid {
    fn obs_dim(&self, m: &Model) -> usize {
        let nb = m.nbody - 1;
        let sizes = [10 * nb, 6 * nb, m.nv - 6, 6 * nb];
        m.nq - self.common.skip + m.nv + sizes.iter().zip(self.parts).filter(|(_, on)| *on).map(|(s, _)| s).sum::<usize>()
    }

    fn info_names(&self) -> &'static [&'static str] {
        PlaneInfo::NAMES
    }

    fn reward_terms(&self) -> usize {
        PlaneInfo::REWARD_TERMS
    }

    /// The mass-weighted xipos over all bodies (gymnasium's `mass_center`).
    fn position(&self, m: &Model, w: &World<'_>) -> [f64; 2] {
        let (mut c, mut total) = ([0.0; 2], 0.0);
        for (b, &mass) in m.body_mass.iter().enumerate() {
            c[0] += mass * w.xipos[3 * b];
            c[1] += mass * w.xipos[3 * b + 1];
            total += mass;
        }
        [c[0] / total, c[1] / total]
    }

    fn observe(&self, m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let nb = m.nbody;
        let mut out = Writer::new(obs);
        out.put(&w.qpos[self.common.skip..]);
        out.put(w.qvel);
        if self.parts[0] {
            out.put(&w.cinert[10..10 * nb]);
        }
        if self.parts[1] {
            out.put(&w.cvel[6..6 * nb]);
        }
        if self.parts[2] {
            // qfrc_actuator of the motors: ctrl (clamped to ctrlrange where limited) times each
            // moment arm (gear) on its dof
            let start = out.at;
            out.obs[start..start + m.nv - 6].fill(0.0);
            for k in 0..m.nu {
                let [lo, hi] = m.actuator_ctrlrange[k];
                let c = if m.actuator_ctrllimited[k] { w.ctrl[k].clamp(lo, hi) } else { w.ctrl[k] };
                for arm in m.moment(k).iter().filter(|arm| arm.dof >= 6) {
                    out.obs[start + arm.dof - 6] += c * arm.coef;
                }
            }
            out.at += m.nv - 6;
        }
        if self.parts[3] {
            out.put(&w.cfrc_ext[6..6 * nb]);
        }
        out.done();
    }

    fn evaluate(&self, m: &Model, w: &World<'_>, _obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let v = progress(before, self.position(m, w), dt);
        let [z0, z1] = self.common.z;
        let ok = z0 < w.qpos[2] && w.qpos[2] < z1;
        let [lo, hi] = self.cost_range;
        let contact = (self.common.contact_weight * sum_sq(w.cfrc_ext)).clamp(lo, hi);
        self.common.evaluate(w, v, contact, ok, info)
    }
}
