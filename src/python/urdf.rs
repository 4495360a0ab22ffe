//! The URDF conversion Python calls on its own (`sinew.urdf_to_mjcf`) and `Model.from_urdf` uses.

use pyo3::prelude::*;

use super::errors::to_py;

/// A URDF file as MJCF text (the options of `Model.from_urdf`), its mesh files as absolute
/// paths: to place the robot in a scene of your own (a floor, terrain) and load it with
/// `Model.from_mjcf_string`.
#[pyfunction]
#[pyo3(signature = (path, *, floating_base=false, visual=false, package_dirs=None, motors=false, self_collision=false))]
pub fn urdf_to_mjcf(py: Python<'_>, path: std::path::PathBuf, floating_base: bool, visual: bool, package_dirs: Option<Vec<std::path::PathBuf>>, motors: bool, self_collision: bool) -> PyResult<String> {
    let opts = crate::urdf::UrdfOptions { floating_base, visual, package_dirs: package_dirs.unwrap_or_default(), motors, self_collision };
    let made = py.detach(|| {
        super::errors::guard_model("urdf_to_mjcf", || {
            let text = crate::mjcf::read_file(&path)?;
            crate::urdf::to_mjcf(&text, Some(&path), &opts).map_err(|e| e.in_file(&path))
        })
    })?;
    made.map_err(|e| to_py(py, e))
}
