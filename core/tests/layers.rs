//! The module graph of core/src, read from the sources: every `use`
//! (with its brace trees, `self`, `super`, `crate` and the re-exports of
//! the `mod.rs` files followed to what they name) and every inline
//! `crate::…`/`super::…` path outside comments and `mod tests` is an
//! import of one module (file) by another. The test fails on
//! - an import circle between modules (files), or between the top-level
//!   modules (`slam`, `shapes`, `nvector`, ...);
//! - a module importing a module of a higher layer;
//! - a module of core/src missing from the tables, or a row naming none.
//!
//! The layers are the pipeline of ARCHITECTURE.md, read from its tables
//! ([`table`]: the one copy): each may import only its own layer (without
//! circles) and the layers below. A file declared test-only by its parent
//! (`#[cfg(test)] mod tests;`) is no module of the graph, as an inline
//! `mod tests { .. }` is not.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The layer tables of ARCHITECTURE.md, the one copy: every table under a
/// heading `### core layer N: ...`, one row per module (its first cell the
/// module's path in backticks, `crate` for the root). A module takes the
/// layer of the longest row that is its path or a parent of it. Errors: a
/// heading without a number, a module named twice, no row at all.
fn table(md: &str) -> Result<Vec<(String, u32)>, String> {
    let mut rows: Vec<(String, u32)> = Vec::new();
    let mut layer: Option<u32> = None;
    for (i, line) in md.lines().enumerate() {
        if line.starts_with('#') {
            layer = match line.strip_prefix("### core layer ") {
                None => None,
                Some(rest) => {
                    let n = rest.split(|c: char| !c.is_ascii_digit()).next();
                    let n = n.and_then(|n| n.parse().ok()).ok_or_else(|| {
                        format!("ARCHITECTURE.md line {}: no layer number: {line}", i + 1)
                    })?;
                    Some(n)
                }
            };
            continue;
        }
        let (Some(l), Some(row)) = (layer, line.strip_prefix("| `")) else {
            continue;
        };
        let Some((module, _)) = row.split_once('`') else {
            return Err(format!("ARCHITECTURE.md line {}: {line}", i + 1));
        };
        let module = if module == "crate" { "" } else { module };
        if rows.iter().any(|(m, _)| m == module) {
            return Err(format!(
                "ARCHITECTURE.md line {}: `{module}` is in the tables twice",
                i + 1
            ));
        }
        rows.push((module.to_string(), l));
    }
    if rows.is_empty() {
        return Err("ARCHITECTURE.md has no `### core layer N` table".to_string());
    }
    Ok(rows)
}

/// ARCHITECTURE.md's layer tables.
// The test reads the workspace's own map: I/O of core's tests only.
#[allow(clippy::disallowed_methods, clippy::disallowed_types)]
fn architecture() -> Vec<(String, u32)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ARCHITECTURE.md");
    let md = std::fs::read_to_string(&path).expect("ARCHITECTURE.md beside core/");
    table(&md).unwrap_or_else(|e| panic!("{e}"))
}

/// A module path: `[]` is the crate root, `["slam", "rounds"]` is
/// `slam/rounds.rs`.
type Module = Vec<String>;

fn name(m: &[String]) -> String {
    if m.is_empty() {
        "crate".to_string()
    } else {
        m.join("::")
    }
}

/// The source with comments, strings' `//` aside, and test-only module
/// blocks (`#[cfg(test)] mod tests { .. }`, `#[cfg(all(test, unix))]`)
/// removed.
fn strip(src: &str) -> String {
    let mut out = String::new();
    for line in src.lines() {
        let code = match line.find("//") {
            // A `//` inside a string literal is rare in core; a quote before
            // it keeps the line whole.
            Some(i) if !line[..i].contains('"') => &line[..i],
            _ => line,
        };
        out.push_str(code);
        out.push('\n');
    }
    // Cut each `#[cfg(test)]` item that is a `mod NAME {` block.
    let mut s = out;
    let mut from = 0;
    while let Some(i) = s[from..].find("#[cfg(").map(|i| i + from) {
        // The attribute: `#[cfg(test)]`, `#[cfg(all(test, unix))]`, ...
        let Some(len) = s[i..].find(")]").map(|j| j + 2) else {
            break;
        };
        let attr = &s[i..i + len];
        let is_test = attr
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .any(|w| w == "test")
            && !attr.contains("not(");
        if !is_test {
            from = i + 1;
            continue;
        }
        let rest = &s[i + len..];
        let mut trimmed = rest.trim_start();
        for vis in ["pub(crate) ", "pub(super) ", "pub "] {
            trimmed = trimmed.strip_prefix(vis).unwrap_or(trimmed);
        }
        let is_block = trimmed.starts_with("mod ")
            && trimmed
                .find(['{', ';'])
                .is_some_and(|j| trimmed.as_bytes()[j] == b'{');
        if !is_block {
            from = i + 1;
            continue;
        }
        let open = i + len + rest.find('{').expect("a brace");
        let mut depth = 0usize;
        let mut end = s.len();
        for (k, c) in s[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + k + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        s.replace_range(i..end, "");
        from = i;
    }
    s
}

/// The file modules a source declares test-only: `#[cfg(test)]` (or a
/// compound cfg with `test`, not `not(test)`) before `mod NAME;`.
fn test_files(src: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut test_attr = false;
    for line in src.lines().map(str::trim) {
        if line.starts_with("#[cfg(") {
            test_attr = line
                .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .any(|w| w == "test")
                && !line.contains("not(");
            continue;
        }
        if test_attr {
            let decl = ["pub(crate) ", "pub(super) ", "pub "]
                .iter()
                .fold(line, |l, vis| l.strip_prefix(vis).unwrap_or(l));
            if let Some(name) = decl.strip_prefix("mod ").and_then(|r| r.strip_suffix(';')) {
                out.push(name.trim().to_string());
            }
        }
        test_attr = false;
    }
    out
}

/// Expands a use tree (`a::{b, c::{d, e as f}, self}`) into paths (the
/// `as` renames kept as the last element: `(path, alias)`).
fn expand(tree: &str) -> Vec<(Vec<String>, String)> {
    let tree: String = tree
        .chars()
        .filter(|c| !c.is_whitespace() || *c == ' ')
        .collect();
    let tree = tree.trim();
    let mut out = Vec::new();
    expand_into(&[], tree, &mut out);
    out
}

fn split_top(s: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0usize, 0usize);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts
        .into_iter()
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect()
}

fn expand_into(prefix: &[String], tree: &str, out: &mut Vec<(Vec<String>, String)>) {
    let tree = tree.trim();
    if let Some(i) = tree.find('{') {
        let head = tree[..i].trim_end_matches(':').trim();
        let mut p = prefix.to_vec();
        p.extend(
            head.split("::")
                .filter(|x| !x.is_empty())
                .map(|x| x.trim().to_string()),
        );
        let inner = &tree[i + 1..tree.rfind('}').expect("a closing brace")];
        for part in split_top(inner) {
            expand_into(&p, part, out);
        }
        return;
    }
    let (path, alias) = match tree.split_once(" as ") {
        Some((p, a)) => (p.trim(), a.trim().to_string()),
        None => (tree, String::new()),
    };
    let mut p = prefix.to_vec();
    p.extend(path.split("::").map(|x| x.trim().to_string()));
    if p.last().is_some_and(|l| l == "self") {
        p.pop();
    }
    let alias = if alias.is_empty() {
        p.last().cloned().unwrap_or_default()
    } else {
        alias
    };
    out.push((p, alias));
}

/// The parsed crate: its modules, their sources and the re-exports.
struct Crate {
    /// Module -> stripped source.
    modules: BTreeMap<Module, String>,
    /// (module, name) -> the absolute path it re-exports.
    aliases: BTreeMap<(Module, String), Vec<String>>,
}

impl Crate {
    fn new(files: &[(String, String)]) -> Crate {
        let mut modules = BTreeMap::new();
        let mut test_only: BTreeSet<Module> = BTreeSet::new();
        for (rel, src) in files {
            let rel = rel.trim_end_matches(".rs");
            let mut m: Module = rel.split('/').map(str::to_string).collect();
            if m.last().is_some_and(|l| l == "mod" || l == "lib") {
                m.pop();
            }
            for child in test_files(src) {
                let mut c = m.clone();
                c.push(child);
                test_only.insert(c);
            }
            modules.insert(m, strip(src));
        }
        modules.retain(|m, _| !test_only.iter().any(|t| m.starts_with(t)));
        let mut c = Crate {
            modules,
            aliases: BTreeMap::new(),
        };
        let mut aliases = BTreeMap::new();
        for (m, src) in &c.modules {
            for (tree, public) in use_trees(src) {
                if !public {
                    continue;
                }
                for (p, alias) in expand(&tree) {
                    if p.last().is_some_and(|l| l == "*") {
                        continue;
                    }
                    if let Some(abs) = c.absolute(m, &p) {
                        aliases.insert((m.clone(), alias), abs);
                    }
                }
            }
        }
        c.aliases = aliases;
        c
    }

    /// A path as written in module `m`, made absolute (None: another crate).
    fn absolute(&self, m: &Module, p: &[String]) -> Option<Vec<String>> {
        let first = p.first()?;
        let mut base: Vec<String> = match first.as_str() {
            "crate" => Vec::new(),
            "self" => m.clone(),
            "super" => {
                let mut b = m.clone();
                let mut rest = p;
                while rest.first().is_some_and(|s| s == "super") {
                    b.pop();
                    rest = &rest[1..];
                }
                b.extend(rest.iter().cloned());
                return Some(b);
            }
            _ => {
                let mut child = m.clone();
                child.push(first.clone());
                if self.modules.contains_key(&child) {
                    m.clone()
                } else {
                    return None;
                }
            }
        };
        let skip = usize::from(matches!(first.as_str(), "crate" | "self"));
        base.extend(p[skip..].iter().cloned());
        Some(base)
    }

    /// The deepest module an absolute path names, following re-exports.
    fn resolve(&self, path: &[String], depth: usize) -> Module {
        let mut cur: Module = Vec::new();
        for (i, seg) in path.iter().enumerate() {
            let mut cand = cur.clone();
            cand.push(seg.clone());
            if self.modules.contains_key(&cand) {
                cur = cand;
                continue;
            }
            if let Some(target) = self.aliases.get(&(cur.clone(), seg.clone())) {
                if depth < 8 {
                    let mut full = target.clone();
                    full.extend(path[i + 1..].iter().cloned());
                    return self.resolve(&full, depth + 1);
                }
            }
            break;
        }
        cur
    }

    /// Module -> the modules it imports.
    fn graph(&self) -> BTreeMap<Module, BTreeSet<Module>> {
        let mut g = BTreeMap::new();
        for (m, src) in &self.modules {
            let mut paths: Vec<Vec<String>> = Vec::new();
            for (tree, _) in use_trees(src) {
                paths.extend(expand(&tree).into_iter().map(|(p, _)| p));
            }
            paths.extend(inline_paths(src));
            let mut to = BTreeSet::new();
            for p in paths {
                let Some(abs) = self.absolute(m, &p) else {
                    continue;
                };
                let r = self.resolve(&abs, 0);
                if !r.is_empty() && &r != m {
                    to.insert(r);
                }
            }
            g.insert(m.clone(), to);
        }
        g
    }
}

/// The `use` trees of a source, with whether each is public (`pub use`,
/// `pub(crate) use`).
fn use_trees(src: &str) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    let bytes = src.as_bytes();
    let mut from = 0;
    while let Some(i) = src[from..].find("use ").map(|i| i + from) {
        from = i + 4;
        let word_start = i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if !word_start {
            continue;
        }
        let line_start = src[..i].rfind('\n').map_or(0, |n| n + 1);
        let before = src[line_start..i].trim();
        if !(before.is_empty() || before.starts_with("pub")) {
            continue;
        }
        let Some(end) = src[i..].find(';') else {
            break;
        };
        out.push((src[i + 4..i + end].to_string(), before.starts_with("pub")));
        from = i + end;
    }
    out
}

/// `crate::a::b` and `super::a` paths written inline in the code.
fn inline_paths(src: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for start in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(i) = src[from..].find(start).map(|i| i + from) {
            from = i + start.len();
            let b = src.as_bytes();
            if i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_') {
                continue;
            }
            let tail: String = src[i..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let p: Vec<String> = tail
                .split("::")
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect();
            if p.len() >= 2 {
                out.push(p);
            }
        }
    }
    out
}

fn layer(m: &[String], layers: &[(String, u32)]) -> Option<u32> {
    let n = name(m);
    layers
        .iter()
        .filter(|(p, _)| {
            p.is_empty() && m.is_empty()
                || !p.is_empty() && (n == *p || n.starts_with(&format!("{p}::")))
        })
        .max_by_key(|(p, _)| p.len())
        .map(|&(_, l)| l)
}

/// A circle of the graph, if any, as the modules along it.
fn circle<N: Ord + Clone>(g: &BTreeMap<N, BTreeSet<N>>) -> Option<Vec<N>> {
    // 0 unseen, 1 on the stack, 2 done.
    fn visit<N: Ord + Clone>(
        n: &N,
        g: &BTreeMap<N, BTreeSet<N>>,
        state: &mut BTreeMap<N, u8>,
        stack: &mut Vec<N>,
    ) -> Option<Vec<N>> {
        state.insert(n.clone(), 1);
        stack.push(n.clone());
        for t in g.get(n).into_iter().flatten() {
            match state.get(t).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|x| x == t).expect("on the stack");
                    let mut c = stack[at..].to_vec();
                    c.push(t.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(t, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in g.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            let mut stack = Vec::new();
            if let Some(c) = visit(n, g, &mut state, &mut stack) {
                return Some(c);
            }
        }
    }
    None
}

/// Whether `to` is reachable from `from`.
fn reaches<N: Ord + Clone>(g: &BTreeMap<N, BTreeSet<N>>, from: &N, to: &N) -> bool {
    let mut seen = BTreeSet::new();
    let mut todo = vec![from.clone()];
    while let Some(n) = todo.pop() {
        if &n == to {
            return true;
        }
        if seen.insert(n.clone()) {
            todo.extend(g.get(&n).into_iter().flatten().cloned());
        }
    }
    false
}

/// Every violation of the laws of the module doc, one line each.
fn violations(files: &[(String, String)], layers: Option<&[(String, u32)]>) -> Vec<String> {
    let c = Crate::new(files);
    let g = c.graph();
    let mut bad = Vec::new();
    if let Some(cyc) = circle(&g) {
        let names: Vec<String> = cyc.iter().map(|m| name(m)).collect();
        bad.push(format!("import circle: {}", names.join(" -> ")));
        for (a, to) in &g {
            for b in to {
                if reaches(&g, b, a) {
                    bad.push(format!("  on a circle: {} -> {}", name(a), name(b)));
                }
            }
        }
    }
    let mut top: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (m, to) in &g {
        let Some(a) = m.first() else { continue };
        let e = top.entry(a.clone()).or_default();
        for t in to {
            if let Some(b) = t.first() {
                if b != a {
                    e.insert(b.clone());
                }
            }
        }
    }
    if let Some(cyc) = circle(&top) {
        bad.push(format!(
            "import circle between top-level modules: {}",
            cyc.join(" -> ")
        ));
    }
    if let Some(layers) = layers {
        for (m, to) in &g {
            let Some(lm) = layer(m, layers) else {
                bad.push(format!(
                    "{} is in no layer: add it to the tables of ARCHITECTURE.md",
                    name(m)
                ));
                continue;
            };
            for t in to {
                match layer(t, layers) {
                    Some(lt) if lt > lm => bad.push(format!(
                        "{} (layer {lm}) imports {} of the higher layer {lt}",
                        name(m),
                        name(t)
                    )),
                    _ => {}
                }
            }
        }
    }
    bad
}

// The test reads core's own sources: the one I/O of core, in a test.
#[allow(clippy::disallowed_methods, clippy::disallowed_types)]
fn sources(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("a readable src directory")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            sources(&p, root, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            let rel = p
                .strip_prefix(root)
                .expect("under src")
                .to_string_lossy()
                .replace('\\', "/");
            out.push((rel, std::fs::read_to_string(&p).expect("a readable source")));
        }
    }
}

#[test]
fn core_is_a_one_way_pipeline() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &root, &mut files);
    assert!(files.len() > 30, "read {} files of core/src", files.len());
    let layers = architecture();
    assert!(
        layers.len() > 40,
        "read {} rows of ARCHITECTURE.md",
        layers.len()
    );
    let mut bad = violations(&files, Some(&layers));
    // One copy, kept true: a row naming no module of core/src is stale.
    let c = Crate::new(&files);
    for (row, _) in &layers {
        let m: Module = row
            .split("::")
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect();
        if !c.modules.contains_key(&m) {
            bad.push(format!(
                "ARCHITECTURE.md names `{row}`, no module of core/src"
            ));
        }
    }
    assert!(
        bad.is_empty(),
        "core/src breaks its layers:\n{}",
        bad.join("\n")
    );
}

/// The other crates of the workspace (the server, the wasm facades, the
/// Python package, the test harness) have no layer table, but no import
/// circle either: between their files, nor between their top-level
/// modules (`cli` may use `service`, not both ways). A binary's root is
/// its `main.rs`. Cargo keeps the crates themselves acyclic.
#[test]
fn the_workspace_has_no_import_circle() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("core sits in the workspace");
    let mut seen = 0;
    for krate in ["server", "import", "web", "web-radar", "python", "tests"] {
        let root = workspace.join(krate).join("src");
        let mut files = Vec::new();
        sources(&root, &root, &mut files);
        for (rel, _) in &mut files {
            if rel == "main.rs" {
                *rel = "lib.rs".to_string();
            }
        }
        assert!(!files.is_empty(), "read no file of {krate}/src");
        seen += files.len();
        let bad = violations(&files, None);
        assert!(bad.is_empty(), "{krate}/src:\n{}", bad.join("\n"));
    }
    assert!(seen > 40, "read {seen} files of the other crates");
}

/// The reading sees what it must: the known imports of core are edges.
#[test]
fn the_graph_holds_known_imports() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &root, &mut files);
    let g = Crate::new(&files).graph();
    let m = |s: &str| -> Module { s.split("::").map(str::to_string).collect() };
    for (a, b) in [
        ("slam::propagate::rounds", "slam::association::step"),
        ("slam::propagate::passes", "contractors::motion_chain"),
        ("slam::solve", "slam::diagnose"),
        ("slam::propagate::fixpoint", "slam::robust"),
        ("slam::robust::subsets", "slam::propagate::rounds"),
        (
            "slam::association::step",
            "slam::association::odometry2d::separation",
        ),
        ("shapes::shape", "contractors::distance"),
        ("slam::association::state", "shapes::frames"),
        ("slam::association", "slam::association::round"),
        ("json", "interval"),
    ] {
        assert!(
            g.get(&m(a)).is_some_and(|to| to.contains(&m(b))),
            "{a} -> {b} not seen: {:?}",
            g.get(&m(a))
        );
    }
}

fn file(path: &str, src: &str) -> (String, String) {
    (path.to_string(), src.to_string())
}

#[test]
fn a_circle_through_use_super_and_a_re_export_is_found() {
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\npub use a::Thing;\n"),
        file("a/mod.rs", "pub mod x;\npub use x::Thing;\n"),
        file(
            "a/x.rs",
            "use crate::b::{self, y::{Other as O}};\npub struct Thing;\n",
        ),
        file("b/mod.rs", "pub mod y;\n"),
        file(
            "b/y.rs",
            "pub struct Other;\nfn f() -> crate::Thing { todo!() }\n",
        ),
    ];
    let bad = violations(&files, None);
    assert!(
        bad.iter()
            .any(|l| l.contains("import circle: ") && l.contains("a::x") && l.contains("b::y")),
        "{bad:?}"
    );
    assert!(bad.iter().any(|l| l.contains("top-level")), "{bad:?}");
}

#[test]
fn comments_and_test_modules_are_not_imports() {
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "//! see [`crate::b::f`]\nuse crate::b::f;\n"),
        file(
            "b.rs",
            "pub fn f() {}\n// crate::a::g\n#[cfg(test)]\npub(crate) mod tests {\n    use crate::a::*;\n    fn t() { crate::a::g(); }\n}\n",
        ),
    ];
    assert!(violations(&files, None).is_empty());
    // A test module under a compound cfg is a test module too; a
    // `not(test)` one is code.
    let unix =
        "pub fn f() {}\n#[cfg(all(test, unix))]\nmod tests {\n    use super::super::a::*;\n}\n";
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use crate::b::f;\npub fn g() {}\n"),
        file("b.rs", unix),
    ];
    assert!(violations(&files, None).is_empty());
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use crate::b::f;\npub fn g() {}\n"),
        file("b.rs", &unix.replace("all(test, unix)", "not(test)")),
    ];
    assert!(!violations(&files, None).is_empty());
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use super::b::f;\npub fn g() {}\n"),
        file("b.rs", "pub fn f() { super::a::g() }\n"),
    ];
    let bad = violations(&files, None);
    assert!(
        bad.iter()
            .any(|l| l.starts_with("import circle: a -> b -> a")),
        "{bad:?}"
    );
}

/// A small crate and its tables: `low` (layer 0) and `high` (layer 1).
fn two_layers() -> Vec<(String, u32)> {
    table("### core layer 0: low\n| module | what |\n|---|---|\n| `low` | x. |\n\n### core layer 1: high\n| module | what |\n|---|---|\n| `high` | y. |\n| `crate` | root. |\n").expect("a table")
}

#[test]
fn an_import_of_a_higher_layer_is_found() {
    let layers = two_layers();
    assert_eq!(
        layers,
        [("low".into(), 0), ("high".into(), 1), (String::new(), 1)]
    );
    let files = [
        file("lib.rs", "pub mod low;\npub mod high;\n"),
        file("low.rs", "pub fn f() {}\n"),
        file("high.rs", "use crate::low::f;\npub fn g() { f() }\n"),
    ];
    assert!(violations(&files, Some(&layers)).is_empty());
    let files = [
        file("lib.rs", "pub mod low;\npub mod high;\n"),
        file("low.rs", "pub fn f() { crate::high::g() }\n"),
        file("high.rs", "pub fn g() {}\n"),
    ];
    let bad = violations(&files, Some(&layers));
    assert!(
        bad.iter()
            .any(|l| l == "low (layer 0) imports high of the higher layer 1"),
        "{bad:?}"
    );
}

#[test]
fn a_module_missing_from_the_tables_is_found() {
    let layers = two_layers();
    let files = [
        file("lib.rs", "pub mod low;\npub mod other;\n"),
        file("low.rs", "pub fn f() {}\n"),
        file("other.rs", "pub fn g() {}\n"),
    ];
    let bad = violations(&files, Some(&layers));
    assert!(
        bad.iter().any(|l| l.starts_with("other is in no layer")),
        "{bad:?}"
    );
    // A child takes its parent's row; a test-only file is no module.
    let files = [
        file("lib.rs", "pub mod low;\n"),
        file("low/mod.rs", "pub mod inner;\n#[cfg(test)]\nmod tests;\n"),
        file("low/inner.rs", "pub fn f() {}\n"),
        file("low/tests.rs", "use crate::high::g;\n"),
    ];
    assert!(violations(&files, Some(&layers)).is_empty());
}

#[test]
fn the_tables_are_read_strictly() {
    assert!(
        table("# Architecture\n| `a` | x |\n").is_err(),
        "no core layer"
    );
    assert!(table("### core layer x: bad\n| `a` | x |\n").is_err());
    let twice = "### core layer 0: a\n| `a` | x |\n### core layer 1: b\n| `a` | y |\n";
    assert!(table(twice).unwrap_err().contains("twice"));
    // Rows of other tables (the server's, the concepts') are not read.
    let md = "### core layer 2: a\n| `a` | x |\n\n## Server\n| `b` | y |\n";
    assert_eq!(table(md).unwrap(), [("a".to_string(), 2)]);
}
