//! Hopper-v5, Walker2d-v5 and HalfCheetah-v5: a planar body rewarded for running forward along
//! x; Hopper and Walker2d also for staying healthy. The three differ only in their parameters.

use super::{Params, Task, World, Writer, progress, skip, sum_sq};
use crate::model::Model;

/// Healthy-state conditions of Hopper and Walker2d (open intervals).
#[derive(Clone, Debug, PartialEq)]
pub struct Healthy {
    /// Reward per healthy step.
    pub reward: f64,
    /// Range of the torso height `qpos[1]`.
    pub z: [f64; 2],
    /// Range of the torso angle `qpos[2]`.
    pub angle: [f64; 2],
    /// Range of every entry of (qpos, qvel) after the first two (Hopper), or none.
    pub state: Option<[f64; 2]>,
    /// Whether an unhealthy state ends the episode.
    pub terminate: bool,
}

/// Forward progress of `qpos[0]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Planar {
    /// Weight of the forward velocity.
    pub forward_weight: f64,
    /// Weight of −‖action‖².
    pub ctrl_weight: f64,
    /// Leading qpos entries left out of the observation.
    pub skip: usize,
    /// Whether qvel is clipped to ±10 in the observation.
    pub clip_qvel: bool,
    /// Health conditions (Hopper, Walker2d), or none (HalfCheetah).
    pub healthy: Option<Healthy>,
}

impl Planar {
    /// Task `kind` (`Hopper`, `Walker2d` or `HalfCheetah`) for `m` (a planar root).
    pub fn new(kind: &str, m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.nq < 3 {
            return Err("the model needs a planar root (three joints)".into());
        }
        let healthy = if kind == "HalfCheetah" {
            None
        } else {
            Some(Healthy {
                reward: p.weight("healthy_reward")?,
                z: p.range("healthy_z_range")?,
                angle: p.range("healthy_angle_range")?,
                state: if kind == "Hopper" { Some(p.range("healthy_state_range")?) } else { None },
                terminate: p.flag("terminate_when_unhealthy")?,
            })
        };
        Ok(Planar {
            forward_weight: p.weight("forward_reward_weight")?,
            ctrl_weight: p.weight("ctrl_cost_weight")?,
            skip: skip(m, p, 1)?,
            clip_qvel: kind != "HalfCheetah",
            healthy,
        })
    }
}

impl Task for Planar {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq - self.skip + m.nv
    }

    fn info_names(&self) -> &'static [&'static str] {
        match self.healthy {
            Some(_) => &["reward_forward", "reward_ctrl", "reward_survive", "x_position", "z_distance_from_origin", "x_velocity"],
            None => &["reward_forward", "reward_ctrl", "x_position", "x_velocity"],
        }
    }

    fn reward_terms(&self) -> usize {
        if self.healthy.is_some() { 3 } else { 2 }
    }

    fn position(&self, _m: &Model, w: &World<'_>) -> [f64; 2] {
        [w.qpos[0], 0.0]
    }

    fn observe(&self, _m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer::new(obs);
        out.put(&w.qpos[self.skip..]);
        if self.clip_qvel {
            out.map(w.qvel, |v| v.clamp(-10.0, 10.0));
        } else {
            out.put(w.qvel);
        }
        out.done();
    }

    fn evaluate(&self, m: &Model, w: &World<'_>, _obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let xv = progress(before, [w.qpos[0], 0.0], dt)[0];
        info[0] = self.forward_weight * xv;
        info[1] = -self.ctrl_weight * sum_sq(w.ctrl);
        match &self.healthy {
            None => {
                info[2] = w.qpos[0];
                info[3] = xv;
                false
            }
            Some(h) => {
                let inside = |x: f64, [lo, hi]: [f64; 2]| lo < x && x < hi;
                let state_ok = h.state.is_none_or(|r| w.qpos[2..].iter().chain(w.qvel).all(|&x| inside(x, r)));
                let ok = state_ok && inside(w.qpos[1], h.z) && inside(w.qpos[2], h.angle);
                info[2] = if ok { h.reward } else { 0.0 };
                info[3] = w.qpos[0];
                info[4] = w.qpos[1] - m.qpos0[1];
                info[5] = xv;
                !ok && h.terminate
            }
        }
    }
}
