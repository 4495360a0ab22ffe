//! ⑤ Many worlds sharing one immutable [`Model`], stepped in parallel with rayon.
//!
//! Worlds are independent: each has its own [`Data`] (scratch and its seeded random stream) and
//! its own rows of the flat (N × nq), (N × nv), (N × nu) state arrays, so the result is
//! bit-identical for any thread count and any batch size. A world whose state leaves the finite
//! range is reset alone to qpos0 and flagged.

use std::sync::Arc;

use rayon::prelude::*;

use crate::data::Data;
use crate::model::Model;
use crate::sensors::{self, Sensors};
use crate::step::step;
use crate::task::Task;

/// Largest magnitude a state entry may reach before the world counts as diverged (MuJoCo's mjMAXVAL).
pub const MAX_STATE: f64 = 1e10;

/// Whether a state entry is NaN or beyond [`MAX_STATE`] (±inf included).
#[inline]
pub fn out_of_range(x: f64) -> bool {
    x.is_nan() || x.abs() > MAX_STATE
}

/// Scratch of N worlds and the thread pool that steps them.
pub struct Batch {
    /// The shared model.
    pub model: Arc<Model>,
    /// Per-world scratch (N).
    pub data: Vec<Data>,
    root: Vec<usize>,
    pool: rayon::ThreadPool,
    /// One zero control per world, for models without actuators (the chunk iterators need a slot).
    no_ctrl: Vec<f64>,
    /// The task outputs' slots (3 per world) of a step without a task.
    no_task: Vec<f64>,
    no_task_flag: Vec<bool>,
}

/// A task to evaluate after each world's env step, and where its outputs go.
pub struct TaskRun<'a> {
    /// The task.
    pub task: &'a Task,
    /// Observations (N × [`Task::obs_dim`]).
    pub obs: &'a mut [f64],
    /// Rewards (N): the sum of the reward terms, 0 for a diverged world.
    pub reward: &'a mut [f64],
    /// Whether the env step ended the episode (N); a diverged world's always does.
    pub terminated: &'a mut [bool],
    /// Info columns (N × [`Task::info_names`]).
    pub info: &'a mut [f64],
}

/// The flat state arrays of a batch, borrowed for one call.
pub struct BatchState<'a> {
    /// Positions (N × nq).
    pub qpos: &'a mut [f64],
    /// Velocities (N × nv).
    pub qvel: &'a mut [f64],
    /// Controls (N × nu).
    pub ctrl: &'a [f64],
    /// Simulated time per world (N).
    pub time: &'a mut [f64],
    /// Set for worlds that diverged and were reset during the call (N).
    pub diverged: &'a mut [bool],
    /// Worlds to step (N); the others keep their state and outputs.
    pub active: &'a [bool],
    /// Sensor outputs after the call, every world's rows one after another ([`Sensors`] × N).
    pub out: Sensors<'a>,
}

/// SplitMix64 finaliser: a well-mixed 64-bit value from a seed.
pub fn mix_seed(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Batch {
    /// `seeds.len()` worlds; world i draws its random friction tangents from `seeds[i]`.
    /// `num_threads` = None uses all cores.
    pub fn new(model: Arc<Model>, seeds: &[u64], num_threads: Option<usize>) -> crate::Result<Batch> {
        let data: Vec<Data> = seeds
            .iter()
            .map(|&s| {
                let mut d = Data::new(&model);
                d.rng = mix_seed(s);
                d
            })
            .collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(num_threads.unwrap_or(0))
            .build()
            .map_err(|e| crate::Error::Input(format!("cannot start the thread pool: {e}")))?;
        let no_ctrl = vec![0.0; if model.nu == 0 { data.len() } else { 0 }];
        let (no_task, no_task_flag) = (vec![0.0; 3 * data.len()], vec![false; data.len()]);
        Ok(Batch { root: sensors::body_root(&model), model, data, pool, no_ctrl, no_task, no_task_flag })
    }

    /// Number of worlds.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// Whether the batch has no worlds.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Threads in the pool.
    pub fn num_threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Re-seeds world `i`'s random stream.
    pub fn seed(&mut self, i: usize, seed: u64) {
        self.data[i].rng = mix_seed(seed);
        self.data[i].tangents.clear();
    }

    /// Advances the active worlds `n` steps in parallel, then writes their sensor outputs and, with
    /// a task, its observation, reward terms and termination (`n` steps make one env step).
    pub fn step(&mut self, st: BatchState<'_>, n: usize, task: Option<TaskRun<'_>>) {
        let m = &*self.model;
        let root = &self.root[..];
        let (nq, nv, nu, nb) = (m.nq.max(1), m.nv.max(1), m.nu.max(1), m.nbody);
        let data = &mut self.data;
        let ctrl = if m.nu == 0 { &self.no_ctrl[..] } else { st.ctrl };
        let BatchState { qpos, qvel, time, diverged, active, out, .. } = st;
        // without a task its outputs are one unused slot per world
        let (spec, obs_dim, ninfo, obs, reward, terminated, info) = match task {
            Some(t) => (Some(t.task), t.task.obs_dim(m), t.task.info_names().len(), t.obs, t.reward, t.terminated, t.info),
            None => {
                let (a, rest) = self.no_task.split_at_mut(data.len());
                let (b, c) = rest.split_at_mut(data.len());
                (None, 1, 1, a, b, &mut self.no_task_flag[..], c)
            }
        };
        let h = m.opt.timestep;
        self.pool.install(|| {
            (
                data.par_iter_mut(),
                qpos.par_chunks_mut(nq),
                qvel.par_chunks_mut(nv),
                ctrl.par_chunks(nu),
                time.par_iter_mut().zip(diverged.par_iter_mut()).zip(active.par_iter()),
                (out.xpos.par_chunks_mut(3 * nb), out.xmat.par_chunks_mut(9 * nb), out.xipos.par_chunks_mut(3 * nb)),
                (out.xvel.par_chunks_mut(6 * nb), out.cfrc_ext.par_chunks_mut(6 * nb), out.qfrc_constraint.par_chunks_mut(nv)),
                (out.cinert.par_chunks_mut(10 * nb), out.cvel.par_chunks_mut(6 * nb)),
                (obs.par_chunks_mut(obs_dim.max(1)), reward.par_iter_mut(), terminated.par_iter_mut(), info.par_chunks_mut(ninfo.max(1))),
            )
                .into_par_iter()
                .for_each(|(d, qpos, qvel, ctrl, ((time, div), &active), (xpos, xmat, xipos), (xvel, cfrc_ext, qfrc_constraint), (cinert, cvel), (obs, reward, terminated, info))| {
                    *div = false;
                    if !active {
                        return;
                    }
                    let (qpos, qvel) = (&mut qpos[..m.nq], &mut qvel[..m.nv]);
                    let ctrl = &ctrl[..m.nu];
                    let qfrc_constraint = &mut qfrc_constraint[..m.nv];
                    let mut out = Sensors { xpos, xmat, xipos, xvel, cfrc_ext, qfrc_constraint, cinert, cvel };
                    // the rewarded position before the env step, from the outputs of the state it starts in
                    let before = spec.map(|t| t.position(m, &out.world_view(qpos, qvel, ctrl)));
                    for _ in 0..n {
                        step(m, d, qpos, qvel, ctrl, time);
                        if qpos.iter().chain(qvel.iter()).any(|&x| out_of_range(x)) {
                            reset_world(m, d, qpos, qvel);
                            *div = true;
                            break;
                        }
                    }
                    sensors::write(m, root, d, qpos, qvel, out.reborrow());
                    if let (Some(t), Some(before)) = (spec, before) {
                        let w = out.world_view(qpos, qvel, ctrl);
                        t.observe(m, &w, obs);
                        *terminated = t.evaluate(m, &w, obs, before, n as f64 * h, info);
                        *reward = info[..t.reward_terms()].iter().sum();
                        // a diverged world was reset: its step earns nothing and ends the episode
                        if *div {
                            *reward = 0.0;
                            *terminated = true;
                        }
                    }
                });
        });
    }

    /// Resets world `i` to qpos0 at rest (its constraint forces cleared) in the given rows.
    pub fn reset(&mut self, i: usize, qpos: &mut [f64], qvel: &mut [f64]) {
        reset_world(&self.model, &mut self.data[i], qpos, qvel);
    }

    /// Recomputes the sensor outputs of world `i` for its current state (after a reset or a
    /// state written from Python), and a task's observation `obs` of it.
    pub fn sense(&mut self, i: usize, qpos: &[f64], qvel: &[f64], ctrl: &[f64], mut out: Sensors<'_>, task: Option<(&Task, &mut [f64])>) {
        sensors::write(&self.model, &self.root, &mut self.data[i], qpos, qvel, out.reborrow());
        if let Some((t, obs)) = task {
            t.observe(&self.model, &out.world_view(qpos, qvel, ctrl), obs);
        }
    }
}

/// Back to qpos0 at rest, with nothing carried over from before: no friction tangents, LCP warm
/// start or cached kinematics (a reset world steps exactly as a new one).
fn reset_world(m: &Model, d: &mut Data, qpos: &mut [f64], qvel: &mut [f64]) {
    qpos.copy_from_slice(&m.qpos0);
    qvel.fill(0.0);
    d.forget_history();
}
