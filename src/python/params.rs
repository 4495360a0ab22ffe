//! Per-world model values from Python: fields by MuJoCo's names, broadcast to the chosen
//! worlds, read back as (N, ...) arrays.

use numpy::{PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::arrays::as_f64;
use crate::batch::Batch;
use crate::compile::params::Param;
use crate::model::Model;

/// The field called `name`, or an error listing the fields.
pub fn named(name: &str) -> PyResult<Param> {
    Param::named(name).ok_or_else(|| {
        let names: Vec<&str> = Param::ALL.iter().map(|p| p.name()).collect();
        PyValueError::new_err(format!("unknown parameter '{name}': one of {}", names.join(", ")))
    })
}

/// The field's shape as Python sees it: (rows,) for one column, (3,) for gravity.
pub fn shape(p: Param, m: &Model) -> Vec<usize> {
    match p.shape(m) {
        (1, c) if p == Param::Gravity => vec![c],
        (r, 1) => vec![r],
        (r, c) => vec![r, c],
    }
}

/// `values` broadcast to one row of the field per world of `which`, row after row.
pub fn broadcast(py: Python<'_>, p: Param, m: &Model, values: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<f64>> {
    let target: Vec<usize> = std::iter::once(n).chain(shape(p, m)).collect();
    let arr = as_f64(values, p.name())?;
    let np = py.import("numpy")?;
    let full = np.call_method1("broadcast_to", (&arr, target.clone())).map_err(|_| {
        let got: Vec<usize> = numpy::PyUntypedArrayMethods::shape(&arr).to_vec();
        PyValueError::new_err(format!("{}: values of shape {got:?} do not broadcast to {target:?} (worlds, ...)", p.name()))
    })?;
    let full = np.call_method1("ascontiguousarray", (full,))?.cast_into::<PyArrayDyn<f64>>()?;
    Ok(full.readonly().as_slice()?.to_vec())
}

/// Field `p` of every world as an (N, ...) array.
pub fn read<'py>(py: Python<'py>, b: &Batch, p: Param) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let dims: Vec<usize> = std::iter::once(b.len()).chain(shape(p, &b.model)).collect();
    numpy::PyArray1::from_vec(py, b.param(p)).reshape(dims)
}

/// What pickling keeps of the worlds with values of their own: (world, every field's values in
/// [`Param::ALL`]'s order, the inertia matrices bit for bit).
pub type Varied = Vec<(usize, Vec<Vec<f64>>, Vec<f64>)>;

/// The worlds' own values, for pickling.
pub fn varied(b: &Batch) -> Varied {
    let fields = |i: usize| Param::ALL.iter().map(|p| p.read(b.model_of(i))).collect();
    b.varied().into_iter().map(|i| (i, fields(i), b.inertia_matrices(i))).collect()
}

/// Gives the worlds back the values `varied` kept.
pub fn restore(b: &mut Batch, varied: Varied) -> crate::error::Result<()> {
    varied.into_iter().try_for_each(|(i, fields, inertia)| b.restore_params(i, &fields, &inertia))
}
