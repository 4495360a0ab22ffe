//! `<include file="…"/>`: the children of the included file's `<mujoco>` (or `<mujocoinclude>`)
//! element in place of the element, nested includes too. A path is taken relative to the including file's directory, else
//! to the main file's (MuJoCo's rule; both agree for a file beside the main one). The expanded text
//! keeps a map from its lines to the files and lines they came from, so an error names the file
//! it is in.

use std::path::{Path, PathBuf};

use roxmltree::Document;

use crate::error::{Error, Result};

/// Deepest nesting of includes accepted.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// MJCF text with every include spliced in, and where each of its lines came from.
#[derive(Clone, Debug)]
pub struct Expanded {
    /// The text, without `<include>` elements.
    pub text: String,
    /// Runs of lines from one file: (first line here, file (None: the main text), its line there).
    runs: Vec<(u32, Option<PathBuf>, u32)>,
    /// The main file's directory (the working directory for text given directly): where asset
    /// paths start.
    pub dir: PathBuf,
}

impl Expanded {
    /// The file (None: the main text) and line that line `line` of the text came from.
    fn origin(&self, line: u32) -> (Option<&Path>, u32) {
        let k = self.runs.partition_point(|r| r.0 <= line).saturating_sub(1);
        match self.runs.get(k) {
            Some((start, file, from)) => (file.as_deref(), from + (line - start)),
            None => (None, line),
        }
    }

    /// The directory of the file that line `line` of the text came from.
    pub fn dir_of(&self, line: u32) -> &Path {
        self.origin(line).0.and_then(Path::parent).unwrap_or(&self.dir)
    }

    /// `e` (about a line of the text) as an error about the file and line it came from.
    pub fn locate(&self, e: Error) -> Error {
        let (file, line) = match &e {
            Error::Xml { line, .. } | Error::Model { line, .. } => self.origin(*line),
            _ => return e,
        };
        let e = match e {
            Error::Xml { message, .. } => Error::Xml { line, message },
            Error::Model { element, attribute, message, .. } => Error::Model { element, attribute, line, message },
            other => other,
        };
        match file {
            Some(f) => e.in_file(f),
            None => e,
        }
    }
}

/// Expands the includes of `text`, the contents of `file` (None: text given directly, whose
/// includes are relative to the working directory).
pub fn expand(text: &str, file: Option<&Path>) -> Result<Expanded> {
    let main_dir = file.and_then(Path::parent).map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    if !text.contains("include") {
        return Ok(Expanded { text: text.to_string(), runs: vec![(1, None, 1)], dir: main_dir });
    }
    let mut out = Builder { text: String::with_capacity(text.len()), lines: 1, runs: vec![], main_dir, stack: vec![] };
    out.splice(text, None, file.map(Path::to_path_buf), 0..text.len())?;
    Ok(Expanded { text: out.text, runs: out.runs, dir: out.main_dir })
}

struct Builder {
    text: String,
    /// The line the text ends on.
    lines: u32,
    runs: Vec<(u32, Option<PathBuf>, u32)>,
    main_dir: PathBuf,
    /// The files being included, outermost first (a file including itself is an error).
    stack: Vec<PathBuf>,
}

impl Builder {
    /// Appends `text[range]` (of `file`; `shown` is the file an error names, None for the main
    /// text), each include in it replaced by its file's contents.
    fn splice(&mut self, text: &str, shown: Option<PathBuf>, file: Option<PathBuf>, range: std::ops::Range<usize>) -> Result<()> {
        let doc = Document::parse(text).map_err(|e| in_file(Error::Xml { line: e.pos().row, message: e.to_string() }, &shown))?;
        let mut at = range.start;
        let includes: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("include") && range.contains(&n.range().start)).collect();
        for n in includes {
            self.push(text, &shown, at..n.range().start);
            at = n.range().end;
            let line = doc.text_pos_at(n.range().start).row;
            let err = |msg: String| in_file(Error::model("include", Some("file"), line, msg), &shown);
            let Some(name) = n.attribute("file") else { return Err(in_file(Error::model("include", Some("file"), line, "required"), &shown)) };
            if n.has_children() {
                return Err(in_file(Error::model("include", None, line, "takes no children"), &shown));
            }
            if self.stack.len() >= MAX_INCLUDE_DEPTH {
                return Err(err(format!("includes nested more than {MAX_INCLUDE_DEPTH} deep")));
            }
            let path = self.resolve(file.as_deref(), name);
            if self.stack.contains(&path) {
                return Err(err(format!("'{name}' includes itself")));
            }
            let inner = super::read_file(&path).map_err(|e| match e {
                Error::Io(m, _) => err(m),
                other => other.in_file(&path),
            })?;
            let idoc = Document::parse(&inner).map_err(|e| Error::Xml { line: e.pos().row, message: e.to_string() }.in_file(&path))?;
            let root = idoc.root_element();
            // MuJoCo takes <mujocoinclude>, the older name, as well
            if !root.has_tag_name("mujoco") && !root.has_tag_name("mujocoinclude") {
                let l = idoc.text_pos_at(root.range().start).row;
                return Err(Error::model(root.tag_name().name(), None, l, "the root element of an included file must be <mujoco> (or <mujocoinclude>)").in_file(&path));
            }
            let body = match (root.first_child(), root.last_child()) {
                (Some(first), Some(last)) => first.range().start..last.range().end,
                _ => 0..0,
            };
            self.stack.push(path.clone());
            self.newlines("\n");
            self.splice(&inner, Some(path.clone()), Some(path), body)?;
            self.newlines("\n");
            self.stack.pop();
        }
        self.push(text, &shown, at..range.end);
        Ok(())
    }

    /// Appends `text[range]` as one run of `file`'s lines.
    fn push(&mut self, text: &str, file: &Option<PathBuf>, range: std::ops::Range<usize>) {
        if range.is_empty() {
            return;
        }
        let there = 1 + text[..range.start].matches('\n').count() as u32;
        self.runs.push((self.lines, file.clone(), there));
        self.newlines(&text[range]);
    }

    /// Appends `s`, counting its lines.
    fn newlines(&mut self, s: &str) {
        self.lines += s.matches('\n').count() as u32;
        self.text.push_str(s);
    }

    /// The path of `name` included from `from`: beside `from` when it is there, else in the main
    /// file's directory.
    fn resolve(&self, from: Option<&Path>, name: &str) -> PathBuf {
        let beside = from.and_then(Path::parent).map(|d| d.join(name));
        match beside {
            Some(p) if p.exists() => p,
            _ => self.main_dir.join(name),
        }
    }
}

/// `e` as an error in `file` when it names one.
fn in_file(e: Error, file: &Option<PathBuf>) -> Error {
    match file {
        Some(f) => e.in_file(f),
        None => e,
    }
}
