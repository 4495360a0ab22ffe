//! Hopper-v5, Walker2d-v5 and HalfCheetah-v5: a planar body rewarded for running forward along
//! x; Hopper and Walker2d also for staying healthy. The three differ only in their parameters.

use super::{info_columns, progress, skip, sum_sq, Params, Reset, Spec, Task, Value, World, Writer};
use crate::model::Model;

/// Hopper-v5's declaration.
pub const HOPPER: Spec = Spec {
    name: "Hopper",
    xml: "hopper.xml",
    frame_skip: 4,
    max_episode_steps: 1000,
    camera: &[("trackbodyid", Value::Body(2)), ("distance", Value::Number(3.0)), ("lookat", Value::Point([0.0, 0.0, 1.15])), ("elevation", Value::Number(-20.0))],
    params: &[
        ("forward_reward_weight", Value::Number(1.0)),
        ("ctrl_cost_weight", Value::Number(1e-3)),
        ("healthy_reward", Value::Number(1.0)),
        ("terminate_when_unhealthy", Value::Flag(true)),
        ("healthy_state_range", Value::Range(-100.0, 100.0)),
        ("healthy_z_range", Value::Range(0.7, f64::INFINITY)),
        ("healthy_angle_range", Value::Range(-0.2, 0.2)),
        ("reset_noise_scale", Value::Number(5e-3)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
    ],
    reset: Reset::Uniform,
    reset_info: &["x_position", "z_distance_from_origin"],
    make: |m, p| Ok(Box::new(Planar::new(m, p, Variant { healthy: true, state_range: true })?)),
};

/// Walker2d-v5's declaration.
pub const WALKER2D: Spec = Spec {
    name: "Walker2d",
    xml: "walker2d_v5.xml",
    frame_skip: 4,
    max_episode_steps: 1000,
    camera: &[("trackbodyid", Value::Body(2)), ("distance", Value::Number(4.0)), ("lookat", Value::Point([0.0, 0.0, 1.15])), ("elevation", Value::Number(-20.0))],
    params: &[
        ("forward_reward_weight", Value::Number(1.0)),
        ("ctrl_cost_weight", Value::Number(1e-3)),
        ("healthy_reward", Value::Number(1.0)),
        ("terminate_when_unhealthy", Value::Flag(true)),
        ("healthy_z_range", Value::Range(0.8, 2.0)),
        ("healthy_angle_range", Value::Range(-1.0, 1.0)),
        ("reset_noise_scale", Value::Number(5e-3)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
    ],
    reset: Reset::Uniform,
    reset_info: &["x_position", "z_distance_from_origin"],
    make: |m, p| Ok(Box::new(Planar::new(m, p, Variant { healthy: true, state_range: false })?)),
};

/// HalfCheetah-v5's declaration.
pub const HALF_CHEETAH: Spec = Spec {
    name: "HalfCheetah",
    xml: "half_cheetah.xml",
    frame_skip: 5,
    max_episode_steps: 1000,
    camera: &[("distance", Value::Number(4.0))],
    params: &[
        ("forward_reward_weight", Value::Number(1.0)),
        ("ctrl_cost_weight", Value::Number(0.1)),
        ("reset_noise_scale", Value::Number(0.1)),
        ("exclude_current_positions_from_observation", Value::Flag(true)),
    ],
    reset: Reset::UniformNormal,
    reset_info: &["x_position"],
    make: |m, p| Ok(Box::new(Planar::new(m, p, Variant { healthy: false, state_range: false })?)),
};

/// What tells the three planar tasks apart.
#[derive(Clone, Copy, Debug)]
pub struct Variant {
    /// Rewarded and ended by health (Hopper, Walker2d); qvel observed clipped to ±10.
    pub healthy: bool,
    /// Health also bounds every entry of (qpos, qvel) after the first two (Hopper).
    pub state_range: bool,
}

info_columns! {
    /// HalfCheetah's info.
    Info { rewards: [reward_forward, reward_ctrl], others: [x_position, x_velocity] }
}

info_columns! {
    /// Hopper's and Walker2d's info.
    HealthyInfo { rewards: [reward_forward, reward_ctrl, reward_survive], others: [x_position, z_distance_from_origin, x_velocity] }
}

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
    /// The task `variant` for `m` (a planar root).
    pub fn new(m: &Model, p: &mut dyn Params, variant: Variant) -> Result<Self, String> {
        if m.nq < 3 {
            return Err("the model needs a planar root (three joints)".into());
        }
        let healthy = if variant.healthy {
            Some(Healthy {
                reward: p.weight("healthy_reward")?,
                z: p.range("healthy_z_range")?,
                angle: p.range("healthy_angle_range")?,
                state: if variant.state_range { Some(p.range("healthy_state_range")?) } else { None },
                terminate: p.flag("terminate_when_unhealthy")?,
            })
        } else {
            None
        };
        Ok(Planar {
            forward_weight: p.weight("forward_reward_weight")?,
            ctrl_weight: p.weight("ctrl_cost_weight")?,
            skip: skip(m, p, 1)?,
            clip_qvel: variant.healthy,
            healthy,
        })
    }
}

impl Task for Planar {
    fn obs_dim(&self, m: &Model) -> usize {
        m.nq - self.skip + m.nv
    }

    fn info_names(&self) -> &'static [&'static str] {
        if self.healthy.is_some() { HealthyInfo::NAMES } else { Info::NAMES }
    }

    fn reward_terms(&self) -> usize {
        if self.healthy.is_some() { HealthyInfo::REWARD_TERMS } else { Info::REWARD_TERMS }
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
        let (reward_forward, reward_ctrl) = (self.forward_weight * xv, -self.ctrl_weight * sum_sq(w.ctrl));
        match &self.healthy {
            None => {
                Info { reward_forward, reward_ctrl, x_position: w.qpos[0], x_velocity: xv }.write(info);
                false
            }
            Some(h) => {
                let inside = |x: f64, [lo, hi]: [f64; 2]| lo < x && x < hi;
                let state_ok = h.state.is_none_or(|r| w.qpos[2..].iter().chain(w.qvel).all(|&x| inside(x, r)));
                let ok = state_ok && inside(w.qpos[1], h.z) && inside(w.qpos[2], h.angle);
                HealthyInfo {
                    reward_forward,
                    reward_ctrl,
                    reward_survive: if ok { h.reward } else { 0.0 },
                    x_position: w.qpos[0],
                    z_distance_from_origin: w.qpos[1] - m.qpos0[1],
                    x_velocity: xv,
                }
                .write(info);
                !ok && h.terminate
            }
        }
    }
}
