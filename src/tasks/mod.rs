//! The gymnasium tasks, each declared once in its own file: its [`Spec`] (model file, frame
//! skip, episode length, camera, keyword arguments with gymnasium's v5 defaults, how a reset
//! draws the initial state, which info the reset reports) and its [`Task`] (observation, reward
//! terms named with their values, termination), as gymnasium's MuJoCo v5 env of the same name
//! (`gymnasium/envs/mujoco/*_v5.py`) computes them. [`TASKS`] is the registry: adding a task is
//! one file and one line there. The Python layer builds its envs from the specs
//! (`envs/sinew/tasks.py`); the reset noise is drawn there, from each world's numpy generator,
//! as the twin draws it.

mod ant;
mod humanoid;
mod inverted_double_pendulum;
mod inverted_pendulum;
mod planar;
mod reacher;
mod swimmer;

use std::fmt::Debug;

pub use ant::Ant;
pub use humanoid::Humanoid;
pub use inverted_double_pendulum::InvertedDoublePendulum;
pub use inverted_pendulum::InvertedPendulum;
pub use planar::{Healthy, Planar};
pub use reacher::Reacher;
pub use swimmer::Swimmer;

use crate::model::Model;

/// Every task, in the order the envs are registered.
pub const TASKS: &[&Spec] = &[
    &inverted_pendulum::SPEC,
    &inverted_double_pendulum::SPEC,
    &reacher::SPEC,
    &swimmer::SPEC,
    &planar::HOPPER,
    &planar::WALKER2D,
    &planar::HALF_CHEETAH,
    &ant::SPEC,
    &humanoid::SPEC,
];

/// A task's declaration: what an env of it needs besides the per-step logic.
#[derive(Debug)]
pub struct Spec {
    /// The env's name (`sinew/<name>-v0`, gymnasium's `<name>-v5`).
    pub name: &'static str,
    /// The model file, in gymnasium's MuJoCo assets.
    pub xml: &'static str,
    /// Physics steps per env step (a keyword may change it).
    pub frame_skip: usize,
    /// Env steps before the time limit truncates an episode.
    pub max_episode_steps: usize,
    /// The twin's `DEFAULT_CAMERA_CONFIG`.
    pub camera: &'static [(&'static str, Value)],
    /// The v5 env's keyword arguments and their defaults.
    pub params: &'static [(&'static str, Value)],
    /// How a reset draws the initial state.
    pub reset: Reset,
    /// The info columns the twin's `reset` reports (each at the reset state).
    pub reset_info: &'static [&'static str],
    /// The task for a model, from its parameters; an error names what is wrong.
    pub make: MakeTask,
}

/// Builds a task for a model from its parameters; an error names what is wrong.
pub type MakeTask = fn(&Model, &mut dyn Params) -> Result<Box<dyn Task>, String>;

/// A parameter's or camera setting's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Number(f64),
    /// A range (low, high).
    Range(f64, f64),
    /// A flag.
    Flag(bool),
    /// A body index (Python takes its name too).
    Body(usize),
    /// A point.
    Point([f64; 3]),
}

/// How a reset draws each world's initial state from its generator (as the twin does), with
/// s = the `reset_noise_scale` parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reset {
    /// qpos0 + U(−s, s) and U(−s, s) velocities, one draw of nq + nv numbers.
    Uniform,
    /// qpos0 + U(−s, s), then s·N(0, 1) velocities.
    UniformNormal,
    /// Reacher's: the arm at qpos0 + U(−0.1, 0.1), the goal drawn in U(−0.2, 0.2)² until it lies
    /// within 0.2 of the origin, U(−0.005, 0.005) arm velocities.
    ReacherGoal,
}

/// Task `kind`: its spec.
pub fn spec(kind: &str) -> Result<&'static Spec, String> {
    TASKS.iter().copied().find(|s| s.name == kind).ok_or_else(|| format!("unknown task '{kind}'"))
}

/// Declares a task's info columns as a struct, each named once and set by name: the reward
/// terms (which sum to the reward) first, then the other columns.
macro_rules! info_columns {
    ($(#[$doc:meta])* $name:ident { rewards: [$($r:ident),* $(,)?], others: [$($o:ident),* $(,)?] $(,)? }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default)]
        pub struct $name {
            $(#[allow(missing_docs)] pub $r: f64,)*
            $(#[allow(missing_docs)] pub $o: f64,)*
        }

        impl $name {
            /// The columns' names, in order.
            pub const NAMES: &'static [&'static str] = &[$(stringify!($r),)* $(stringify!($o),)*];
            /// How many leading columns are reward terms.
            pub const REWARD_TERMS: usize = [$(stringify!($r)),*].len();

            /// Writes the columns into `info`.
            pub fn write(&self, info: &mut [f64]) {
                let values = [$(self.$r,)* $(self.$o,)*];
                info[..values.len()].copy_from_slice(&values);
            }
        }
    };
}
pub(crate) use info_columns;

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

/// What a gymnasium task computes from a world after each env step.
pub trait Task: Debug + Send + Sync {
    /// Length of the observation.
    fn obs_dim(&self, m: &Model) -> usize;

    /// Names of the info columns [`Task::evaluate`] writes; the first [`Task::reward_terms`]
    /// are the reward's terms, which sum to the reward.
    fn info_names(&self) -> &'static [&'static str];

    /// How many leading info columns are reward terms.
    fn reward_terms(&self) -> usize;

    /// The position whose change over the env step is the rewarded progress (x, y).
    fn position(&self, _m: &Model, _w: &World<'_>) -> [f64; 2] {
        [0.0; 2]
    }

    /// Writes the observation of `w` into `obs` ([`Task::obs_dim`] long).
    fn observe(&self, m: &Model, w: &World<'_>, obs: &mut [f64]);

    /// The info columns ([`Task::info_names`]) of the env step that moved [`Task::position`]
    /// from `before` over `dt`, and whether it ends the episode. `obs` is the step's observation.
    fn evaluate(&self, m: &Model, w: &World<'_>, obs: &[f64], before: [f64; 2], dt: f64, info: &mut [f64]) -> bool;
}

/// A task's parameters (the v5 env's keyword arguments) by name, each read once; errors name
/// the parameter.
pub trait Params {
    /// A finite number.
    fn weight(&mut self, name: &str) -> Result<f64, String>;
    /// A range (low ≤ high, neither NaN).
    fn range(&mut self, name: &str) -> Result<[f64; 2], String>;
    /// A boolean.
    fn flag(&mut self, name: &str) -> Result<bool, String>;
    /// A non-negative integer.
    fn index(&mut self, name: &str) -> Result<usize, String>;
}

/// Task `kind` for model `m` from `p`; an error names what is wrong.
pub fn make(kind: &str, m: &Model, p: &mut dyn Params) -> Result<Box<dyn Task>, String> {
    (spec(kind)?.make)(m, p).map_err(|e| format!("task {kind}: {e}"))
}

/// How many leading qpos entries the observation leaves out: `most` (at most nq) when
/// `exclude_current_positions_from_observation`.
fn skip(m: &Model, p: &mut dyn Params, most: usize) -> Result<usize, String> {
    Ok(if p.flag("exclude_current_positions_from_observation")? { most.min(m.nq) } else { 0 })
}

/// Index of body `name`.
fn body(m: &Model, name: &str) -> Result<usize, String> {
    m.body_id(name).ok_or_else(|| format!("the model has no body '{name}'"))
}

fn sum_sq(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

/// Velocity of the progress from `before` to `now` over `dt`.
fn progress(before: [f64; 2], now: [f64; 2], dt: f64) -> [f64; 2] {
    [(now[0] - before[0]) / dt, (now[1] - before[1]) / dt]
}

/// What Ant and Humanoid share: the free root, the reward's weights, the healthy height range and
/// the observation's skipped positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Locomotion {
    /// Weight of the forward velocity.
    pub forward_weight: f64,
    /// Weight of −‖ctrl‖².
    pub ctrl_weight: f64,
    /// Weight of the contact cost.
    pub contact_weight: f64,
    /// Reward per healthy step.
    pub healthy_reward: f64,
    /// Range of the torso height `qpos[2]` (closed for Ant, open for Humanoid).
    pub z: [f64; 2],
    /// Whether an unhealthy state ends the episode.
    pub terminate: bool,
    /// Leading qpos entries left out of the observation.
    pub skip: usize,
}

impl Locomotion {
    /// The shared parameters, for `m` (a free root).
    fn new(m: &Model, p: &mut dyn Params) -> Result<Self, String> {
        if m.nq < 7 || m.nv < 6 {
            return Err("the model needs a free root joint".into());
        }
        Ok(Locomotion {
            forward_weight: p.weight("forward_reward_weight")?,
            ctrl_weight: p.weight("ctrl_cost_weight")?,
            contact_weight: p.weight("contact_cost_weight")?,
            healthy_reward: p.weight("healthy_reward")?,
            z: p.range("healthy_z_range")?,
            terminate: p.flag("terminate_when_unhealthy")?,
            skip: skip(m, p, 2)?,
        })
    }

    /// The info ([`PlaneInfo`]) of a step with progress velocity `v`, contact cost `contact`
    /// (weighted) and health `ok`; whether it ends the episode.
    fn evaluate(&self, w: &World<'_>, v: [f64; 2], contact: f64, ok: bool, info: &mut [f64]) -> bool {
        PlaneInfo {
            reward_forward: self.forward_weight * v[0],
            reward_ctrl: -self.ctrl_weight * sum_sq(w.ctrl),
            reward_contact: -contact,
            reward_survive: if ok { self.healthy_reward } else { 0.0 },
            x_position: w.qpos[0],
            y_position: w.qpos[1],
            distance_from_origin: w.qpos[0].hypot(w.qpos[1]),
            x_velocity: v[0],
            y_velocity: v[1],
        }
        .write(info);
        !ok && self.terminate
    }
}

info_columns! {
    /// Ant's and Humanoid's info: the four reward terms, then where the root is in the plane and
    /// the progress velocity.
    PlaneInfo {
        rewards: [reward_forward, reward_ctrl, reward_contact, reward_survive],
        others: [x_position, y_position, distance_from_origin, x_velocity, y_velocity],
    }
}

/// Appends slices to an observation.
struct Writer<'a> {
    obs: &'a mut [f64],
    at: usize,
}

impl<'a> Writer<'a> {
    fn new(obs: &'a mut [f64]) -> Self {
        Writer { obs, at: 0 }
    }

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

    /// Checks that the observation is full.
    fn done(self) {
        debug_assert_eq!(self.at, self.obs.len());
    }
}
