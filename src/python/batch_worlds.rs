//! `sinew.Batch`'s own helpers: which worlds a call names, and bringing their outputs, surfaces
//! and placed geoms up to date.

use numpy::{PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::{as_f64, checked_values, chosen_worlds, masked_worlds};
use super::batch::PyBatch;
use crate::render::Placed;

impl PyBatch {
    /// World indices selected by a boolean mask of shape (N,), or all of them.
    pub(super) fn chosen(&self, mask: Option<Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
        masked_worlds(self.inner.len(), mask)
    }

    /// Copies of the sensor, task and divergence output arrays, by attribute name.
    pub(super) fn clone_outputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        self.out.copy_into(&d)?;
        d.set_item("diverged", self.diverged.bind(py).call_method0("copy")?)?;
        if let Some(t) = &self.task {
            d.set_item("obs", t.obs.bind(py).call_method0("copy")?)?;
            d.set_item("reward", t.reward.bind(py).call_method0("copy")?)?;
            d.set_item("terminated", t.terminated.bind(py).call_method0("copy")?)?;
            d.set_item("info", t.info.bind(py).call_method0("copy")?)?;
        }
        Ok(d)
    }

    /// A world index, checked.
    pub(super) fn world(&self, i: usize) -> PyResult<usize> {
        if i >= self.inner.len() {
            return Err(PyValueError::new_err(format!("world {i} out of range for {} worlds", self.inner.len())));
        }
        Ok(i)
    }

    /// World indices from a boolean mask of shape (N,) or a sequence of indices (all when None).
    pub(super) fn worlds(&self, worlds: Option<Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
        chosen_worlds(self.inner.len(), worlds)
    }

    pub(super) fn refresh_poses(&mut self, py: Python<'_>) -> PyResult<()> {
        let all: Vec<usize> = (0..self.inner.len()).collect();
        self.refresh(py, &all)
    }

    /// Sensor outputs of the worlds `which` for their current state.
    pub(super) fn refresh(&mut self, py: Python<'_>, which: &[usize]) -> PyResult<()> {
        let m = self.inner.model.clone();
        let (qpos, qvel) = (self.qpos.bind(py).readonly(), self.qvel.bind(py).readonly());
        let mut arrays = self.out.readwrite(py);
        let mut out = arrays.slices()?;
        let ctrl = self.ctrl.bind(py).readonly();
        let (qp, qv, c) = (qpos.as_slice()?, qvel.as_slice()?, ctrl.as_slice()?);
        let mut outputs = self.task.as_ref().map(|t| t.borrow(py));
        let mut task = match &mut outputs {
            Some((task, obs, ..)) => Some((&**task, obs.as_slice_mut()?)),
            None => None,
        };
        for &i in which {
            let obs = task.as_mut().map(|(t, obs)| {
                let dim = obs.len() / self.inner.len();
                (*t, &mut obs[i * dim..(i + 1) * dim])
            });
            let (q, v, u) = (&qp[i * m.nq..(i + 1) * m.nq], &qv[i * m.nv..(i + 1) * m.nv], &c[i * m.nu..(i + 1) * m.nu]);
            self.inner.sense(i, q, v, u, out.world(i, m.nbody, m.nv), obs);
        }
        Ok(())
    }
}

impl PyBatch {
    /// The surfaces the worlds `which` are drawn with: their own where their height fields are.
    pub(super) fn redraw(&mut self, py: Python<'_>, which: &[usize]) {
        self.moved.redraw(&self.inner, || self.py_model.bind(py).get().renderer(), which);
    }

    /// Puts `what` at `pos` (one row, or one per chosen world) in the worlds `worlds`.
    pub(super) fn place(&mut self, what: Placed, pos: Bound<'_, PyAny>, worlds: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        let which = self.worlds(worlds)?;
        // one position for all the worlds, or one row each
        let rows = if as_f64(&pos, "pos")?.ndim() == 1 {
            vec![checked_values(&pos, "pos", &[3])?; which.len()].concat()
        } else {
            checked_values(&pos, "pos", &[which.len(), 3])?
        };
        self.moved.place(&self.inner.model, self.inner.len(), what, &which, &rows);
        Ok(())
    }
}
