//! Arrays from Python: any array-like as contiguous float64, checked for shape and finiteness;
//! world selections (masks and index lists); model arrays to Python (rotations, rows, ranges).

use numpy::{PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
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

/// Indices of the `n` worlds a boolean mask of shape (n,) selects, or all of them.
pub fn masked_worlds(n: usize, mask: Option<Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
    match mask {
        None => Ok((0..n).collect()),
        Some(mk) => {
            // a boolean array as it is; anything else through float64
            if let Ok(b) = mk.cast::<PyArray1<bool>>()
                && b.len() == n
            {
                let v = b.readonly();
                return Ok(v.as_array().iter().enumerate().filter(|(_, x)| **x).map(|(i, _)| i).collect());
            }
            let arr = as_f64(&mk, "mask")?;
            if arr.shape() != [n] {
                return Err(PyValueError::new_err(format!("mask: expected shape [{n}], got {:?}", arr.shape())));
            }
            let v = arr.readonly();
            Ok(v.as_slice()?.iter().enumerate().filter(|(_, x)| **x != 0.0).map(|(i, _)| i).collect())
        }
    }
}

/// Indices of `n` worlds from a boolean mask of shape (n,) or a sequence of indices (all when
/// None).
pub fn chosen_worlds(n: usize, worlds: Option<Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
    let Some(w) = worlds else { return Ok((0..n).collect()) };
    if let Ok(b) = w.cast::<PyArray1<bool>>() {
        if b.len() != n {
            return Err(PyValueError::new_err(format!("worlds: a mask needs shape ({n},), got ({},)", b.len())));
        }
        return masked_worlds(n, Some(w));
    }
    let idx: Vec<i64> = w.extract().map_err(|_| PyValueError::new_err("worlds must be None, a boolean mask or a sequence of world indices"))?;
    idx.iter()
        .map(|&i| {
            if i < 0 || i as usize >= n {
                Err(PyValueError::new_err(format!("worlds: index {i} out of range for {n} worlds")))
            } else {
                Ok(i as usize)
            }
        })
        .collect()
}

/// Rotation matrices as an (n, 3, 3) array, row-major.
pub(super) fn mats<'py>(py: Python<'py>, m: &[glam::DMat3]) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
    let flat: Vec<f64> = m.iter().flat_map(|r| r.transpose().to_cols_array()).collect();
    numpy::PyArray1::from_vec(py, flat).reshape([m.len(), 3, 3])
}

pub(super) fn rows3<'py>(py: Python<'py>, it: impl Iterator<Item = [f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = it.flat_map(|a| a.into_iter()).collect();
    let n = flat.len() / 3;
    numpy::PyArray1::from_vec(py, flat).reshape([n, 3]).expect("n*3 elements")
}

/// Ranges as an (n, 2) array.
pub(super) fn ranges<'py>(py: Python<'py>, rows: impl ExactSizeIterator<Item = [f64; 2]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    PyArray1::from_vec(py, rows.flatten().collect()).reshape([n, 2])
}
