//! The crate's error type; the only place error text is assembled.

use std::fmt;

/// Everything that can go wrong when loading a model or driving a simulation.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// The MJCF text is not well-formed XML.
    Xml {
        /// 1-based line of the problem.
        line: u32,
        /// What the XML parser reported.
        message: String,
    },
    /// Well-formed XML that is not a valid or supported model: names the element, attribute and line.
    Model {
        /// Element tag, e.g. `joint`.
        element: String,
        /// Offending attribute, when one is to blame.
        attribute: Option<String>,
        /// 1-based line of the element.
        line: u32,
        /// What is wrong.
        message: String,
    },
    /// A model that parsed but cannot be compiled (e.g. a moving body without mass).
    Compile(String),
    /// A file could not be read: what, and the OS's error number (ENOENT: no such file).
    Io(String, Option<i32>),
    /// Bad runtime input: wrong shape, non-finite value, out-of-range option.
    Input(String),
    /// An error in a model file: the file, and the error.
    InFile {
        /// The file's path as given.
        file: String,
        /// What is wrong in it.
        error: Box<Error>,
    },
}

/// Result alias for sinew.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// A file that could not be read: `what` names it, `e` says why.
    pub fn io(what: String, e: &std::io::Error) -> Self {
        Error::Io(format!("{what}: {e}"), e.raw_os_error())
    }

    /// Error about an element (and optionally one of its attributes) at a line.
    pub fn model(element: &str, attribute: Option<&str>, line: u32, message: impl Into<String>) -> Self {
        Error::Model {
            element: element.to_string(),
            attribute: attribute.map(str::to_string),
            line,
            message: message.into(),
        }
    }

    /// The error as one in the file `path` (an error already naming a file is kept).
    pub fn in_file(self, path: &std::path::Path) -> Self {
        match self {
            Error::InFile { .. } | Error::Io(..) => self,
            error => Error::InFile { file: path.display().to_string(), error: Box::new(error) },
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Xml { line, message } => write!(f, "malformed XML at line {line}: {message}"),
            Error::Model { element, attribute: Some(a), line, message } => {
                write!(f, "<{element}> attribute '{a}' at line {line}: {message}")
            }
            Error::Model { element, attribute: None, line, message } => {
                write!(f, "<{element}> at line {line}: {message}")
            }
            Error::Compile(m) => write!(f, "model compilation failed: {m}"),
            Error::Io(m, _) => write!(f, "{m}"),
            Error::Input(m) => write!(f, "{m}"),
            Error::InFile { file, error } => write!(f, "{file}: {error}"),
        }
    }
}

impl std::error::Error for Error {}

/// The message of a caught panic.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic without a message".to_string()
    }
}
