//! A task from the keyword arguments `Batch.set_task` receives (`envs/sinew/tasks.py` passes
//! the gymnasium v5 env's arguments, defaults filled in): a Python dict read as
//! [`tasks::Params`](crate::tasks::Params).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::model::Model;
use crate::tasks::{self, Task};

/// Reads named parameters from a dict, each exactly once; unknown names are an error.
struct Dict<'py> {
    dict: Bound<'py, PyDict>,
    used: Vec<String>,
}

impl<'py> Dict<'py> {
    fn get<T: for<'a> FromPyObject<'a, 'py>>(&mut self, name: &str) -> Result<T, String> {
        self.used.push(name.to_owned());
        let value = self.dict.get_item(name).ok().flatten().ok_or_else(|| format!("missing parameter '{name}'"))?;
        value.extract().map_err(|_| format!("parameter '{name}' has the wrong type"))
    }

    /// The first key not read, if any.
    fn unused(&self) -> PyResult<Option<String>> {
        for key in self.dict.keys() {
            let k: String = key.extract()?;
            if !self.used.contains(&k) {
                return Ok(Some(k));
            }
        }
        Ok(None)
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

/// Builds task `kind` for model `m` from `params`.
pub fn parse(m: &Model, kind: &str, params: Bound<'_, PyDict>) -> PyResult<Box<dyn Task>> {
    let mut p = Dict { dict: params, used: vec![] };
    let task = tasks::make(kind, m, &mut p).map_err(PyValueError::new_err)?;
    if let Some(k) = p.unused()? {
        return Err(PyValueError::new_err(format!("task {kind}: unknown parameter '{k}'")));
    }
    Ok(task)
}
