//! The output arrays of a batch: a task's (observation, reward, termination, info) and the
//! sensor arrays, borrowed for writing by the Rust side.

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadwriteArray2, PyReadwriteArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::Model;
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

/// A batch's sensor output arrays.
pub(super) struct SensorOutputs {
    pub xpos: Py<PyArray3<f64>>,
    pub xmat: Py<PyArray3<f64>>,
    pub xipos: Py<PyArray3<f64>>,
    pub xvel: Py<PyArray3<f64>>,
    pub cfrc_ext: Py<PyArray3<f64>>,
    pub qfrc_constraint: Py<PyArray2<f64>>,
    pub cinert: Py<PyArray3<f64>>,
    pub cvel: Py<PyArray3<f64>>,
}

impl SensorOutputs {
    /// Zeroed arrays for `n` worlds of `m`.
    pub fn new(py: Python<'_>, n: usize, m: &Model) -> SensorOutputs {
        let per_body = |k: usize| PyArray3::zeros(py, [n, m.nbody, k], false).unbind();
        SensorOutputs {
            xpos: per_body(3),
            xmat: per_body(9),
            xipos: per_body(3),
            xvel: per_body(6),
            cfrc_ext: per_body(6),
            qfrc_constraint: PyArray2::zeros(py, [n, m.nv], false).unbind(),
            cinert: per_body(10),
            cvel: per_body(6),
        }
    }

    /// The arrays, borrowed for writing.
    pub fn readwrite<'py>(&self, py: Python<'py>) -> SensorArrays<'py> {
        SensorArrays {
            xpos: self.xpos.bind(py).readwrite(),
            xmat: self.xmat.bind(py).readwrite(),
            xipos: self.xipos.bind(py).readwrite(),
            xvel: self.xvel.bind(py).readwrite(),
            cfrc_ext: self.cfrc_ext.bind(py).readwrite(),
            qfrc_constraint: self.qfrc_constraint.bind(py).readwrite(),
            cinert: self.cinert.bind(py).readwrite(),
            cvel: self.cvel.bind(py).readwrite(),
        }
    }

    /// Copies of the arrays into `d`, by attribute name.
    pub fn copy_into(&self, d: &Bound<'_, PyDict>) -> PyResult<()> {
        let py = d.py();
        let threes = [("xpos", &self.xpos), ("xmat", &self.xmat), ("xipos", &self.xipos), ("xvel", &self.xvel), ("cfrc_ext", &self.cfrc_ext), ("cinert", &self.cinert), ("cvel", &self.cvel)];
        for (k, a) in threes {
            d.set_item(k, a.bind(py).call_method0("copy")?)?;
        }
        d.set_item("qfrc_constraint", self.qfrc_constraint.bind(py).call_method0("copy")?)
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
