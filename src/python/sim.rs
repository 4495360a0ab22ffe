//! `sinew.Sim`: one world. qpos/qvel/ctrl are NumPy arrays owned by the Sim and stepped in place.

use std::sync::Arc;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::arrays::{as_f64, checked_values, first_nonfinite};
use super::errors::{diverged, to_py};
use super::model::PyModel;
use crate::model::Model;
use crate::dynamics::{energy, kinematics, tendon};
use crate::sensordata;
use crate::constraint::History;
use crate::state::WorldState;
use crate::step::run::{advance, guarded, Divergence};
use crate::step::state::FlatState;
use crate::step::data::Data;

use crate::math::out_of_range;

/// One simulated world.
#[pyclass(name = "Sim", module = "sinew._core")]
pub struct PySim {
    model: Arc<Model>,
    py_model: Py<PyModel>,
    data: Data,
    qpos: Py<PyArray1<f64>>,
    qvel: Py<PyArray1<f64>>,
    ctrl: Py<PyArray1<f64>>,
    act: Py<PyArray1<f64>>,
    qacc: Py<PyArray1<f64>>,
    time: f64,
    /// The history at the start of the running `step` call, restored if it diverges.
    saved: History,
}

impl PySim {
    fn assign(&self, py: Python<'_>, target: &Py<PyArray1<f64>>, value: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
        let arr = target.bind(py);
        let n = arr.len()?;
        let v = checked_values(value, what, &[n])?;
        arr.readwrite().as_slice_mut()?.copy_from_slice(&v);
        Ok(())
    }
}

#[pymethods]
impl PySim {
    /// A world at the model's reference configuration qpos0, at rest, with zero control.
    #[new]
    fn new(py: Python<'_>, model: Bound<'_, PyModel>) -> Self {
        let m = model.get().inner.clone();
        PySim {
            data: Data::new(&m),
            qpos: PyArray1::from_slice(py, &m.qpos0).unbind(),
            qvel: PyArray1::zeros(py, m.nv, false).unbind(),
            ctrl: PyArray1::zeros(py, m.nu, false).unbind(),
            act: PyArray1::zeros(py, m.na, false).unbind(),
            qacc: PyArray1::zeros(py, m.nv, false).unbind(),
            time: 0.0,
            saved: History::new(),
            py_model: model.unbind(),
            model: m,
        }
    }

    /// The model this world simulates.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<PyModel> {
        self.py_model.clone_ref(py)
    }
    /// Positions (nq,), float64; assign into it or assign to it.
    #[getter]
    fn qpos(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.qpos.clone_ref(py)
    }
    #[setter]
    fn set_qpos(&self, py: Python<'_>, v: Bound<'_, PyAny>) -> PyResult<()> {
        self.assign(py, &self.qpos, &v, "qpos")
    }
    /// Velocities (nv,), float64.
    #[getter]
    fn qvel(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.qvel.clone_ref(py)
    }
    #[setter]
    fn set_qvel(&self, py: Python<'_>, v: Bound<'_, PyAny>) -> PyResult<()> {
        self.assign(py, &self.qvel, &v, "qvel")
    }
    /// Controls (nu,), float64; clamped to ctrlrange inside the step when limited.
    #[getter]
    fn ctrl(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.ctrl.clone_ref(py)
    }
    #[setter]
    fn set_ctrl(&self, py: Python<'_>, v: Bound<'_, PyAny>) -> PyResult<()> {
        self.assign(py, &self.ctrl, &v, "ctrl")
    }
    /// Actuator activations (na,), float64: the state of the actuators with dynamics (MuJoCo's
    /// `act`), advanced by the step.
    #[getter]
    fn act(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.act.clone_ref(py)
    }
    #[setter]
    fn set_act(&self, py: Python<'_>, v: Bound<'_, PyAny>) -> PyResult<()> {
        self.assign(py, &self.act, &v, "act")
    }
    /// Accelerations (nv,) from the last `forward()` or at the start of the last step.
    #[getter]
    fn qacc(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.qacc.clone_ref(py)
    }
    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.time
    }
    #[setter]
    fn set_time(&mut self, t: f64) -> PyResult<()> {
        if !t.is_finite() {
            return Err(PyValueError::new_err(format!("time must be finite, got {t}")));
        }
        self.time = t;
        Ok(())
    }

    /// Body positions in world (nbody, 3) for the current qpos.
    #[getter]
    fn xpos<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.kinematics(py)?;
        let flat: Vec<f64> = self.data.dynamics.kin.xpos.iter().flat_map(|v| v.to_array()).collect();
        PyArray1::from_vec(py, flat).reshape([self.model.nbody, 3])
    }
    /// Body orientations in world as rotation matrices (nbody, 3, 3) for the current qpos.
    #[getter]
    fn xmat<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        self.kinematics(py)?;
        let flat: Vec<f64> = self
            .data
            .dynamics
            .kin
            .xmat
            .iter()
            .flat_map(|m| (0..3).flat_map(move |r| (0..3).map(move |c| m.col(c)[r])))
            .collect();
        PyArray1::from_vec(py, flat).reshape([self.model.nbody, 3, 3])
    }

    /// The file's sensors (nsensordata) at the current state, touch, force and torque from the last
    /// step's constraint forces, as MuJoCo's `sensordata` (`Model.sensor_names`, `sensor_adr`; the kinds sinew does
    /// not compute are left out).
    #[getter]
    fn sensordata<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (qpos, qvel, ctrl, act) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly(), self.ctrl.bind(py).readonly(), self.act.bind(py).readonly());
        let mut out = vec![0.0; self.model.nsensordata];
        let s = sensordata::State { qpos: qpos.as_slice()?, qvel: qvel.as_slice()?, ctrl: ctrl.as_slice()?, act: act.as_slice()? };
        let all: Vec<usize> = (0..self.model.sensor_kind.len()).collect();
        sensordata::read(&self.model, &mut self.data, s, &all, &mut out);
        Ok(PyArray1::from_vec(py, out))
    }
    /// Tendon lengths (ntendon) for the current qpos, as MuJoCo's `ten_length`.
    #[getter]
    fn ten_length<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.tendons(py)?;
        Ok(PyArray1::from_vec(py, self.data.dynamics.ten.length.clone()))
    }
    /// Tendon velocities J q̇ (ntendon) for the current state, as MuJoCo's `ten_velocity`.
    #[getter]
    fn ten_velocity<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.tendons(py)?;
        let qvel = self.qvel.bind(py).readonly();
        let (ten, q) = (&self.data.dynamics.ten, qvel.as_slice()?);
        let v = (0..self.model.ntendon).map(|t| ten.rate(&self.model, t, q)).collect();
        Ok(PyArray1::from_vec(py, v))
    }
    /// Tendon Jacobians (ntendon, nv) for the current qpos, as MuJoCo's `ten_J`.
    #[getter]
    #[allow(non_snake_case)]
    fn ten_J<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.tendons(py)?;
        PyArray1::from_vec(py, self.data.dynamics.ten.jac.clone()).reshape([self.model.ntendon, self.model.nv])
    }

    /// Potential (gravity and springs) and kinetic energy of the current state, as MuJoCo's
    /// `energy` (with `enableflags` energy on).
    #[getter]
    fn energy<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.tendons(py)?;
        let (qpos, qvel) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly());
        let (m, dy) = (&*self.model, &self.data.dynamics);
        let potential = energy::gravity_potential(m, &dy.kin) + energy::spring_potential(m, &dy.ten, qpos.as_slice()?);
        let (kinetic, _) = energy::kinetic_and_gravity_power(m, &dy.kin, qvel.as_slice()?);
        Ok(PyArray1::from_vec(py, vec![potential, kinetic]))
    }

    /// Draws the world: rgb (H, W, 3) uint8 and/or depth (H, W) float32 (MuJoCo's z-buffer
    /// values, see `Model.clip`), a tuple when both. `camera`: None or -1 for the default free
    /// camera, a camera id or name, or a dict of free-camera settings.
    #[pyo3(signature = (width=480, height=480, camera=None, *, rgb=true, depth=false))]
    fn render<'py>(&self, py: Python<'py>, width: i64, height: i64, camera: Option<Bound<'py, PyAny>>, rgb: bool, depth: bool) -> PyResult<Bound<'py, PyAny>> {
        let (w, h) = super::render::check_size(width, height, 1)?;
        let pm = self.py_model.bind(py).get();
        let r = pm.renderer();
        let cam = super::render::camera(&self.model, &r, camera.as_ref())?;
        let qpos = self.qpos.bind(py).readonly();
        let q = qpos.as_slice()?;
        if let Some(i) = q.iter().position(|&x| out_of_range(x)) {
            return Err(PyValueError::new_err(format!("cannot render: qpos[{i}] is {}", q[i])));
        }
        super::render::draw(py, &self.model, &r, &[(&self.model, q)], &[(vec![], None)], &[cam], super::render::Frames { width: w, height: h, rgb, depth, single: true })
    }

    /// Computes qacc for the current state without advancing time.
    fn forward(&mut self, py: Python<'_>) -> PyResult<()> {
        self.check_inputs(py)?;
        let (mut qpos, mut qvel, ctrl, mut act) = (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readonly(), self.act.bind(py).readwrite());
        let (m, data, mut time) = (&self.model, &mut self.data, self.time);
        let s = WorldState { time: &mut time, qpos: qpos.as_slice_mut()?, qvel: qvel.as_slice_mut()?, ctrl: ctrl.as_slice()?, act: act.as_slice_mut()? };
        super::errors::guard("Sim.forward", || crate::step::forward(m, data, &s))?;
        self.qacc.bind(py).readwrite().as_slice_mut()?.copy_from_slice(&self.data.dynamics.qacc);
        Ok(())
    }

    /// Advances `n` steps inside Rust (GIL released). If the state becomes non-finite or exceeds
    /// 1e10, the world (state and history) is restored to where this call began and
    /// `SimulationError` is raised.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: usize) -> PyResult<()> {
        self.check_inputs(py)?;
        let m = &*self.model;
        let data = &mut self.data;
        let (mut qpos, mut qvel, ctrl, mut act) =
            (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readonly(), self.act.bind(py).readwrite());
        let start = self.time;
        let mut s = WorldState { time: &mut self.time, qpos: qpos.as_slice_mut()?, qvel: qvel.as_slice_mut()?, ctrl: ctrl.as_slice()?, act: act.as_slice_mut()? };
        self.saved.clone_from(&data.constraints.history);
        let outcome = py.detach(|| guarded(data, &mut s, |data, s| advance(m, data, s, n)));
        let error = match outcome {
            Ok(None) => None,
            Ok(Some(Divergence { step, entry: (name, i, v), time })) => Some(diverged(format!(
                "simulation diverged at t={time:.6} s (step {} of {n}): {name}[{i}] = {v}; state restored to t={start:.6} s",
                step + 1
            ))),
            Err(message) => Some(super::errors::internal("Sim.step", message + &format!("; state restored to t={start:.6} s"))),
        };
        if let Some(e) = error {
            data.fault.restore(&mut s);
            data.restore_history(&self.saved);
            return Err(e);
        }
        self.qacc.bind(py).readwrite().as_slice_mut()?.copy_from_slice(&self.data.dynamics.qacc);
        Ok(())
    }

    /// Feed-forward reference velocity and acceleration (nu each) of trajectory following; ctrl is
    /// the reference position. Ignored unless the model has `trajectory_gains`.
    fn set_feedforward(&mut self, qvel_ref: Bound<'_, PyAny>, qacc_ref: Bound<'_, PyAny>) -> PyResult<()> {
        let nu = self.model.nu;
        let v = checked_values(&qvel_ref, "qvel_ref", &[nu])?;
        let a = checked_values(&qacc_ref, "qacc_ref", &[nu])?;
        self.data.constraints.feedforward[..nu].copy_from_slice(&v);
        self.data.constraints.feedforward[nu..].copy_from_slice(&a);
        Ok(())
    }

    /// Back to qpos0, zero velocity, zero control and feed-forward, time 0, or to the keyframe
    /// `key` (a name or an index of `Model.key_names`), with nothing kept from earlier steps
    /// (friction tangents, the LCP warm start, the random stream): it then steps exactly as a new
    /// Sim given that state.
    #[pyo3(signature = (key=None))]
    fn reset(&mut self, py: Python<'_>, key: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let m = self.model.clone();
        let k = key.map(|k| super::model::keyframe_index(&m, &k)).transpose()?.map(|i| &m.keys[i]);
        self.qpos.bind(py).readwrite().as_slice_mut()?.copy_from_slice(k.map_or(&m.qpos0, |k| &k.qpos));
        let (mut qvel, mut ctrl) = (self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readwrite());
        let mut act = self.act.bind(py).readwrite();
        match k {
            Some(k) => {
                qvel.as_slice_mut()?.copy_from_slice(&k.qvel);
                ctrl.as_slice_mut()?.copy_from_slice(&k.ctrl);
                act.as_slice_mut()?.copy_from_slice(&k.act);
            }
            None => {
                qvel.as_slice_mut()?.fill(0.0);
                ctrl.as_slice_mut()?.fill(0.0);
                act.as_slice_mut()?.fill(0.0);
            }
        }
        self.qacc.bind(py).readwrite().as_slice_mut()?.fill(0.0);
        self.time = k.map_or(0.0, |k| k.time);
        self.data.constraints.feedforward.fill(0.0);
        self.data.dynamics.xfrc_applied.clear();
        self.data.restore_history(&History::new());
        Ok(())
    }

    /// Applies Cartesian forces to the bodies from the next step on, as MuJoCo's `xfrc_applied`:
    /// (nbody, 6), per body a force at its centre of mass, then a torque, in world axes; held
    /// until set again or reset.
    fn set_xfrc_applied(&mut self, values: Bound<'_, PyAny>) -> PyResult<()> {
        let v = checked_values(&values, "values", &[self.model.nbody, 6])?;
        let xfrc = &mut self.data.dynamics.xfrc_applied;
        xfrc.clear();
        if v.iter().any(|&x| x != 0.0) {
            xfrc.extend_from_slice(&v);
        }
        Ok(())
    }

    /// The forces `set_xfrc_applied` applies (nbody, 6): a copy.
    #[getter]
    fn xfrc_applied<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let nb = self.model.nbody;
        let x = &self.data.dynamics.xfrc_applied;
        let rows = if x.is_empty() { vec![0.0; 6 * nb] } else { x.clone() };
        PyArray1::from_vec(py, rows).reshape([nb, 6])
    }

    /// The state as one float64 array: [time, qpos (nq), qvel (nv), act (na), ctrl (nu)], MuJoCo's
    /// integration state. `full=True` appends the trajectory feed-forward (2 nu) and the history
    /// the next step reads (friction tangents, the LCP's warm start, the random stream, whether
    /// the last step had rows:
    /// `Data::History`), so that a Sim given it steps bit-identically to this one.
    #[pyo3(signature = (full=false))]
    fn get_state<'py>(&self, py: Python<'py>, full: bool) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut v = Vec::with_capacity(1 + self.model.nq + self.model.nv + self.model.nu);
        let (qpos, qvel, ctrl, act) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly(), self.ctrl.bind(py).readonly(), self.act.bind(py).readonly());
        FlatState::write(self.time, (qpos.as_slice()?, qvel.as_slice()?, act.as_slice()?), ctrl.as_slice()?, full.then(|| self.data.full_state()), &mut v);
        Ok(PyArray1::from_vec(py, v))
    }

    /// Restores a state from `get_state`, bit-exactly. A full state (`get_state(full=True)`)
    /// restores the history too, and the Sim then steps exactly as the one it came from; the
    /// short one leaves no history (and zero feed-forward), and the Sim steps as a new Sim given
    /// that state. Bad length or entries raise ValueError and leave the world untouched.
    fn set_state(&mut self, py: Python<'_>, state: Bound<'_, PyAny>) -> PyResult<()> {
        let len = as_f64(&state, "state")?.len()?;
        let v = checked_values(&state, "state", &[len])?;
        let st = FlatState::read(&self.model, &v).map_err(|e| to_py(py, e))?;
        self.time = st.time;
        self.qpos.bind(py).readwrite().as_slice_mut()?.copy_from_slice(st.qpos);
        self.qvel.bind(py).readwrite().as_slice_mut()?.copy_from_slice(st.qvel);
        self.ctrl.bind(py).readwrite().as_slice_mut()?.copy_from_slice(st.ctrl);
        self.act.bind(py).readwrite().as_slice_mut()?.copy_from_slice(st.act);
        let (ff, history) = st.kept();
        self.data.restore(ff, &history);
        Ok(())
    }

    /// Pickles as its model and full state: a copy steps on bit-identically.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<super::Reduced<'py>> {
        let args = pyo3::types::PyTuple::new(py, [self.py_model.bind(py).clone().into_any(), self.get_state(py, true)?.into_any()])?;
        Ok((py.import("sinew._pickle")?.getattr("sim")?, args))
    }

    /// Contacts of the last step: dicts with geom1, geom2, body1, body2, pos, normal, dist (m,
    /// negative when penetrating), normal_force, friction_force (world vector, N) and
    /// friction_torque (the torsional and rolling friction's couple on geom 1, world, N m).
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, pyo3::types::PyDict>>> {
        let m = &*self.model;
        let mut out = Vec::new();
        for (ci, c) in self.data.coll.contacts.iter().enumerate() {
            let f = self.data.constraints.applied.contact.get(ci).copied().unwrap_or_default();
            let d = pyo3::types::PyDict::new(py);
            d.set_item("geom1", c.geom1)?;
            d.set_item("geom2", c.geom2)?;
            d.set_item("body1", m.geom_body[c.geom1])?;
            d.set_item("body2", m.geom_body[c.geom2])?;
            d.set_item("pos", c.pos.to_array())?;
            d.set_item("normal", c.normal.to_array())?;
            d.set_item("dist", c.dist)?;
            d.set_item("normal_force", f.normal)?;
            d.set_item("friction_force", f.friction.to_array())?;
            d.set_item("friction_torque", f.torque.to_array())?;
            out.push(d);
        }
        Ok(out)
    }

    /// The constraint system a step from the current state starts with, computed afresh at it
    /// (the world and its history are untouched): a dict of `kind` (per row: "normal",
    /// "friction", "spin" (torsional or rolling friction), "limit", "motion", "dry_friction", "equality" or "connect"), `J` (rows × nv), `K` (rows × rows, every column by unit
    /// test forces through the articulated-body quantities), `b` (rows,) and `M` (nv × nv, the
    /// CRBA inertia K is built with: M + h × joint damping, which the constrained step treats
    /// implicitly), so that K = J M⁻¹ Jᵀ.
    fn constraint_system<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        use crate::constraint::RowKind;
        self.check_inputs(py)?;
        let m = &*self.model;
        let (mut qpos, mut qvel, ctrl) = (self.qpos.bind(py).readwrite(), self.qvel.bind(py).readwrite(), self.ctrl.bind(py).readonly());
        let (mut time, mut act) = (self.time, self.act.bind(py).to_vec()?);
        let s = WorldState { time: &mut time, qpos: qpos.as_slice_mut()?, qvel: qvel.as_slice_mut()?, ctrl: ctrl.as_slice()?, act: &mut act };
        let sys = crate::step::constraint_system(m, &self.data, &s);
        let nr = sys.kind.len();
        let d = pyo3::types::PyDict::new(py);
        let kinds: Vec<&str> = sys
            .kind
            .iter()
            .map(|k| match k {
                RowKind::Normal => "normal",
                RowKind::Tangent { .. } => "friction",
                RowKind::Spin { .. } => "spin",
                RowKind::Limit => "limit",
                RowKind::Motion { .. } => "motion",
                RowKind::DryFriction => "dry_friction",
                RowKind::Equality => "equality",
                RowKind::Connect { .. } => "connect",
            })
            .collect();
        d.set_item("kind", kinds)?;
        d.set_item("J", PyArray1::from_vec(py, sys.jac).reshape([nr, m.nv])?)?;
        d.set_item("K", PyArray1::from_vec(py, sys.k).reshape([nr, nr])?)?;
        d.set_item("b", PyArray1::from_vec(py, sys.b))?;
        d.set_item("M", PyArray1::from_vec(py, sys.inertia).reshape([m.nv, m.nv])?)?;
        Ok(d)
    }

    /// Constraint statistics: rows of the last step, LCP solves, pivots, warm starts, regularised
    /// retries, solves rescued from a failed Lemke, fallbacks, steps solved as impulses where
    /// the force LCP had no exact answer, rows left out of solves as
    /// separating (summed) and times one was brought back, residual, impacts, post-stabilisation
    /// projections, steps whose velocities the energy bound scaled.
    #[getter]
    fn constraint_stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let c = &self.data.constraints;
        let d = stats_dict(py, &c.stats, c.impacts, c.projections)?;
        d.set_item("rows", c.con.len())?;
        d.set_item("energy_bounded", self.data.energy.bounded)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!("Sim(model='{}', time={})", self.model.name, self.time)
    }
}

impl PySim {
    fn check_inputs(&self, py: Python<'_>) -> PyResult<()> {
        for (name, arr) in [("qpos", &self.qpos), ("qvel", &self.qvel), ("ctrl", &self.ctrl), ("act", &self.act)] {
            let a = arr.bind(py).readonly();
            if let Some(i) = first_nonfinite(a.as_slice()?) {
                return Err(PyValueError::new_err(format!("{name}[{i}] is {} (must be finite)", a.as_slice()?[i])));
            }
        }
        Ok(())
    }

    fn tendons(&mut self, py: Python<'_>) -> PyResult<()> {
        self.kinematics(py)?;
        let qpos = self.qpos.bind(py).readonly();
        tendon::compute(&self.model, &self.data.dynamics.kin, qpos.as_slice()?, &mut self.data.dynamics.ten);
        Ok(())
    }

    fn kinematics(&mut self, py: Python<'_>) -> PyResult<()> {
        let (qpos, qvel) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly());
        kinematics::forward(&self.model, qpos.as_slice()?, qvel.as_slice()?, &mut self.data.dynamics.kin);
        Ok(())
    }
}

/// The LCP counters of `s` (the residual as it is), impacts and projections as a dict: what
/// `Sim.constraint_stats` and `Batch.constraint_stats` share.
pub(super) fn stats_dict<'py>(py: Python<'py>, s: &crate::constraint::lcp::LcpStats, impacts: u64, projections: u64) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let d = pyo3::types::PyDict::new(py);
    for (key, value) in [("solves", s.solves), ("pivots", s.pivots), ("warm_starts", s.warm_starts), ("retries", s.retries), ("rescued", s.rescued),
                         ("fallback_pgs", s.fallback_pgs), ("inexact", s.inexact), ("fallback_zero", s.fallback_zero),
                         ("impulse_steps", s.impulse_steps), ("left_out", s.left_out), ("regrown", s.regrown), ("impacts", impacts), ("projections", projections)] {
        d.set_item(key, value)?;
    }
    d.set_item("residual", s.residual)?;
    Ok(d)
}
