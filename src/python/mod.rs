//! pyo3 bindings (feature `python`): conversion, error mapping, and the Python classes over
//! `step`, `batch` and `render`.

mod arrays;
mod batch;
mod batch_worlds;
mod errors;
mod model;
mod outputs;
mod params;
mod placed;
mod render;
mod sim;
mod task;
mod urdf;

use pyo3::prelude::*;

/// What `__reduce__` returns: the function that rebuilds an object and its arguments.
type Reduced<'py> = (Bound<'py, PyAny>, Bound<'py, pyo3::types::PyTuple>);

/// The compiled extension module `sinew._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<model::PyModel>()?;
    m.add_class::<sim::PySim>()?;
    m.add_class::<batch::PyBatch>()?;
    m.add_function(wrap_pyfunction!(task::task_specs, m)?)?;
    m.add_function(wrap_pyfunction!(urdf::urdf_to_mjcf, m)?)?;
    m.add("ModelError", py.get_type::<errors::ModelError>())?;
    m.add("ModelWarning", py.get_type::<errors::ModelWarning>())?;
    m.add("SimulationError", py.get_type::<errors::SimulationError>())?;
    m.add("MAX_STATE", crate::math::MAX_STATE)?;
    m.add("MAX_RENDER_SIDE", crate::render::MAX_SIDE)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
