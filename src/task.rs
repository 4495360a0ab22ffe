//! ⑤ Task logic of the gymnasium environments, run per world inside the batch's parallel step:
//! the observation, reward terms and termination of gymnasium's MuJoCo v5 env of the same name
//! (`gymnasium/envs/mujoco/*_v5.py`), from sinew's own state and sensor outputs. Reset noise, which
//! must come from each world's numpy generator to match the twin, stays in Python
//! (`envs/sinew/tasks.py`, which also holds the defaults of every parameter below).

use glam::DVec3;

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

/// One gymnasium task and its parameters (the keyword arguments of the v5 env).
#[derive(Clone, Debug, PartialEq)]
pub enum Task {
    /// Pole upright: reward 1 while `|qpos[1]| ≤ 0.2`.
    InvertedPendulum,
    /// Double pendulum: tip height above 1, near (0, 2), slow.
    InvertedDoublePendulum {
        /// Reward while the tip is above 1.
        healthy_reward: f64,
        /// Body and body-frame position of the tip site.
        tip: (usize, DVec3),
    },
    /// Two-link arm reaching for a target body.
    Reacher {
        /// Weight of −‖fingertip − target‖.
        dist_weight: f64,
        /// Weight of −‖action‖².
        ctrl_weight: f64,
        /// Fingertip and target bodies.
        bodies: (usize, usize),
    },
    /// Hopper, Walker2d, HalfCheetah: forward progress of `qpos[0]`.
    Planar {
        /// Weight of the forward velocity.
        forward_weight: f64,
        /// Weight of −‖action‖².
        ctrl_weight: f64,
        /// Leading qpos entries left out of the observation.
        skip: usize,
        /// Whether qvel is clipped to ±10 in the observation.
        clip_qvel: bool,
        /// Health conditions (Hopper, Walker2d), or none (HalfCheetah).
        healthy: Option<Healthy>,
    },
    /// Ant: forward progress of the main body, contact cost.
    Ant {
        /// Weights of forward velocity, −‖action‖², −Σ clip(cfrc_ext)², healthy.
        weights: [f64; 4],
        /// The body whose xy progress is rewarded.
        main: usize,
        /// Range of the torso height `qpos[2]` (closed).
        z: [f64; 2],
        /// Range cfrc_ext is clipped to.
        force_range: [f64; 2],
        /// Whether an unhealthy state ends the episode.
        terminate: bool,
        /// Leading qpos entries left out of the observation.
        skip: usize,
        /// Whether the clipped cfrc_ext of bodies 1.. is observed.
        cfrc: bool,
    },
    /// Humanoid: forward progress of the centre of mass.
    Humanoid {
        /// Weights of forward velocity, −‖ctrl‖², −contact cost, healthy.
        weights: [f64; 4],
        /// Range the contact cost is clipped to.
        cost_range: [f64; 2],
        /// Range of the torso height `qpos[2]` (open).
        z: [f64; 2],
        /// Whether an unhealthy state ends the episode.
        terminate: bool,
        /// Leading qpos entries left out of the observation.
        skip: usize,
        /// Which of cinert, cvel, qfrc_actuator, cfrc_ext are observed.
        parts: [bool; 4],
    },
}

/// One world's state and sensor outputs, read by a task.
pub struct World<'a> {
    /// Positions (nq).
    pub qpos: &'a [f64],
    /// Velocities (nv).
    pub qvel: &'a [f64],
    /// Controls as given: the action (nu).
    pub ctrl: &'a [f64],
    /// Body positions (nbody × 3).
    pub xpos: &'a [f64],
    /// Body rotations, row-major (nbody × 9).
    pub xmat: &'a [f64],
    /// Body centres of mass (nbody × 3).
    pub xipos: &'a [f64],
    /// Contact wrenches (nbody × 6).
    pub cfrc_ext: &'a [f64],
    /// Generalised constraint force (nv).
    pub qfrc_constraint: &'a [f64],
    /// Com-based inertias (nbody × 10).
    pub cinert: &'a [f64],
    /// Com-based velocities (nbody × 6).
    pub cvel: &'a [f64],
}

fn sum_sq(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

impl Task {
    /// Length of the observation.
    pub fn obs_dim(&self, m: &Model) -> usize {
        let nb = m.nbody - 1;
        match self {
            Task::InvertedPendulum => m.nq + m.nv,
            Task::InvertedDoublePendulum { .. } => 1 + 2 * (m.nq - 1) + m.nv + 1,
            Task::Reacher { .. } => 10,
            Task::Planar { skip, .. } => m.nq - skip + m.nv,
            Task::Ant { skip, cfrc, .. } => m.nq - skip + m.nv + if *cfrc { 6 * nb } else { 0 },
            Task::Humanoid { skip, parts, .. } => {
                let sizes = [10 * nb, 6 * nb, m.nv - 6, 6 * nb];
                m.nq - skip + m.nv + sizes.iter().zip(parts).filter(|(_, on)| **on).map(|(s, _)| s).sum::<usize>()
            }
        }
    }

    /// Names of the info columns [`Task::evaluate`] writes; the first [`Task::reward_terms`] are
    /// the reward's terms, which sum to the reward.
    pub fn info_names(&self) -> &'static [&'static str] {
        match self {
            Task::InvertedPendulum => &["reward_survive"],
            Task::InvertedDoublePendulum { .. } => &["reward_survive", "distance_penalty", "velocity_penalty"],
            Task::Reacher { .. } => &["reward_dist", "reward_ctrl"],
            Task::Planar { healthy: Some(_), .. } => {
                &["reward_forward", "reward_ctrl", "reward_survive", "x_position", "z_distance_from_origin", "x_velocity"]
            }
            Task::Planar { healthy: None, .. } => &["reward_forward", "reward_ctrl", "x_position", "x_velocity"],
            Task::Ant { .. } | Task::Humanoid { .. } => &[
                "reward_forward",
                "reward_ctrl",
                "reward_contact",
                "reward_survive",
                "x_position",
                "y_position",
                "distance_from_origin",
                "x_velocity",
                "y_velocity",
            ],
        }
    }

    /// How many leading info columns are reward terms.
    pub fn reward_terms(&self) -> usize {
        match self {
            Task::InvertedPendulum => 1,
            Task::Reacher { .. } => 2,
            Task::InvertedDoublePendulum { .. } | Task::Planar { healthy: Some(_), .. } => 3,
            Task::Planar { healthy: None, .. } => 2,
            Task::Ant { .. } | Task::Humanoid { .. } => 4,
        }
    }

    /// The position whose change over the env step is the rewarded progress (x, y).
    pub fn position(&self, m: &Model, w: &World<'_>) -> [f64; 2] {
        match self {
            Task::Planar { .. } => [w.qpos[0], 0.0],
            Task::Ant { main, .. } => [w.xpos[3 * main], w.xpos[3 * main + 1]],
            Task::Humanoid { .. } => {
                // mass-weighted xipos over all bodies (gymnasium's mass_center)
                let (mut c, mut total) = ([0.0; 2], 0.0);
                for (b, &mass) in m.body_mass.iter().enumerate() {
                    c[0] += mass * w.xipos[3 * b];
                    c[1] += mass * w.xipos[3 * b + 1];
                    total += mass;
                }
                [c[0] / total, c[1] / total]
            }
            _ => [0.0; 2],
        }
    }

    /// Writes the observation of `w` into `obs` ([`Task::obs_dim`] long).
    pub fn observe(&self, m: &Model, w: &World<'_>, obs: &mut [f64]) {
        let mut out = Writer { obs, at: 0 };
        let nb = m.nbody;
        match self {
            Task::InvertedPendulum => {
                out.put(w.qpos);
                out.put(w.qvel);
            }
            Task::InvertedDoublePendulum { .. } => {
                out.put(&w.qpos[..1]);
                out.map(&w.qpos[1..], f64::sin);
                out.map(&w.qpos[1..], f64::cos);
                out.map(w.qvel, |v| v.clamp(-10.0, 10.0));
                out.map(&w.qfrc_constraint[..1], |v| v.clamp(-10.0, 10.0));
            }
            Task::Reacher { bodies: (tip, target), .. } => {
                out.map(&w.qpos[..2], f64::cos);
                out.map(&w.qpos[..2], f64::sin);
                out.put(&w.qpos[2..]);
                out.put(&w.qvel[..2]);
                out.put(&[w.xipos[3 * tip] - w.xipos[3 * target], w.xipos[3 * tip + 1] - w.xipos[3 * target + 1]]);
            }
            Task::Planar { skip, clip_qvel, .. } => {
                out.put(&w.qpos[*skip..]);
                if *clip_qvel {
                    out.map(w.qvel, |v| v.clamp(-10.0, 10.0));
                } else {
                    out.put(w.qvel);
                }
            }
            Task::Ant { skip, cfrc, force_range: [lo, hi], .. } => {
                out.put(&w.qpos[*skip..]);
                out.put(w.qvel);
                if *cfrc {
                    out.map(&w.cfrc_ext[6..6 * nb], |f| f.clamp(*lo, *hi));
                }
            }
            Task::Humanoid { skip, parts, .. } => {
                out.put(&w.qpos[*skip..]);
                out.put(w.qvel);
                if parts[0] {
                    out.put(&w.cinert[10..10 * nb]);
                }
                if parts[1] {
                    out.put(&w.cvel[6..6 * nb]);
                }
                if parts[2] {
                    // qfrc_actuator: gear × ctrl (clamped to ctrlrange where limited) on each motor's dof
                    let start = out.at;
                    out.obs[start..start + m.nv - 6].fill(0.0);
                    for k in 0..m.nu {
                        let dof = m.jnt_dofadr[m.actuator_jnt[k]];
                        let [lo, hi] = m.actuator_ctrlrange[k];
                        let c = if m.actuator_ctrllimited[k] { w.ctrl[k].clamp(lo, hi) } else { w.ctrl[k] };
                        if dof >= 6 {
                            out.obs[start + dof - 6] += c * m.actuator_gear[k];
                        }
                    }
                    out.at += m.nv - 6;
                }
                if parts[3] {
                    out.put(&w.cfrc_ext[6..6 * nb]);
                }
            }
        }
        debug_assert_eq!(out.at, out.obs.len());
    }

    /// The info columns ([`Task::info_names`]) of the env step that moved [`Task::position`] from
    /// `before` over `dt`, and whether it ends the episode. `obs` is the step's observation.
    pub fn evaluate(&self, m: &Model, w: &World<'_>, obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool {
        let progress = |now: [f64; 2]| [(now[0] - before[0]) / dt, (now[1] - before[1]) / dt];
        let ctrl_sq = sum_sq(w.ctrl);
        match self {
            Task::InvertedPendulum => {
                let terminated = !obs.iter().all(|x| x.is_finite()) || w.qpos[1].abs() > 0.2;
                info[0] = if terminated { 0.0 } else { 1.0 };
                terminated
            }
            Task::InvertedDoublePendulum { healthy_reward, tip: (body, pos) } => {
                let (p, r) = (&w.xpos[3 * body..3 * body + 3], &w.xmat[9 * body..9 * body + 9]);
                let x = p[0] + r[0] * pos.x + r[1] * pos.y + r[2] * pos.z;
                let y = p[2] + r[6] * pos.x + r[7] * pos.y + r[8] * pos.z;
                let terminated = y <= 1.0;
                let (v1, v2) = (w.qvel[1], w.qvel[2]);
                info[0] = if terminated { 0.0 } else { *healthy_reward };
                info[1] = -(0.01 * x * x + (y - 2.0) * (y - 2.0));
                info[2] = -(1e-3 * v1 * v1 + 5e-3 * v2 * v2);
                terminated
            }
            Task::Reacher { dist_weight, ctrl_weight, bodies: (tip, target) } => {
                let d = DVec3::from_slice(&w.xipos[3 * tip..]) - DVec3::from_slice(&w.xipos[3 * target..]);
                info[0] = -d.length() * dist_weight;
                info[1] = -ctrl_sq * ctrl_weight;
                false
            }
            Task::Planar { forward_weight, ctrl_weight, healthy, .. } => {
                let xv = progress([w.qpos[0], 0.0])[0];
                info[0] = forward_weight * xv;
                info[1] = -ctrl_weight * ctrl_sq;
                match healthy {
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
            Task::Ant { weights: [wf, wc, wk, wh], main, z, force_range: [lo, hi], terminate, .. } => {
                let v = progress([w.xpos[3 * main], w.xpos[3 * main + 1]]);
                let finite = w.qpos.iter().chain(w.qvel).all(|x| x.is_finite());
                let ok = finite && z[0] <= w.qpos[2] && w.qpos[2] <= z[1];
                let contact: f64 = w.cfrc_ext.iter().map(|f| f.clamp(*lo, *hi).powi(2)).sum();
                self.planar_info(w, v, [wf * v[0], -wc * ctrl_sq, -wk * contact, if ok { *wh } else { 0.0 }], info);
                !ok && *terminate
            }
            Task::Humanoid { weights: [wf, wc, wk, wh], cost_range: [lo, hi], z, terminate, .. } => {
                let v = progress(self.position(m, w));
                let ok = z[0] < w.qpos[2] && w.qpos[2] < z[1];
                let contact = (wk * sum_sq(w.cfrc_ext)).clamp(*lo, *hi);
                self.planar_info(w, v, [wf * v[0], -wc * ctrl_sq, -contact, if ok { *wh } else { 0.0 }], info);
                !ok && *terminate
            }
        }
    }

    /// Ant's and Humanoid's info: the four reward terms, then where the root is in the plane
    /// and the progress velocity.
    fn planar_info(&self, w: &World<'_>, v: [f64; 2], terms: [f64; 4], info: &mut [f64]) {
        info[..4].copy_from_slice(&terms);
        info[4] = w.qpos[0];
        info[5] = w.qpos[1];
        info[6] = w.qpos[0].hypot(w.qpos[1]);
        info[7] = v[0];
        info[8] = v[1];
    }
}

/// Appends slices to an observation.
struct Writer<'a> {
    obs: &'a mut [f64],
    at: usize,
}

impl Writer<'_> {
    fn put(&mut self, x: &[f64]) {
        self.obs[self.at..self.at + x.len()].copy_from_slice(x);
        self.at += x.len();
    }

    fn map(&mut self, x: &[f64], f: impl Fn(f64) -> f64) {
        for (o, &v) in self.obs[self.at..self.at + x.len()].iter_mut().zip(x) {
            *o = f(v);
        }
        self.at += x.len();
    }
}
