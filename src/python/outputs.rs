//! The output arrays of a batch: a task's (observation, reward, termination, info) and the
//! sensor arrays, borrowed for writing by the Rust side.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadwriteArray2, PyReadwriteArray3};
use pyo3::prelude::*;

use crate::sensors::Sensors;
use crate::tasks::Task;

/// A task set on a batch and its output arrays.
pub(super) struct TaskArrays {
    pub spec: &'static crate::tasks::Spec,
    pub task: Box<dyn Task>,
    pub obs: Py<PyArray2<f64>>,
    pub reward: Py<PyArray1<f64>>,
    pub terminated: Py<PyArray1<bool>>,
    pub info: Py<PyArray2<f64>>,
}

impl TaskArrays {
    /// The task and its output arrays, borrowed for writing.
    #[allow(clippy::type_complexity)]
    pub fn borrow<'py>(
        &self,
        py: Python<'py>,
    ) -> (&dyn Task, PyReadwriteArray2<'py, f64>, numpy::PyReadwriteArray1<'py, f64>, numpy::PyReadwriteArray1<'py, bool>, PyReadwriteArray2<'py, f64>) {
        (&*self.task, self.obs.bind(py).readwrite(), self.reward.bind(py).readwrite(), self.terminated.bind(py).readwrite(), self.info.bind(py).readwrite())
    }
}

/// Write borrows of a batch's sensor arrays.
pub(super) struct SensorArrays<'py> {
    pub xpos: PyReadwriteArray3<'py, f64>,
    pub xmat: PyReadwriteArray3<'py, f64>,
    pub xipos: PyReadwriteArray3<'py, f64>,
    pub xvel: PyReadwriteArray3<'py, f64>,
    pub cfrc_ext: PyReadwriteArray3<'py, f64>,
    pub qfrc_constraint: PyReadwriteArray2<'py, f64>,
    pub cinert: PyReadwriteArray3<'py, f64>,
    pub cvel: PyReadwriteArray3<'py, f64>,
}

impl SensorArrays<'_> {
    /// Every world's outputs as one [`Sensors`].
    pub fn slices(&mut self) -> PyResult<Sensors<'_>> {
        Ok(Sensors {
            xpos: self.xpos.as_slice_mut()?,
            xmat: self.xmat.as_slice_mut()?,
            xipos: self.xipos.as_slice_mut()?,
            xvel: self.xvel.as_slice_mut()?,
            cfrc_ext: self.cfrc_ext.as_slice_mut()?,
            qfrc_constraint: self.qfrc_constraint.as_slice_mut()?,
            cinert: self.cinert.as_slice_mut()?,
            cvel: self.cvel.as_slice_mut()?,
        })
    }
}
