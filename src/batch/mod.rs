//! Many worlds sharing one immutable [`Model`], stepped in parallel: the calling thread takes
//! worlds one at a time from the front of a shared queue, the workers of a rayon pool from its
//! back.
//!
//! Worlds are independent: each keeps its own [`Kept`] (its history with its seeded random stream,
//! the caches its next step reads, the forces read after its step) and its own rows of the flat
//! (N × nq), (N × nv), (N × nu) state arrays, so the result is bit-identical for any thread count
//! and any batch size. A step's scratch is the threads': each has one [`Data`], which takes a
//! world's keeping for the world's step ([`Data::with_kept`]). A world whose state leaves the
//! finite range is reset alone to qpos0 and flagged.

use std::sync::{Arc, Mutex};

use crate::constraint::lcp::LcpStats;
use crate::collision::{self, CollisionData};
use crate::compile::params::{self, Param};
use crate::dynamics::kinematics::{self, KinData};
use crate::sensordata;
use crate::step::data::{Data, Kept};
use crate::model::Model;
use crate::sensors::{self, Sensors};
use crate::state::WorldState;
use crate::step::run::{advance, guarded};
use crate::tasks::Task;

mod workers;
use workers::Workers;

pub use crate::math::{out_of_range, MAX_STATE};

/// Most threads a batch accepts (a thread each costs its stack; beyond this a count is a mistake).
pub const MAX_THREADS: usize = 1024;

/// Most worlds a batch accepts.
pub const MAX_WORLDS: usize = 1 << 20;

/// Scratch of N worlds and the thread pool that steps them.
pub struct Batch {
    /// The shared model.
    pub model: Arc<Model>,
    /// What each world keeps between its steps (N).
    pub data: Vec<Kept>,
    /// The worlds' own models, where [`Batch::set_param`] gave them values of their own (N).
    own: Vec<Option<Box<Model>>>,
    root: Vec<usize>,
    /// Threads that step worlds, the calling one included.
    threads: usize,
    /// The scratch of each thread, which takes a world's keeping for its step: the calling
    /// thread's first, then each worker's.
    scratch: Vec<Mutex<Data>>,
    /// The `threads − 1` workers beside the calling thread (None for one thread).
    workers: Option<Workers>,
    /// One zero control per world, for models without actuators (the chunk iterators need a slot).
    no_ctrl: Vec<f64>,
    /// Stand-in activations (one per world) for a model without any.
    no_act: Vec<f64>,
    /// The task outputs' slots (3 per world) of a step without a task.
    no_task: Vec<f64>,
    no_task_flag: Vec<bool>,
    /// The readings' slots (one per world) of a step that reads no sensors.
    no_sensors: Vec<f64>,
}

/// A task to evaluate after each world's env step, and where its outputs go.
pub struct TaskRun<'a> {
    /// The task.
    pub task: &'a dyn Task,
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
    /// Actuator activations (N × na).
    pub act: &'a mut [f64],
    /// Simulated time per world (N).
    pub time: &'a mut [f64],
    /// Set for worlds that diverged and were reset during the call (N).
    pub diverged: &'a mut [bool],
    /// Worlds to step (N); the others keep their state and outputs.
    pub active: &'a [bool],
    /// Sensor outputs after the call, every world's rows one after another ([`Sensors`] × N).
    pub out: Sensors<'a>,
    /// File sensors (indices) to read after the call, as [`Batch::read_sensors`] reads them
    /// (none: nothing is read).
    pub sensors: &'a [usize],
    /// Their readings after the call (N × their total dimension; unused without sensors).
    pub sensordata: &'a mut [f64],
}

impl Batch {
    /// `seeds.len()` worlds; world i draws its random friction tangents from `seeds[i]`.
    /// `num_threads` = None uses all cores (`std::thread::available_parallelism`).
    pub fn new(model: Arc<Model>, seeds: &[u64], num_threads: Option<usize>) -> crate::error::Result<Batch> {
        if seeds.len() > MAX_WORLDS {
            return Err(crate::error::Error::Input(format!("a batch holds at most {MAX_WORLDS} worlds, got {}", seeds.len())));
        }
        if num_threads.is_some_and(|t| t > MAX_THREADS) {
            return Err(crate::error::Error::Input(format!("num_threads must be at most {MAX_THREADS}, got {}", num_threads.unwrap_or(0))));
        }
        let data: Vec<Kept> = seeds.iter().map(|&s| Kept::new(&model, s)).collect();
        // no more threads than worlds: a thread with no world would only wake and linger
        let threads = num_threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).clamp(1, seeds.len().max(1));
        // the calling thread steps worlds too: a pool of one fewer, none for one thread (waking a
        // worker costs each call tens of microseconds on a loaded machine)
        let workers = if threads == 1 { None } else { Some(Workers::new(threads - 1)?) };
        let no_ctrl = vec![0.0; if model.nu == 0 { data.len() } else { 0 }];
        let no_act = vec![0.0; if model.na == 0 { data.len() } else { 0 }];
        let (no_task, no_task_flag) = (vec![0.0; 3 * data.len()], vec![false; data.len()]);
        let scratch = (0..threads).map(|_| Mutex::new(Data::new(&model))).collect();
        let no_sensors = vec![0.0; data.len()];
        Ok(Batch { root: sensors::body_root(&model), own: (0..seeds.len()).map(|_| None).collect(), model, data, threads, scratch, workers, no_ctrl, no_act, no_task, no_task_flag, no_sensors })
    }

    /// Number of worlds.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// Whether the batch has no worlds.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Threads that step worlds (the calling thread and the pool's workers): the number asked
    /// for, or every core, but never more than there are worlds.
    pub fn num_threads(&self) -> usize {
        self.threads
    }

    /// World `i`'s model: the shared one, or its own after [`Batch::set_param`].
    pub fn model_of(&self, i: usize) -> &Model {
        world_model(&self.own, &self.model, i)
    }

    /// Gives the worlds `which` the values `values` of field `p` (one row of
    /// [`Param::shape`] per world, in `which`'s order) and forgets their warm starts. Every
    /// value is checked first: on an error naming the world and the field, no world changes.
    pub fn set_param(&mut self, p: Param, which: &[usize], values: &[f64]) -> crate::error::Result<()> {
        let (rows, cols) = p.shape(&self.model);
        let len = rows * cols;
        if values.len() != which.len() * len {
            return Err(crate::error::Error::Input(format!("{} takes {rows} × {cols} values per world, got {} for {} worlds", p.name(), values.len(), which.len())));
        }
        let changed = (which.iter().zip(values.chunks(len.max(1))))
            .map(|(&i, row)| {
                let mut m = self.model_of(i).clone();
                p.check(&m, row).map_err(|e| crate::error::Error::Input(format!("world {i}: {e}")))?;
                p.write(&mut m, row).map_err(|e| crate::error::Error::Input(format!("world {i}: {}: {e}", p.name())))?;
                Ok((i, m))
            })
            .collect::<crate::error::Result<Vec<_>>>()?;
        for (i, m) in changed {
            self.own[i] = Some(Box::new(m));
            self.data[i].forget_history();
        }
        Ok(())
    }

    /// Field `p` of every world, one row of [`Param::shape`] after another.
    pub fn param(&self, p: Param) -> Vec<f64> {
        (0..self.len()).flat_map(|i| p.read(self.model_of(i))).collect()
    }

    /// Gives the worlds `which` the shared model's values back (and forgets their warm starts).
    pub fn reset_params(&mut self, which: &[usize]) {
        for &i in which {
            if self.own[i].take().is_some() {
                self.data[i].forget_history();
            }
        }
    }

    /// The worlds with values of their own.
    pub fn varied(&self) -> Vec<usize> {
        (0..self.len()).filter(|&i| self.own[i].is_some()).collect()
    }

    /// World `i`'s own rotational inertias (nbody 3 × 3 matrices, columns), bit for bit: a
    /// copy's with [`Batch::restore_params`] (principal moments would round).
    pub fn inertia_matrices(&self, i: usize) -> Vec<f64> {
        params::read_inertia_matrices(self.model_of(i))
    }

    /// Gives world `i` the values a copy read from another world: every field of
    /// [`Param::ALL`] (in that order) and its [`Batch::inertia_matrices`].
    pub fn restore_params(&mut self, i: usize, fields: &[Vec<f64>], inertia: &[f64]) -> crate::error::Result<()> {
        let mut m = (*self.model).clone();
        params::restore(&mut m, fields, inertia).map_err(|e| crate::error::Error::Input(format!("world {i}: {e}")))?;
        self.own[i] = Some(Box::new(m));
        self.data[i].forget_history();
        Ok(())
    }

    /// Re-seeds world `i`'s random stream.
    pub fn seed(&mut self, i: usize, seed: u64) {
        self.data[i].seed(seed);
    }

    /// Advances the active worlds `n` steps in parallel, then writes their sensor outputs, the
    /// readings of `st.sensors` and, with a task, its observation, reward terms and termination
    /// (`n` steps make one env step).
    pub fn step(&mut self, st: BatchState<'_>, n: usize, task: Option<TaskRun<'_>>) {
        let m = &*self.model;
        let root = &self.root[..];
        let (nq, nv, nu, na, nb) = (m.nq.max(1), m.nv.max(1), m.nu.max(1), m.na.max(1), m.nbody);
        let data = &mut self.data;
        let own = &self.own;
        let ctrl = if m.nu == 0 { &self.no_ctrl[..] } else { st.ctrl };
        let BatchState { qpos, qvel, act, time, diverged, active, out, sensors: which, sensordata, .. } = st;
        let dim: usize = which.iter().map(|&k| m.sensor_kind[k].dim()).sum();
        let sensordata = if dim == 0 { &mut self.no_sensors[..] } else { sensordata };
        // without activations, one unused slot per world
        let act = if m.na == 0 { &mut self.no_act[..] } else { act };
        // without a task its outputs are one unused slot per world
        let (spec, obs_dim, ninfo, obs, reward, terminated, info) = match task {
            Some(t) => (Some(t.task), t.task.obs_dim(m), t.task.info_names().len(), t.obs, t.reward, t.terminated, t.info),
            None => {
                let (a, rest) = self.no_task.split_at_mut(data.len());
                let (b, c) = rest.split_at_mut(data.len());
                (None, 1, 1, a, b, &mut self.no_task_flag[..], c)
            }
        };
        // one world per item
        let worlds = data
            .iter_mut()
            .enumerate()
            .map(|(i, d)| (d, world_model(own, m, i)))
            .zip(qpos.chunks_mut(nq).zip(qvel.chunks_mut(nv)).zip(ctrl.chunks(nu)).zip(act.chunks_mut(na)))
            .zip(time.iter_mut().zip(diverged.iter_mut()).zip(active.iter()))
            .zip(out.xpos.chunks_mut(3 * nb).zip(out.xmat.chunks_mut(9 * nb)).zip(out.xipos.chunks_mut(3 * nb)))
            .zip(out.xvel.chunks_mut(6 * nb).zip(out.cfrc_ext.chunks_mut(6 * nb)).zip(out.qfrc_constraint.chunks_mut(nv)))
            .zip(out.cinert.chunks_mut(10 * nb).zip(out.cvel.chunks_mut(6 * nb)))
            .zip(obs.chunks_mut(obs_dim.max(1)).zip(reward.iter_mut()).zip(terminated.iter_mut()).zip(info.chunks_mut(ninfo.max(1))))
            .zip(sensordata.chunks_mut(dim.max(1)))
            .map(|((((((((d, model), (((qpos, qvel), ctrl), act)), ((time, diverged), &active)), ((xpos, xmat), xipos)), ((xvel, cfrc_ext), qfrc_constraint)), (cinert, cvel)), (((obs, reward), terminated), info)), readings)| World {
                model,
                data: d,
                state: WorldState { time, qpos: &mut qpos[..m.nq], qvel: &mut qvel[..m.nv], ctrl: &ctrl[..m.nu], act: &mut act[..m.na] },
                diverged,
                active,
                out: Sensors { xpos, xmat, xipos, xvel, cfrc_ext, qfrc_constraint: &mut qfrc_constraint[..m.nv], cinert, cvel },
                obs,
                reward,
                terminated,
                info,
                sensors: which,
                readings,
            });
        share_out(self.workers.as_ref(), &self.scratch, worlds, |w, scratch| env_step(root, spec, n, w, scratch));
    }

    /// Resets world `i` to qpos0 at rest (its constraint and applied body forces cleared) in the
    /// given rows.
    pub fn reset(&mut self, i: usize, qpos: &mut [f64], qvel: &mut [f64], act: &mut [f64]) {
        reset_state(world_model(&self.own, &self.model, i), qpos, qvel, act);
        self.data[i].forget_history();
        self.data[i].set_xfrc_applied(&[]);
    }

    /// The readings of the file sensors `which` (indices) of every world at the state in `st`
    /// (every world's rows one after another), the worlds in parallel.
    pub fn read_sensors(&mut self, st: sensordata::State<'_>, which: &[usize], chosen: Option<&[bool]>) -> Vec<f64> {
        let m = &*self.model;
        let dim: usize = which.iter().map(|&k| m.sensor_kind[k].dim()).sum();
        let rows = chosen.map_or(self.data.len(), |c| c.iter().filter(|&&x| x).count());
        let mut out = vec![0.0; rows * dim];
        let own = &self.own;
        let picked = self.data.iter_mut().enumerate().filter(|(i, _)| chosen.is_none_or(|c| c[*i]));
        let worlds: Vec<_> = picked.zip(out.chunks_mut(dim.max(1))).map(|((i, d), row)| (i, (d, row))).collect();
        share_out(self.workers.as_ref(), &self.scratch, worlds.into_iter(), |(i, (d, row)), scratch| {
            let m = world_model(own, m, i);
            let s = sensordata::State {
                qpos: &st.qpos[i * m.nq..(i + 1) * m.nq],
                qvel: &st.qvel[i * m.nv..(i + 1) * m.nv],
                ctrl: &st.ctrl[i * m.nu..(i + 1) * m.nu],
                act: &st.act[i * m.na..(i + 1) * m.na],
            };
            scratch.with_kept(d, |d| sensordata::read(m, d, s, which, row));
        });
        out
    }

    /// The worlds' solver counters since they were made, summed (the residual: the largest of
    /// their last solves): LCP statistics, impacts, projections.
    pub fn constraint_stats(&self) -> (LcpStats, u64, u64) {
        let mut total = (LcpStats::default(), 0, 0);
        for kept in &self.data {
            let (s, impacts, projections) = kept.stats();
            total.0.add(s);
            (total.1, total.2) = (total.1 + impacts, total.2 + projections);
        }
        total
    }

    /// How many contacts penetrate (distance < 0) in each world's configuration (rows of
    /// `qpos`, `qvel`): MuJoCo's `ncon` after `mj_forward` where margins are zero.
    pub fn penetrations(&mut self, qpos: &[f64], qvel: &[f64]) -> Vec<usize> {
        let shared = &*self.model;
        let mut coll = CollisionData::new(shared);
        let mut kin = KinData::new(shared);
        (0..self.data.len())
            .map(|i| {
                // a world's own model: its own terrain, say
                let m = world_model(&self.own, shared, i);
                kinematics::forward(m, &qpos[i * m.nq..(i + 1) * m.nq], &qvel[i * m.nv..(i + 1) * m.nv], &mut kin);
                collision::penetrations(m, &kin, &mut coll);
                coll.contacts.len()
            })
            .collect()
    }

    /// Recomputes the sensor outputs of world `i` for its current state (after a reset or a
    /// state written from Python), and a task's observation `obs` of it.
    pub fn sense(&mut self, i: usize, qpos: &[f64], qvel: &[f64], ctrl: &[f64], mut out: Sensors<'_>, task: Option<(&dyn Task, &mut [f64])>) {
        let m = world_model(&self.own, &self.model, i);
        let (d, scratch) = (&mut self.data[i], scratch_here(&mut self.scratch));
        scratch.with_kept(d, |d| sensors::write(m, &self.root, d, qpos, qvel, out.reborrow()));
        if let Some((t, obs)) = task {
            t.observe(m, &out.world_view(qpos, qvel, ctrl), obs);
        }
    }
}

/// Calls `each` on every item of `items` with a thread's scratch: the calling thread takes items
/// from the front, the workers (when there are any) from the back, so that each keeps to its own
/// end of the batch from call to call.
fn share_out<I>(workers: Option<&Workers>, scratch: &[Mutex<Data>], items: I, each: impl Fn(I::Item, &mut Data) + Sync)
where
    I: DoubleEndedIterator + Send,
{
    let queue = Mutex::new(items);
    let work = |from_back: bool| {
        // each thread keeps its own scratch from call to call, warm in its core's cache
        let slot = if from_back { 1 + rayon::current_thread_index().unwrap_or(0) } else { 0 };
        let mut scratch = scratch[slot.min(scratch.len() - 1)].lock().unwrap_or_else(|e| e.into_inner());
        loop {
            // the lock is held only to take the next item (a guard in a `while let` scrutinee
            // would live through the loop body)
            let mut q = queue.lock().unwrap_or_else(|e| e.into_inner());
            let next = if from_back { q.next_back() } else { q.next() };
            drop(q);
            let Some(item) = next else { break };
            each(item, &mut scratch);
        }
    };
    match workers {
        Some(workers) => workers.run(&work),
        None => work(false),
    }
}

/// A thread's scratch for a world outside a step call (there is always one per thread).
fn scratch_here(scratch: &mut [Mutex<Data>]) -> &mut Data {
    scratch[0].get_mut().unwrap_or_else(|e| e.into_inner())
}

/// World `i`'s own model if it has one, else the shared one (a field-wise borrow of a
/// [`Batch`], beside its mutable scratch).
fn world_model<'a>(own: &'a [Option<Box<Model>>], shared: &'a Model, i: usize) -> &'a Model {
    own[i].as_deref().unwrap_or(shared)
}

/// One world's rows of a batch's arrays, for one call of [`Batch::step`].
struct World<'a> {
    model: &'a Model,
    data: &'a mut Kept,
    state: WorldState<'a>,
    diverged: &'a mut bool,
    active: bool,
    out: Sensors<'a>,
    obs: &'a mut [f64],
    reward: &'a mut f64,
    terminated: &'a mut bool,
    info: &'a mut [f64],
    /// File sensors to read after the step, and where.
    sensors: &'a [usize],
    readings: &'a mut [f64],
}

/// `n` steps of one world (reset alone if it diverges) in the thread's scratch `scratch`,
/// then its sensor outputs, the readings of the watched sensors and, with a task, its observation,
/// reward terms and termination, under
/// the step's panic guard: a panic (a bug)
/// leaves the world as the call found it, its history forgotten, and its message in
/// [`Kept::fault`].
fn env_step(root: &[usize], task: Option<&dyn Task>, n: usize, w: World<'_>, scratch: &mut Data) {
    let World { model: m, data, mut state, diverged, active, mut out, obs, reward, terminated, info, sensors: which, readings } = w;
    *diverged = false;
    data.fault = None;
    if !active {
        return;
    }
    let outcome = scratch.with_kept(data, |data| guarded(data, &mut state, |data, s| {
        // the rewarded position before the env step, from the outputs of the state it starts in
        let before = task.map(|t| t.position(m, &out.world_view(s.qpos, s.qvel, s.ctrl)));
        if advance(m, data, s, n).is_some() {
            reset_state(m, s.qpos, s.qvel, s.act);
            data.forget_history();
            *s.time = 0.0;
            *diverged = true;
        }
        sensors::write(m, root, data, s.qpos, s.qvel, out.reborrow());
        if !which.is_empty() {
            sensordata::read(m, data, sensordata::State { qpos: s.qpos, qvel: s.qvel, ctrl: s.ctrl, act: s.act }, which, readings);
        }
        if let (Some(t), Some(before)) = (task, before) {
            let view = out.world_view(s.qpos, s.qvel, s.ctrl);
            t.observe(m, &view, obs);
            *terminated = t.evaluate(m, &view, obs, before, n as f64 * m.opt.timestep, info);
            *reward = info[..t.reward_terms()].iter().sum();
            // a diverged world was reset: its step earns nothing and ends the episode
            if *diverged {
                *reward = 0.0;
                *terminated = true;
            }
        }
    }));
    if let Err(message) = outcome {
        data.fault = Some(message);
    }
}

/// Back to qpos0 at rest; with the world's history forgotten (no friction tangents, LCP warm
/// start or cached kinematics) a reset world steps exactly as a new one.
fn reset_state(m: &Model, qpos: &mut [f64], qvel: &mut [f64], act: &mut [f64]) {
    qpos.copy_from_slice(&m.qpos0);
    qvel.fill(0.0);
    act.fill(0.0);
}
