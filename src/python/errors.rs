//! crate::error::Error → Python exceptions, and array-argument conversion with shape checks.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyOSError, PyUserWarning, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::create_exception;

use crate::error::Error;

create_exception!(
    sinew,
    ModelError,
    PyValueError,
    "A model file that is malformed or asks for something sinew does not support."
);
create_exception!(sinew, ModelWarning, PyUserWarning, "A model feature that sinew accepts but does not simulate.");
create_exception!(sinew, SimulationError, PyRuntimeError, "A simulation whose state became non-finite or huge.");

/// Maps a sinew error to the matching Python exception; model errors carry `element`,
/// `attribute` and `line` attributes.
pub fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let msg = e.to_string();
    exception(py, e, msg)
}

/// The exception of `e`'s kind with the message `msg` (an error in a file: its error's kind).
fn exception(py: Python<'_>, e: Error, msg: String) -> PyErr {
    match e {
        Error::Xml { line, .. } => {
            let err = ModelError::new_err(msg);
            let v = err.value(py);
            let _ = v.setattr("line", line);
            let _ = v.setattr("element", py.None());
            let _ = v.setattr("attribute", py.None());
            err
        }
        Error::Model { element, attribute, line, .. } => {
            let err = ModelError::new_err(msg);
            let v = err.value(py);
            let _ = v.setattr("line", line);
            let _ = v.setattr("element", element);
            let _ = v.setattr("attribute", attribute);
            err
        }
        Error::Compile(_) => ModelError::new_err(msg),
        Error::Io(_) => PyOSError::new_err(msg),
        Error::Input(_) => PyValueError::new_err(msg),
        Error::InFile { error, .. } => exception(py, *error, msg),
    }
}

/// Converts any array-like to a contiguous float64 array, as `numpy.ascontiguousarray` (which
/// is not called for an array that already is one).
pub fn as_f64<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(arr) = obj.cast::<PyArrayDyn<f64>>()
        && arr.is_c_contiguous()
    {
        return Ok(arr.clone());
    }
    let py = obj.py();
    let np = py.import("numpy")?;
    let arr = np
        .call_method1("ascontiguousarray", (obj, "float64"))
        .map_err(|e| PyValueError::new_err(format!("{what}: cannot convert to a float64 array ({e})")))?;
    Ok(arr.cast_into::<PyArrayDyn<f64>>()?)
}

/// `as_f64` plus an exact shape check and a finiteness check; returns the values.
pub fn checked_values(obj: &Bound<'_, PyAny>, what: &str, shape: &[usize]) -> PyResult<Vec<f64>> {
    let arr = as_f64(obj, what)?;
    if arr.shape() != shape {
        return Err(PyValueError::new_err(format!("{what}: expected shape {shape:?}, got {:?}", arr.shape())));
    }
    let v = arr.readonly().as_slice()?.to_vec();
    if let Some(i) = first_nonfinite(&v) {
        return Err(PyValueError::new_err(format!("{what}: element {i} is {} (must be finite)", v[i])));
    }
    Ok(v)
}

/// Index of the first non-finite entry, if any.
pub fn first_nonfinite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

/// Raised by `step` when the state leaves the finite range.
pub fn diverged(msg: String) -> PyErr {
    SimulationError::new_err(msg)
}

/// Runs `f`, turning a panic (a bug in sinew) into a `SimulationError` that says so: a Rust panic
/// never reaches Python as a `PanicException` (a `BaseException`).
pub fn guard<T>(what: &str, f: impl FnOnce() -> T) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|e| internal(what, crate::error::panic_message(&*e)))
}

/// As [`guard`] for loading a model: a panic becomes a `ModelError`.
pub fn guard_model<T>(what: &str, f: impl FnOnce() -> T) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|e| {
        ModelError::new_err(format!("{what}: internal error in sinew (a bug; please report it with the model): {}", crate::error::panic_message(&*e)))
    })
}

/// The error for a panic caught in `what`.
pub fn internal(what: &str, msg: String) -> PyErr {
    SimulationError::new_err(format!("{what}: internal error in sinew (a bug; please report it with the model): {msg}"))
}
