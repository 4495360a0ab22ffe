//! The tasks as Python sees them: their declarations (`sinew._core.task_specs()`, from which
//! `envs/sinew/tasks.py` builds the envs) and a task from the keyword arguments `Batch.set_task`
//! receives (every one of the v5 env's, defaults filled in), a Python dict read as
//! [`tasks::Params`](crate::tasks::Params).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::Model;
use crate::tasks::{self, Reset, Spec, Task, Value};

/// Reads named parameters from a dict.
struct Dict<'py> {
    dict: Bound<'py, PyDict>,
}

impl<'py> Dict<'py> {
    fn get<T: for<'a> FromPyObject<'a, 'py>>(&mut self, name: &str) -> Result<T, String> {
        let value = self.dict.get_item(name).ok().flatten().ok_or_else(|| format!("missing parameter '{name}'"))?;
        value.extract().map_err(|_| format!("parameter '{name}' has the wrong type"))
    }
}

impl tasks::Params for Dict<'_> {
    fn weight(&mut self, name: &str) -> Result<f64, String> {
        let w: f64 = self.get(name)?;
        if !w.is_finite() {
            return Err(format!("'{name}' must be finite, got {w}"));
        }
        Ok(w)
    }

    fn range(&mut self, name: &str) -> Result<[f64; 2], String> {
        let (lo, hi): (f64, f64) = self.get(name)?;
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(format!("'{name}' must be a range (low ≤ high), got ({lo}, {hi})"));
        }
        Ok([lo, hi])
    }

    fn flag(&mut self, name: &str) -> Result<bool, String> {
        self.get(name)
    }

    fn index(&mut self, name: &str) -> Result<usize, String> {
        self.get(name)
    }
}

/// Builds task `kind` for model `m` from `params`, every key one of its spec's parameters.
pub fn parse(m: &Model, kind: &str, params: Bound<'_, PyDict>) -> PyResult<(&'static Spec, Box<dyn Task>)> {
    let spec = tasks::spec(kind).map_err(PyValueError::new_err)?;
    for key in params.keys() {
        let k: String = key.extract()?;
        if !spec.params.iter().any(|(name, _)| *name == k) {
            return Err(PyValueError::new_err(format!("task {kind}: unknown parameter '{k}'")));
        }
    }
    let task = tasks::make(kind, m, &mut Dict { dict: params }).map_err(PyValueError::new_err)?;
    Ok((spec, task))
}

/// A spec value as Python's: float, (low, high), bool, int or (x, y, z).
fn value<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match *v {
        Value::Number(x) => x.into_pyobject(py)?.into_any(),
        Value::Range(lo, hi) => (lo, hi).into_pyobject(py)?.into_any(),
        Value::Flag(b) => pyo3::types::PyBool::new(py, b).to_owned().into_any(),
        Value::Body(i) => i.into_pyobject(py)?.into_any(),
        Value::Point(p) => (p[0], p[1], p[2]).into_pyobject(py)?.into_any(),
    })
}

/// Every task's declaration, in registration order: dicts of name, xml, frame_skip,
/// max_episode_steps, camera (dict), params (dict of defaults, in order), reset ("uniform",
/// "uniform_normal" or "reacher_goal") and reset_info (list of info names).
#[pyfunction]
pub fn task_specs(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    tasks::TASKS
        .iter()
        .map(|s| {
            let d = PyDict::new(py);
            d.set_item("name", s.name)?;
            d.set_item("xml", s.xml)?;
            d.set_item("frame_skip", s.frame_skip)?;
            d.set_item("max_episode_steps", s.max_episode_steps)?;
            let (camera, params) = (PyDict::new(py), PyDict::new(py));
            for (k, v) in s.camera {
                camera.set_item(k, value(py, v)?)?;
            }
            for (k, v) in s.params {
                params.set_item(k, value(py, v)?)?;
            }
            d.set_item("camera", camera)?;
            d.set_item("params", params)?;
            let reset = match s.reset {
                Reset::Uniform => "uniform",
                Reset::UniformNormal => "uniform_normal",
                Reset::ReacherGoal => "reacher_goal",
            };
            d.set_item("reset", reset)?;
            d.set_item("reset_info", s.reset_info.to_vec())?;
            Ok(d)
        })
        .collect()
}
