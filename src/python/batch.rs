//! `sinew.Batch`: N worlds sharing one model; state arrays are NumPy arrays stepped in place by
//! rayon with the GIL released.

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use pyo3::types::PyDict;

use super::arrays::{as_f64, checked_values};
use super::model::PyModel;
use super::outputs::{SensorOutputs, TaskArrays};
use super::placed::Placements;
use crate::batch::{Batch, BatchState, TaskRun};
use crate::step::state::FlatState;
use crate::render::Placed;
use crate::sensordata;

/// N simulated worlds of one model, stepped in parallel (at most 2**20 worlds and 1024 threads;
/// num_threads=None uses all cores; never more threads than worlds).
#[pyclass(name = "Batch", module = "sinew._core")]
pub struct PyBatch {
    pub(super) inner: Batch,
    pub(super) py_model: Py<PyModel>,
    pub(super) qpos: Py<PyArray2<f64>>,
    pub(super) qvel: Py<PyArray2<f64>>,
    pub(super) ctrl: Py<PyArray2<f64>>,
    pub(super) act: Py<PyArray2<f64>>,
    pub(super) time: Py<PyArray1<f64>>,
    pub(super) diverged: Py<PyArray1<bool>>,
    pub(super) out: SensorOutputs,
    pub(super) task: Option<TaskArrays>,
    /// The task's kind and parameters as given to `set_task` (for pickling).
    pub(super) task_args: Option<(String, Py<PyDict>)>,
    /// Geoms and sites placed per world (`set_geom_pos`, `set_site_pos`): each with its position
    /// in its body's frame in every world.
    pub(super) moved: Placements,
    /// The sensors `watch_sensors` chose, and their readings after the last `step`.
    pub(super) watched: Vec<usize>,
    pub(super) watched_readings: Py<PyArray2<f64>>,
}

#[pymethods]
impl PyBatch {
    /// `num_envs` worlds at qpos0; world i's random stream is seeded from `seed + i`.
    /// `num_threads=None` uses every core; never more threads than worlds.
    #[new]
    #[pyo3(signature = (model, num_envs, seed=0, num_threads=None))]
    fn new(py: Python<'_>, model: Bound<'_, PyModel>, num_envs: usize, seed: u64, num_threads: Option<usize>) -> PyResult<Self> {
        let m = model.get().inner.clone();
        if num_envs == 0 {
            return Err(PyValueError::new_err("num_envs must be at least 1"));
        }
        if m.nq == 0 {
            return Err(PyValueError::new_err("the model has no joints: nothing to simulate"));
        }
        if num_threads == Some(0) {
            return Err(PyValueError::new_err("num_threads must be at least 1 (or None for all cores)"));
        }
        if num_envs > crate::batch::MAX_WORLDS {
            return Err(PyValueError::new_err(format!("num_envs must be at most {}, got {num_envs}", crate::batch::MAX_WORLDS)));
        }
        let seeds: Vec<u64> = (0..num_envs as u64).map(|i| seed.wrapping_add(i)).collect();
        let inner = Batch::new(m.clone(), &seeds, num_threads).map_err(|e| super::errors::to_py(py, e))?;
        let qpos0: Vec<f64> = (0..num_envs).flat_map(|_| m.qpos0.iter().copied()).collect();
        let qpos = PyArray1::from_vec(py, qpos0).reshape([num_envs, m.nq])?.unbind();
        let mut b = PyBatch {
            inner,
            py_model: model.unbind(),
            qpos,
            qvel: PyArray2::zeros(py, [num_envs, m.nv], false).unbind(),
            ctrl: PyArray2::zeros(py, [num_envs, m.nu], false).unbind(),
            act: PyArray2::zeros(py, [num_envs, m.na], false).unbind(),
            time: PyArray1::zeros(py, num_envs, false).unbind(),
            diverged: PyArray1::from_vec(py, vec![false; num_envs]).unbind(),
            out: SensorOutputs::new(py, num_envs, &m),
            task: None,
            task_args: None,
            moved: Placements::default(),
            watched: vec![],
            watched_readings: PyArray2::zeros(py, [num_envs, 0], false).unbind(),
        };
        b.refresh_poses(py)?;
        Ok(b)
    }

    /// The shared model.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<PyModel> {
        self.py_model.clone_ref(py)
    }
    /// Number of worlds.
    #[getter]
    fn num_envs(&self) -> usize {
        self.inner.len()
    }
    /// Threads stepping the worlds.
    #[getter]
    fn num_threads(&self) -> usize {
        self.inner.num_threads()
    }
    /// Positions (N, nq), stepped in place.
    #[getter]
    fn qpos(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.qpos.clone_ref(py)
    }
    /// Velocities (N, nv), stepped in place.
    #[getter]
    fn qvel(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.qvel.clone_ref(py)
    }
    /// Controls (N, nu); clamped to ctrlrange inside the step when limited.
    #[getter]
    fn ctrl(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.ctrl.clone_ref(py)
    }
    /// Actuator activations (N, na), stepped in place (MuJoCo's `act`).
    #[getter]
    fn act(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.act.clone_ref(py)
    }
    /// Simulated time per world (N,).
    #[getter]
    fn time(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.time.clone_ref(py)
    }
    /// Worlds that diverged during the last `step` and were reset to qpos0 (N,).
    #[getter]
    fn diverged(&self, py: Python<'_>) -> Py<PyArray1<bool>> {
        self.diverged.clone_ref(py)
    }
    /// Each world's file sensors (N, nsensordata) at its current state, touch, force and torque
    /// from its last step's constraint forces, as `Sim.sensordata` (computed on each read).
    #[getter]
    fn sensordata<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let all: Vec<usize> = (0..self.inner.model.sensor_kind.len()).collect();
        self.read_sensors(py, all, None)
    }

    /// Chooses sensors (indices into `Model.sensor_names`) that every `step` reads after it, in
    /// the same parallel pass, into `watched_readings`: the columns `read_sensors` would give for
    /// the state the step reached (an empty list stops it). The rows of worlds a step leaves
    /// alone keep their last readings.
    fn watch_sensors(&mut self, py: Python<'_>, sensors: Vec<usize>) -> PyResult<()> {
        let dim = sensors_dim(&self.inner.model, &sensors)?;
        self.watched_readings = PyArray2::zeros(py, [self.inner.len(), dim], false).unbind();
        self.watched = sensors;
        Ok(())
    }
    /// The readings of the sensors `watch_sensors` chose after the last `step` (N, their dims).
    #[getter]
    fn watched_readings(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.watched_readings.clone_ref(py)
    }

    /// The readings of the sensors `sensors` (indices into `Model.sensor_names`), one after
    /// another, of each world (N, their total dimension), or of the worlds `worlds` only (one row
    /// each, in ascending order): `sensordata`'s columns of those sensors, computing only them.
    #[pyo3(signature = (sensors, worlds=None))]
    fn read_sensors<'py>(&mut self, py: Python<'py>, sensors: Vec<usize>, worlds: Option<Vec<usize>>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let ns = sensors_dim(&self.inner.model, &sensors)?;
        let chosen = match &worlds {
            None => None,
            Some(w) => {
                let n = self.inner.len();
                let mut mask = vec![false; n];
                for &i in w {
                    *mask.get_mut(i).ok_or_else(|| PyValueError::new_err(format!("world {i} out of range for {n} worlds")))? = true;
                }
                Some(mask)
            }
        };
        let n = chosen.as_ref().map_or(self.inner.len(), |c| c.iter().filter(|&&x| x).count());
        let (qpos, qvel, ctrl, act) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly(), self.ctrl.bind(py).readonly(), self.act.bind(py).readonly());
        let st = sensordata::State { qpos: qpos.as_slice()?, qvel: qvel.as_slice()?, ctrl: ctrl.as_slice()?, act: act.as_slice()? };
        let out = self.inner.read_sensors(st, &sensors, chosen.as_deref());
        PyArray1::from_vec(py, out).reshape([n, ns])
    }
    /// Solver counters summed over the worlds (residual: the largest), as `Sim.constraint_stats`.
    #[getter]
    fn constraint_stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (s, impacts, projections) = self.inner.constraint_stats();
        super::sim::stats_dict(py, &s, impacts, projections)
    }
    /// How many contacts penetrate (distance < 0) in each world's current configuration (N,):
    /// MuJoCo's `ncon` after `mj_forward` where margins are zero, which a task's reset reads to
    /// turn down a drawn state whose bodies overlap.
    fn penetrations<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<usize>>> {
        let (qpos, qvel) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly());
        Ok(PyArray1::from_vec(py, self.inner.penetrations(qpos.as_slice()?, qvel.as_slice()?)))
    }
    /// Body positions (N, nbody, 3) for the current state.
    #[getter]
    fn xpos(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.xpos.clone_ref(py)
    }
    /// Body rotation matrices, row-major (N, nbody, 9), for the current state.
    #[getter]
    fn xmat(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.xmat.clone_ref(py)
    }
    /// Body centres of mass in world (N, nbody, 3), MuJoCo's `xipos`, for the current state.
    #[getter]
    fn xipos(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.xipos.clone_ref(py)
    }

    /// Body velocities (N, nbody, 6): world angular velocity, then world velocity of the body origin.
    #[getter]
    fn xvel(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.xvel.clone_ref(py)
    }
    /// Contact wrench per body (N, nbody, 6) of the last step: torque then force, world axes, about
    /// the centre of mass of the body's root subtree (MuJoCo's `cfrc_ext`).
    #[getter]
    fn cfrc_ext(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.cfrc_ext.clone_ref(py)
    }

    /// Com-based body inertias after the last step (N, nbody, 10): xx, yy, zz, xy, xz, yz about
    /// the centre of mass of the body's root subtree in world axes, mass × offset, mass
    /// (MuJoCo's `cinert`).
    #[getter]
    fn cinert(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.cinert.clone_ref(py)
    }

    /// Com-based body velocities after the last step (N, nbody, 6): angular, then the linear
    /// velocity of the body point at the root subtree's centre of mass (MuJoCo's `cvel`).
    #[getter]
    fn cvel(&self, py: Python<'_>) -> Py<PyArray3<f64>> {
        self.out.cvel.clone_ref(py)
    }
    /// Generalised constraint force of the last step (N, nv) (MuJoCo's `qfrc_constraint`).
    #[getter]
    fn qfrc_constraint(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.out.qfrc_constraint.clone_ref(py)
    }

    /// Advances the worlds where `mask` is true (every world when None) `n` steps (GIL released);
    /// the others keep their state and outputs. Non-finite controls of stepped worlds raise
    /// ValueError naming them; worlds that diverge are reset alone and flagged in `diverged`.
    #[pyo3(signature = (n=1, mask=None))]
    fn step(&mut self, py: Python<'_>, n: usize, mask: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let nu = self.inner.model.nu;
        let mut active = vec![false; self.inner.len()];
        for i in self.chosen(mask)? {
            active[i] = true;
        }
        {
            let ctrl = self.ctrl.bind(py).readonly();
            let c = ctrl.as_slice()?;
            let bad: Vec<usize> = (0..self.inner.len()).filter(|&i| active[i] && c[i * nu..(i + 1) * nu].iter().any(|x| !x.is_finite())).collect();
            if !bad.is_empty() {
                return Err(PyValueError::new_err(format!("ctrl is not finite in worlds {bad:?}")));
            }
        }
        let (mut qpos, mut qvel, ctrl) = (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readonly());
        let (mut time, mut div, mut act) = (self.time.bind(py).readwrite(), self.diverged.bind(py).readwrite(), self.act.bind(py).readwrite());
        let mut out = self.out.readwrite(py);
        let mut readings = self.watched_readings.bind(py).readwrite();
        let st = BatchState {
            qpos: qpos.as_slice_mut()?,
            qvel: qvel.as_slice_mut()?,
            ctrl: ctrl.as_slice()?,
            act: act.as_slice_mut()?,
            time: time.as_slice_mut()?,
            diverged: div.as_slice_mut()?,
            active: &active,
            out: out.slices()?,
            sensors: &self.watched,
            sensordata: readings.as_slice_mut()?,
        };
        let mut outputs = self.task.as_ref().map(|t| t.borrow(py));
        let run = match &mut outputs {
            Some((task, obs, reward, terminated, info)) => Some(TaskRun {
                task: *task,
                obs: obs.as_slice_mut()?,
                reward: reward.as_slice_mut()?,
                terminated: terminated.as_slice_mut()?,
                info: info.as_slice_mut()?,
            }),
            None => None,
        };
        let inner = &mut self.inner;
        py.detach(|| super::errors::guard("Batch.step", || inner.step(st, n, run)))?;
        let faults: Vec<String> = (0..self.inner.len())
            .filter_map(|i| self.inner.data[i].fault.take().map(|msg| format!("world {i}: {msg}")))
            .collect();
        if !faults.is_empty() {
            return Err(super::errors::internal("Batch.step", format!("{}; those worlds are back where this call found them", faults.join("; "))));
        }
        Ok(())
    }

    /// Sets the task evaluated after every `step` (`n` = its frame_skip): gymnasium's MuJoCo v5
    /// env `kind` ("InvertedPendulum", "InvertedDoublePendulum", "Reacher", "Hopper", "Walker2d",
    /// "HalfCheetah", "Ant", "Humanoid") with that env's keyword arguments, every one given
    /// (`sinew.tasks` fills in the defaults). Its outputs are `obs`, `reward`, `terminated` and
    /// `info` (columns named by `info_names`); the observations of all worlds are computed now.
    #[pyo3(signature = (kind, **params))]
    fn set_task(&mut self, py: Python<'_>, kind: &str, params: Option<Bound<'_, PyDict>>) -> PyResult<()> {
        let m = self.inner.model.clone();
        let params = params.unwrap_or_else(|| PyDict::new(py));
        let (spec, task) = super::task::parse(&m, kind, params.clone())?;
        self.task_args = Some((kind.to_string(), params.copy()?.unbind()));
        let n = self.inner.len();
        self.task = Some(TaskArrays {
            obs: PyArray2::zeros(py, [n, task.obs_dim(&m)], false).unbind(),
            reward: PyArray1::zeros(py, n, false).unbind(),
            terminated: PyArray1::from_vec(py, vec![false; n]).unbind(),
            info: PyArray2::zeros(py, [n, task.info_names().len()], false).unbind(),
            spec,
            task,
        });
        self.refresh_poses(py)
    }

    /// The task's observations (N, obs_dim), for the current state: after `step`, or after
    /// `reset`/`forward_kinematics` for the worlds they touched. None without a task.
    #[getter]
    fn obs(&self, py: Python<'_>) -> Option<Py<PyArray2<f64>>> {
        self.task.as_ref().map(|t| t.obs.clone_ref(py))
    }
    /// The last `step`'s rewards (N); 0 for a world that diverged. None without a task.
    #[getter]
    fn reward(&self, py: Python<'_>) -> Option<Py<PyArray1<f64>>> {
        self.task.as_ref().map(|t| t.reward.clone_ref(py))
    }
    /// Whether the last `step` ended each world's episode (N); true for a world that diverged.
    /// None without a task.
    #[getter]
    fn terminated(&self, py: Python<'_>) -> Option<Py<PyArray1<bool>>> {
        self.task.as_ref().map(|t| t.terminated.clone_ref(py))
    }
    /// The last `step`'s info columns (N, len(info_names)): reward terms first. None without a task.
    #[getter]
    fn info(&self, py: Python<'_>) -> Option<Py<PyArray2<f64>>> {
        self.task.as_ref().map(|t| t.info.clone_ref(py))
    }
    /// Names of the `info` columns; the reward is the sum of the first `reward_terms`.
    #[getter]
    fn info_names(&self) -> Vec<&'static str> {
        self.task.as_ref().map_or(vec![], |t| t.task.info_names().to_vec())
    }
    /// The task's reset info (gymnasium's `reset` info of the same env) for each world at its
    /// current state: {name: (N,) array}, each the info column of that name at zero progress.
    /// Empty without a task.
    #[getter]
    fn reset_info<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let Some(t) = &self.task else { return Ok(out) };
        let m = self.inner.model.clone();
        let (n, names) = (self.inner.len(), t.task.info_names());
        let mut cols = Vec::with_capacity(t.spec.reset_info.len());
        for k in t.spec.reset_info {
            let col = names.iter().position(|x| x == k);
            cols.push(col.ok_or_else(|| super::errors::internal("Batch.reset_info", format!("task {}: reset info '{k}' is no info column", t.spec.name)))?);
        }
        let mut values = vec![0.0; n * cols.len()];
        let (qpos, qvel, ctrl) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly(), self.ctrl.bind(py).readonly());
        let (qp, qv, c) = (qpos.as_slice()?, qvel.as_slice()?, ctrl.as_slice()?);
        let obs = t.obs.bind(py).readonly();
        let obs = obs.as_slice()?;
        let dim = obs.len() / n;
        let mut arrays = self.out.readwrite(py);
        let mut sensors = arrays.slices()?;
        let mut info = vec![0.0; names.len()];
        for i in 0..n {
            let (q, v, u) = (&qp[i * m.nq..(i + 1) * m.nq], &qv[i * m.nv..(i + 1) * m.nv], &c[i * m.nu..(i + 1) * m.nu]);
            let world = sensors.world(i, m.nbody, m.nv);
            let view = world.world_view(q, v, u);
            t.task.evaluate(&m, &view, &obs[i * dim..(i + 1) * dim], t.task.position(&m, &view), 1.0, &mut info);
            for (k, &col) in cols.iter().enumerate() {
                values[k * n + i] = info[col];
            }
        }
        for (k, name) in t.spec.reset_info.iter().enumerate() {
            out.set_item(name, PyArray1::from_slice(py, &values[k * n..(k + 1) * n]))?;
        }
        Ok(out)
    }
    /// How many leading `info` columns are reward terms.
    #[getter]
    fn reward_terms(&self) -> usize {
        self.task.as_ref().map_or(0, |t| t.task.reward_terms())
    }

    /// Resets the worlds where `mask` is true (all when None) to qpos0, zero velocity, control
    /// and time, or to the given `qpos` (k, nq) and `qvel` (k, nv), one row per reset world in
    /// order; `seeds` (one per reset world) re-seeds their random streams.
    #[pyo3(signature = (mask=None, seeds=None, qpos=None, qvel=None))]
    fn reset(
        &mut self,
        py: Python<'_>,
        mask: Option<Bound<'_, PyAny>>,
        seeds: Option<Vec<u64>>,
        qpos: Option<Bound<'_, PyAny>>,
        qvel: Option<Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let chosen = self.chosen(mask)?;
        if let Some(s) = &seeds
            && s.len() != chosen.len()
        {
            return Err(PyValueError::new_err(format!("seeds: expected {} values, got {}", chosen.len(), s.len())));
        }
        let m = self.inner.model.clone();
        let k = chosen.len();
        let start_q = qpos.map(|q| checked_values(&q, "qpos", &[k, m.nq])).transpose()?;
        let start_v = qvel.map(|v| checked_values(&v, "qvel", &[k, m.nv])).transpose()?;
        {
            let (mut qpos, mut qvel) = (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite());
            let (mut ctrl, mut time, mut act) = (self.ctrl.bind(py).readwrite(), self.time.bind(py).readwrite(), self.act.bind(py).readwrite());
            let (qp, qv, c, t, a) = (qpos.as_slice_mut()?, qvel.as_slice_mut()?, ctrl.as_slice_mut()?, time.as_slice_mut()?, act.as_slice_mut()?);
            for (k, &i) in chosen.iter().enumerate() {
                let (q, v) = (&mut qp[i * m.nq..(i + 1) * m.nq], &mut qv[i * m.nv..(i + 1) * m.nv]);
                self.inner.reset(i, q, v, &mut a[i * m.na..(i + 1) * m.na]);
                if let Some(s) = &start_q {
                    q.copy_from_slice(&s[k * m.nq..(k + 1) * m.nq]);
                }
                if let Some(s) = &start_v {
                    v.copy_from_slice(&s[k * m.nv..(k + 1) * m.nv]);
                }
                c[i * m.nu..(i + 1) * m.nu].fill(0.0);
                t[i] = 0.0;
                if let Some(s) = &seeds {
                    self.inner.seed(i, s[k]);
                }
            }
        }
        self.refresh(py, &chosen)
    }

    /// Recomputes the sensor outputs (and a task's observations) after qpos/qvel were written from
    /// Python, for the worlds where `mask` is true (all when None).
    #[pyo3(signature = (mask=None))]
    fn forward_kinematics(&mut self, py: Python<'_>, mask: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let which = self.chosen(mask)?;
        self.refresh(py, &which)
    }

    /// World `i`'s state as `Sim.get_state` gives it: [time, qpos, qvel, act, ctrl], and with
    /// `full=True` the feed-forward and the history the next step reads, so that a world (or a
    /// Sim) given it by `set_state` steps on bit-identically. Without `i`, every world's: an
    /// (N, 1 + nq + nv + na + nu) array of short states, or a list of N full ones.
    #[pyo3(signature = (i=None, full=false))]
    fn get_state<'py>(&self, py: Python<'py>, i: Option<usize>, full: bool) -> PyResult<Bound<'py, PyAny>> {
        let m = &*self.inner.model;
        let (qpos, qvel, ctrl, time) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly(), self.ctrl.bind(py).readonly(), self.time.bind(py).readonly());
        let act = self.act.bind(py).readonly();
        let (q, v, c, t, a) = (qpos.as_slice()?, qvel.as_slice()?, ctrl.as_slice()?, time.as_slice()?, act.as_slice()?);
        let one = |i: usize| {
            let mut out = Vec::with_capacity(1 + m.nq + m.nv + m.na + m.nu);
            let d = &self.inner.data[i];
            let world = (&q[i * m.nq..(i + 1) * m.nq], &v[i * m.nv..(i + 1) * m.nv], &a[i * m.na..(i + 1) * m.na]);
            FlatState::write(t[i], world, &c[i * m.nu..(i + 1) * m.nu], full.then(|| d.full_state()), &mut out);
            out
        };
        match i {
            Some(i) => Ok(PyArray1::from_vec(py, one(self.world(i)?)).into_any()),
            None if full => Ok(pyo3::types::PyList::new(py, (0..self.inner.len()).map(|i| PyArray1::from_vec(py, one(i))))?.into_any()),
            None => {
                let flat: Vec<f64> = (0..self.inner.len()).flat_map(one).collect();
                Ok(PyArray1::from_vec(py, flat).reshape([self.inner.len(), 1 + m.nq + m.nv + m.na + m.nu])?.into_any())
            }
        }
    }

    /// Restores world `i` from a state of `get_state` (of any world, or a Sim, of this model),
    /// bit-exactly; without `i` every world, from an (N, L) array or a list of N states. A full
    /// state restores the history too; a short one leaves none. Bad lengths or entries raise
    /// ValueError naming the world and leave the batch untouched.
    #[pyo3(signature = (state, i=None))]
    fn set_state(&mut self, py: Python<'_>, state: Bound<'_, PyAny>, i: Option<usize>) -> PyResult<()> {
        let m = self.inner.model.clone();
        let rows: Vec<(usize, Vec<f64>)> = match i {
            Some(i) => {
                let len = as_f64(&state, "state")?.len();
                vec![(self.world(i)?, checked_values(&state, "state", &[len])?)]
            }
            None => {
                let items: Vec<Bound<'_, PyAny>> = state.try_iter()?.collect::<PyResult<_>>()?;
                if items.len() != self.inner.len() {
                    return Err(PyValueError::new_err(format!("state: expected one state per world ({}), got {}", self.inner.len(), items.len())));
                }
                let mut rows = Vec::with_capacity(items.len());
                for (k, it) in items.iter().enumerate() {
                    let len = as_f64(it, "state")?.len();
                    rows.push((k, checked_values(it, &format!("state of world {k}"), &[len])?));
                }
                rows
            }
        };
        // every state checked before any world changes
        let mut states = Vec::with_capacity(rows.len());
        for (k, v) in &rows {
            states.push((*k, FlatState::read(&m, v).map_err(|e| PyValueError::new_err(format!("world {k}: {e}")))?));
        }
        {
            let (mut qpos, mut qvel, mut ctrl, mut time) = (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readwrite(), self.time.bind(py).readwrite());
            let (q, v, c, t) = (qpos.as_slice_mut()?, qvel.as_slice_mut()?, ctrl.as_slice_mut()?, time.as_slice_mut()?);
            let mut act = self.act.bind(py).readwrite();
            let a = act.as_slice_mut()?;
            for (k, st) in &states {
                t[*k] = st.time;
                q[k * m.nq..(k + 1) * m.nq].copy_from_slice(st.qpos);
                v[k * m.nv..(k + 1) * m.nv].copy_from_slice(st.qvel);
                a[k * m.na..(k + 1) * m.na].copy_from_slice(st.act);
                c[k * m.nu..(k + 1) * m.nu].copy_from_slice(st.ctrl);
                let (ff, history) = st.kept();
                self.inner.data[*k].restore(ff, &history);
            }
            let mut div = self.diverged.bind(py).readwrite();
            for (k, _) in &states {
                div.as_slice_mut()?[*k] = false;
            }
        }
        let which: Vec<usize> = states.iter().map(|(k, _)| *k).collect();
        self.refresh(py, &which)
    }

    /// Pickles as its model, size, threads, task, every world's full state and the sensors it
    /// watches: a copy steps on bit-identically.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<super::Reduced<'py>> {
        let task = self.task_args.as_ref().map(|(k, p)| (k.clone(), p.clone_ref(py)));
        let states = self.get_state(py, None, true)?;
        // what the last step left in the output arrays (contact forces among them), which a
        // state alone does not give back
        let outputs = self.clone_outputs(py)?;
        // each placed geom and site as ("geom" or "site", index, positions)
        let (m, n) = (&self.inner.model, self.inner.len());
        let moved: Vec<(&str, usize, Bound<'py, PyArray2<f64>>)> = self
            .moved
            .placed()
            .map(|k| match k {
                Placed::Geom(g) => Ok(("geom", g, self.moved.positions(py, m, n, k)?)),
                Placed::Site(s) => Ok(("site", s, self.moved.positions(py, m, n, k)?)),
            })
            .collect::<PyResult<_>>()?;
        let own = super::params::varied(&self.inner);
        // the watched sensors and their readings after the last step
        let watched = (self.watched.clone(), self.watched_readings.bind(py).call_method0("copy")?);
        let args = (self.py_model.clone_ref(py), self.inner.len(), self.inner.num_threads(), task, states, outputs, moved, own, watched).into_pyobject(py)?;
        Ok((py.import("sinew._pickle")?.getattr("batch")?, args))
    }

    /// Gives the worlds `worlds` (all when None; a mask or indices) values of their own of the
    /// model field `field` (MuJoCo's name: body_mass, body_ipos, body_inertia, geom_friction,
    /// dof_damping, dof_armature, dof_frictionloss, jnt_stiffness, actuator_gain, actuator_bias,
    /// actuator_gear, actuator_ctrlrange, gravity, wrap_prm, hfield_data, body_pos, body_quat,
    /// eq_active, pair_friction), `values` broadcast to (worlds, ...); a new body mass scales its inertia. What
    /// derives from the field follows, the worlds' warm starts are forgotten; a bad value raises
    /// ValueError naming the world and the field, and then no world changes.
    #[pyo3(signature = (field, values, worlds=None))]
    fn set_params(&mut self, py: Python<'_>, field: &str, values: Bound<'_, PyAny>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let p = super::params::named(field)?;
        let which = self.worlds(worlds)?;
        let v = super::params::broadcast(py, p, &self.inner.model, &values, which.len())?;
        self.inner.set_param(p, &which, &v).map_err(|e| super::errors::to_py(py, e))?;
        self.redraw(py, &which);
        self.refresh(py, &which)
    }

    /// Field `field` (as `set_params` names it) of every world, (N, ...): a copy.
    fn params<'py>(&self, py: Python<'py>, field: &str) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
        super::params::read(py, &self.inner, super::params::named(field)?)
    }

    /// Gives the worlds `worlds` (all when None) the model's own values back.
    #[pyo3(signature = (worlds=None))]
    fn reset_params(&mut self, py: Python<'_>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let which = self.worlds(worlds)?;
        self.inner.reset_params(&which);
        self.redraw(py, &which);
        self.refresh(py, &which)
    }

    /// What pickling keeps of the worlds' own values.
    fn _varied_params(&self) -> super::params::Varied {
        super::params::varied(&self.inner)
    }

    /// Restores what pickling kept of the worlds' own values.
    fn _restore_params(&mut self, py: Python<'_>, own: super::params::Varied) -> PyResult<()> {
        let which: Vec<usize> = own.iter().map(|(i, _, _)| *i).collect();
        if let Some(&i) = which.iter().find(|&&i| i >= self.inner.len()) {
            return Err(PyValueError::new_err(format!("world {i} out of range for {} worlds", self.inner.len())));
        }
        super::params::restore(&mut self.inner, own).map_err(|e| super::errors::to_py(py, e))?;
        self.redraw(py, &which);
        self.refresh(py, &which)
    }

    /// Places geom `geom` (an index) at `pos` in its body's frame, in the worlds `worlds` (all
    /// when None; a mask or indices): (3,) for all of them or one row each. Only a geom that
    /// touches nothing (a target, a marker; any geom when contacts are off) may differ between
    /// worlds: the renderer and `geom_pos` read it, collisions never meet it.
    #[pyo3(signature = (geom, pos, worlds=None))]
    fn set_geom_pos(&mut self, geom: usize, pos: Bound<'_, PyAny>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let m = self.inner.model.clone();
        Placements::check(&self.inner.model, Placed::Geom(geom))?;
        if m.opt.contact && m.collision_pairs.iter().any(|p| p.g1 == geom || p.g2 == geom) {
            return Err(PyValueError::new_err(format!(
                "geom '{}' can touch other geoms: only a geom without contacts may be placed per world", m.geom_name[geom]
            )));
        }
        self.place(Placed::Geom(geom), pos, worlds)
    }

    /// Places site `site` (an index) at `pos` in its body's frame in the worlds `worlds`, as
    /// `set_geom_pos`: the renderer and `site_pos` read it (the file's sensors do not).
    #[pyo3(signature = (site, pos, worlds=None))]
    fn set_site_pos(&mut self, site: usize, pos: Bound<'_, PyAny>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        Placements::check(&self.inner.model, Placed::Site(site))?;
        self.place(Placed::Site(site), pos, worlds)
    }

    /// Geom `geom`'s position in its body's frame in every world (N, 3): the model's unless
    /// `set_geom_pos` placed it.
    fn geom_pos<'py>(&self, py: Python<'py>, geom: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Placements::check(&self.inner.model, Placed::Geom(geom))?;
        self.moved.positions(py, &self.inner.model, self.inner.len(), Placed::Geom(geom))
    }

    /// Site `site`'s position in its body's frame in every world (N, 3), as `geom_pos`.
    fn site_pos<'py>(&self, py: Python<'py>, site: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Placements::check(&self.inner.model, Placed::Site(site))?;
        self.moved.positions(py, &self.inner.model, self.inner.len(), Placed::Site(site))
    }

    /// Applies Cartesian forces to the bodies of the worlds `worlds` (all when None) from the
    /// next step on, as MuJoCo's `xfrc_applied`: `values` (nbody, 6) for each of them or
    /// (k, nbody, 6), per body a force at its centre of mass, then a torque, in world axes. They
    /// hold until set again or the world is reset.
    #[pyo3(signature = (values, worlds=None))]
    fn set_xfrc_applied(&mut self, values: Bound<'_, PyAny>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let which = self.worlds(worlds)?;
        let size = 6 * self.inner.model.nbody;
        let rows = if as_f64(&values, "values")?.ndim() == 2 {
            vec![checked_values(&values, "values", &[self.inner.model.nbody, 6])?; which.len()].concat()
        } else {
            checked_values(&values, "values", &[which.len(), self.inner.model.nbody, 6])?
        };
        for (k, &i) in which.iter().enumerate() {
            self.inner.data[i].set_xfrc_applied(&rows[k * size..(k + 1) * size]);
        }
        Ok(())
    }

    /// The forces `set_xfrc_applied` applies in every world (N, nbody, 6): a copy.
    #[getter]
    fn xfrc_applied<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let nb = self.inner.model.nbody;
        let mut all = vec![0.0; self.inner.len() * 6 * nb];
        for (row, d) in all.chunks_exact_mut(6 * nb.max(1)).zip(&self.inner.data) {
            if !d.xfrc_applied().is_empty() {
                row.copy_from_slice(d.xfrc_applied());
            }
        }
        PyArray1::from_vec(py, all).reshape([self.inner.len(), nb, 6])
    }

    /// Draws worlds in parallel: rgb (n, H, W, 3) uint8 and/or depth (n, H, W) float32, a tuple
    /// when both. `worlds`: None for all, a boolean mask (N,) or a sequence of world indices
    /// (rendering every 100th world costs a hundredth). `camera` as in `Sim.render`, or a list
    /// of one per rendered world.
    #[pyo3(signature = (width=480, height=480, camera=None, worlds=None, *, rgb=true, depth=false))]
    // Python's keywords, one argument each (what the method's signature and stub show)
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self, py: Python<'py>, width: i64, height: i64, camera: Option<Bound<'py, PyAny>>, worlds: Option<Bound<'py, PyAny>>, rgb: bool, depth: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let which = self.worlds(worlds)?;
        let (w, h) = super::render::check_size(width, height, which.len())?;
        let m = self.inner.model.clone();
        let r = self.py_model.bind(py).get().renderer();
        let cams = super::render::cameras(&m, &r, camera.as_ref(), which.len())?;
        let qpos = self.qpos.bind(py).readonly();
        let all = qpos.as_slice()?;
        let rows: Vec<(&crate::model::Model, &[f64])> = which.iter().map(|&i| (self.inner.model_of(i), &all[i * m.nq..(i + 1) * m.nq])).collect();
        if let Some((k, v)) = rows.iter().enumerate().find_map(|(k, (_, q))| q.iter().find(|x| crate::math::out_of_range(**x)).map(|v| (k, *v))) {
            return Err(PyValueError::new_err(format!("cannot render world {}: its qpos holds {v}", which[k])));
        }
        let looks: Vec<_> = which.iter().map(|&i| self.moved.of_world(i)).collect();
        super::render::draw(py, &m, &r, &rows, &looks, &cams, super::render::Frames { width: w, height: h, rgb, depth, single: false })
    }

    fn __repr__(&self) -> String {
        format!("Batch(model='{}', num_envs={}, num_threads={})", self.inner.model.name, self.inner.len(), self.inner.num_threads())
    }
}

/// The total dimension of the sensors `sensors` (indices into `m`'s sensors), or a `ValueError`
/// naming one out of range.
fn sensors_dim(m: &crate::model::Model, sensors: &[usize]) -> PyResult<usize> {
    if let Some(&bad) = sensors.iter().find(|&&k| k >= m.sensor_kind.len()) {
        return Err(PyValueError::new_err(format!("sensor {bad} out of range for {} sensors", m.sensor_kind.len())));
    }
    Ok(sensors.iter().map(|&k| m.sensor_kind[k].dim()).sum())
}
