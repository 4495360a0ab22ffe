//! crate::error::Error → Python exceptions, and the panic guards of the calls outside the step.

use std::ffi::CString;

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
        // OSError(errno, message) is the errno's own subclass: FileNotFoundError for ENOENT
        Error::Io(_, Some(errno)) => PyOSError::new_err((errno, msg)),
        Error::Io(_, None) => PyOSError::new_err(msg),
        Error::Input(_) => PyValueError::new_err(msg),
        Error::InFile { error, .. } => exception(py, *error, msg),
    }
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

/// One `ModelWarning` for the model: its one warning, or a line that groups many by what they
/// say (`Model.warnings` lists each).
pub fn emit_warnings(py: Python<'_>, m: &crate::model::Model) -> PyResult<()> {
    let text = match m.warnings.as_slice() {
        [] => return Ok(()),
        [one] => one.clone(),
        many => warnings_summary(many),
    };
    let msg = CString::new(text.replace('\0', " ")).expect("no interior NUL");
    PyErr::warn(py, py.get_type::<ModelWarning>().as_any(), &msg, 2)
}

/// Warnings ("<geom> 'a' at line 3: what") grouped by what they say, in the order first seen.
fn warnings_summary(warnings: &[String]) -> String {
    let mut groups: Vec<(&str, &str, usize)> = vec![];
    for w in warnings {
        let (subject, what) = w.split_once(": ").unwrap_or(("", w));
        match groups.iter_mut().find(|g| g.1 == what) {
            Some(g) => g.2 += 1,
            None => groups.push((subject, what, 1)),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|&(subject, what, n)| if n == 1 { format!("{subject}: {what}") } else { format!("{what} ({n} times, first {subject})") })
        .collect();
    format!("{} model features are not simulated as written (Model.warnings lists each): {}", warnings.len(), parts.join("; "))
}
