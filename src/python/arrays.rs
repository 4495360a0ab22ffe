//! Arrays from Python: any array-like as contiguous float64, checked for shape and finiteness.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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

