//! The house's rules, read from the crate's own source: no source file over 700 lines, and no
//! import circle between files. An import is a `use` of, or a path through, `crate::`, `super::`,
//! `self::` or a child module; it points at the file of the deepest module the path names. A
//! module's file reaching into its own submodules (declaring them, handing their names on) is that
//! room's face, not an import between files: those edges are left out, so a child that uses its
//! parent's types closes no circle.
//! A file's `#[cfg(test)] mod tests` is its tests, not part of the house, and is left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 700;

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file under `src/` (`src/a/mod.rs` and `src/a.rs` are both `a`).
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// The code of a file without comments, string literals and its test module.
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    let (mut out, mut chars) = (String::new(), text.chars().peekable());
    while let Some(c) = chars.next() {
        match (c, chars.peek()) {
            ('/', Some('/')) => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                let mut last = ' ';
                for c in chars.by_ref() {
                    if last == '*' && c == '/' {
                        break;
                    }
                    last = c;
                }
            }
            ('"', _) => {
                let mut escaped = false;
                for c in chars.by_ref() {
                    if c == '"' && !escaped {
                        break;
                    }
                    escaped = c == '\\' && !escaped;
                }
                out.push_str("\"\"");
            }
            _ => out.push(c),
        }
    }
    out
}

/// The paths a `use` tree names, braces expanded (`a::{b, c::d}` → `a::b`, `a::c::d`).
fn expand(tree: &str) -> Vec<Vec<String>> {
    fn walk(tokens: &[String], at: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
        let mut path = prefix.to_vec();
        while *at < tokens.len() {
            let t = tokens[*at].clone();
            *at += 1;
            match t.as_str() {
                "{" => {
                    loop {
                        walk(tokens, at, &path, out);
                        let sep = tokens.get(*at).cloned();
                        *at += 1;
                        if sep.as_deref() != Some(",") {
                            break;
                        }
                    }
                    return;
                }
                "," | "}" => {
                    *at -= 1;
                    break;
                }
                "as" => *at += 1,
                "::" | "*" => {}
                _ => path.push(t),
            }
        }
        out.push(path);
    }
    let tokens: Vec<String> = tree
        .replace("::", " :: ")
        .replace('{', " { ")
        .replace('}', " } ")
        .replace(',', " , ")
        .split_whitespace()
        .map(str::to_string)
        .collect();
    let mut out = vec![];
    walk(&tokens, &mut 0, &[], &mut out);
    out
}

/// The paths a file names through `use` and inline (`crate::a::b`, `super::c`).
fn paths(code: &str) -> Vec<Vec<String>> {
    let mut out = vec![];
    let mut rest = String::new();
    for stmt in code.split_inclusive(';') {
        let t = stmt.trim_start();
        let t = t.strip_prefix("pub(crate) ").or_else(|| t.strip_prefix("pub(super) ")).or_else(|| t.strip_prefix("pub ")).unwrap_or(t);
        match t.strip_prefix("use ") {
            Some(tree) => out.extend(expand(tree.trim_end_matches(';'))),
            None => rest.push_str(stmt),
        }
    }
    let bytes: Vec<char> = rest.chars().collect();
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut i = 0;
    while i < bytes.len() {
        if ident(bytes[i]) && (i == 0 || !ident(bytes[i - 1])) {
            let mut j = i;
            while j < bytes.len() && (ident(bytes[j]) || (bytes[j] == ':' && bytes.get(j + 1) == Some(&':'))) {
                j += if bytes[j] == ':' { 2 } else { 1 };
            }
            let word: String = bytes[i..j].iter().collect();
            if word.starts_with("crate::") || word.starts_with("super::") || word.starts_with("self::") {
                out.push(word.split("::").filter(|s| !s.is_empty()).map(str::to_string).collect());
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    out
}

/// The file of the deepest module that `path` names from module `here` (None outside the crate).
fn resolve(src: &Path, here: &[String], children: &BTreeSet<String>, path: &[String]) -> Option<PathBuf> {
    let mut module: Vec<String> = match path.first()?.as_str() {
        "crate" => vec![],
        "self" | "super" => here.to_vec(),
        first if children.contains(first) => here.to_vec(),
        _ => return None,
    };
    let mut rest = path;
    if rest[0] == "crate" || rest[0] == "self" {
        rest = &rest[1..];
    }
    while rest.first().is_some_and(|s| s == "super") {
        module.pop();
        rest = &rest[1..];
    }
    let file_of = |m: &[String]| {
        let base = m.iter().fold(src.to_path_buf(), |p, s| p.join(s));
        if m.is_empty() {
            return Some(src.join("lib.rs"));
        }
        [base.with_extension("rs"), base.join("mod.rs")].into_iter().find(|p| p.is_file())
    };
    let mut found = file_of(&module);
    for seg in rest {
        module.push(seg.clone());
        match file_of(&module) {
            Some(f) => found = Some(f),
            None => break,
        }
    }
    found
}

/// Whether module `other` lies inside module `here` (a submodule of it, at any depth).
fn inside(here: &[String], other: &[String]) -> bool {
    other.len() > here.len() && other.starts_with(here)
}

/// The import graph: each file's set of files it imports (itself left out).
fn graph(src: &Path) -> (BTreeMap<PathBuf, BTreeSet<PathBuf>>, Vec<(PathBuf, usize)>) {
    let mut files = vec![];
    sources(src, &mut files);
    let (mut edges, mut lines) = (BTreeMap::new(), vec![]);
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        lines.push((file.clone(), text.lines().count()));
        let code = code(&text);
        let children: BTreeSet<String> = code
            .lines()
            .filter_map(|l| l.trim().trim_start_matches("pub ").strip_prefix("mod ")?.strip_suffix(';').map(str::to_string))
            .collect();
        let here = module_of(src, file);
        let to: BTreeSet<PathBuf> = paths(&code)
            .iter()
            .filter_map(|p| resolve(src, &here, &children, p))
            .filter(|t| t != file && !inside(&here, &module_of(src, t)))
            .collect();
        edges.insert(file.clone(), to);
    }
    (edges, lines)
}

/// The circles of `edges` (strongly connected sets of more than one file; Tarjan 1972).
fn circles(edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    struct S<'a> {
        edges: &'a BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: BTreeMap<&'a PathBuf, (usize, usize)>,
        stack: Vec<&'a PathBuf>,
        on: BTreeSet<&'a PathBuf>,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut S<'a>, v: &'a PathBuf) {
        let n = s.index.len();
        s.index.insert(v, (n, n));
        s.stack.push(v);
        s.on.insert(v);
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.index[w].1.min(s.index[v].1);
                s.index.get_mut(v).unwrap().1 = low;
            } else if s.on.contains(w) {
                let low = s.index[w].0.min(s.index[v].1);
                s.index.get_mut(v).unwrap().1 = low;
            }
        }
        if s.index[v].0 == s.index[v].1 {
            let mut set = vec![];
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                set.push(w.clone());
                if w == v {
                    break;
                }
            }
            if set.len() > 1 {
                s.out.push(set);
            }
        }
    }
    let mut s = S { edges, index: BTreeMap::new(), stack: vec![], on: BTreeSet::new(), out: vec![] };
    for v in edges.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn no_import_circle() {
    let (edges, _) = graph(&src());
    let found = circles(&edges);
    assert!(found.is_empty(), "import circles between files: {found:#?}");
}

#[test]
fn no_file_over_700_lines() {
    let (_, lines) = graph(&src());
    let long: Vec<_> = lines.into_iter().filter(|(_, n)| *n > MAX_LINES).collect();
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

#[test]
fn the_check_sees_imports_and_circles() {
    // the reader itself: a grouped use, an inline path and a circle of two files
    let src = src();
    let named = paths(&code("use crate::constraint::{rows::build_rows, solve};\nfn f() { crate::math::Force::ZERO; } // crate::urdf\n"));
    let here = vec!["step".to_string()];
    let files: BTreeSet<_> = named.iter().filter_map(|p| resolve(&src, &here, &BTreeSet::new(), p)).collect();
    let want: BTreeSet<_> = ["constraint/rows.rs", "constraint/solve.rs", "math/mod.rs"].iter().map(|f| src.join(f)).collect();
    assert_eq!(files, want);
    let (a, b, c) = (PathBuf::from("a"), PathBuf::from("b"), PathBuf::from("c"));
    let edges = BTreeMap::from([(a.clone(), BTreeSet::from([b.clone()])), (b.clone(), BTreeSet::from([a.clone()])), (c, BTreeSet::from([a]))]);
    assert_eq!(circles(&edges).len(), 1);
    // and the graph it reads is not empty: step/mod.rs imports the constraint room
    let (edges, _) = graph(&src);
    assert!(edges[&src.join("step/mod.rs")].contains(&src.join("constraint/solve.rs")));
}
