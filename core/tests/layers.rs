//! The module graph of core/src, read from the sources: every `use`
//! (with its brace trees, `self`, `super`, `crate` and the re-exports of
//! the `mod.rs` files followed to what they name) and every inline
//! `crate::…`/`super::…` path outside comments and `mod tests` is an
//! import of one module (file) by another. The test fails on
//! - an import circle between modules (files), or between the top-level
//!   modules (`slam`, `shapes`, `nvector`, ...);
//! - a module importing a module of a higher layer (the table [`LAYERS`]);
//! - a module of core/src missing from the table.
//!
//! The layers are the pipeline of ARCHITECTURE.md: each may import only
//! its own layer (without circles) and the layers below.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// (module, layer, what it is): a module takes the layer of the longest
/// entry that is a prefix of its path; lower layers come first.
const LAYERS: &[(&str, u32, &str)] = &[
    ("error", 0, "the input error type"),
    ("interval", 0, "sound interval arithmetic"),
    ("radix", 0, "radix sorts"),
    ("rng", 0, "the one splitmix64 generator"),
    ("sort", 0, "the one comparison sort (wasm size)"),
    ("union_find", 0, "the union-find of proved equalities"),
    ("test_rng", 0, "the tests' generator"),
    ("ibox", 1, "interval boxes"),
    ("json", 2, "JSON reading helpers of the formats"),
    (
        "format",
        2,
        "the JSON formats as serde types (paths in errors)",
    ),
    // `figure` and `odometry` are on main (merged while this table was
    // written): their places from their imports there.
    ("figure", 2, "the description of a result's picture"),
    (
        "contractors",
        3,
        "the basic contractors: distance, bearing, motion chain",
    ),
    ("nvector", 3, "the atmost_nvector contractors"),
    ("nvector::contract", 4, "the `contract` job on JSON"),
    (
        "shapes",
        4,
        "pure geometry of detection shapes (no mission)",
    ),
    (
        "odometry",
        4,
        "the odometry2d pieces (angle, chain, sensor, sector)",
    ),
    (
        "odometry::drift",
        4,
        "the heading drift bound over windows of k steps",
    ),
    (
        "odometry::motion_drift",
        4,
        "the position drift bound over windows of k steps",
    ),
    (
        "odometry::pair_heading",
        4,
        "the heading from two detections of one step",
    ),
    (
        "odometry::relative",
        4,
        "relative poses from the odometry alone",
    ),
    (
        "odometry::scan_pose",
        4,
        "a step's detections, position and heading over heading pieces",
    ),
    ("outline", 5, "outlines of shapes and regions for drawing"),
    ("slam::mission", 5, "the typed, validated mission"),
    ("tdoa::problem", 5, "the typed, validated TDOA problem"),
    ("tdoa::arrival", 5, "the arrival constraint (TDOA)"),
    ("tdoa::cuts", 5, "altitude and region cuts (TDOA)"),
    ("slam::model", 6, "the domains"),
    (
        "slam::codec",
        6,
        "the validated mission as a binary stream (the page's solver)",
    ),
    ("slam::simulate", 6, "mission writer (beside the pipeline)"),
    (
        "slam::simulate_schema",
        6,
        "the simulation request's OpenAPI schema",
    ),
    ("slam::woods", 6, "the woods scenario writer (odometry2d)"),
    (
        "slam::check",
        6,
        "the constraints a mission's truth breaks (nvector check)",
    ),
    (
        "slam::plant",
        6,
        "false ranges planted in a mission with truth",
    ),
    ("tdoa::pulse", 6, "the per-pulse fixpoint and paving"),
    ("slam::types", 7, "shared options, progress, solution"),
    (
        "slam::robust_regions",
        7,
        "landmark regions under max_outliers",
    ),
    (
        "slam::robust_heading",
        7,
        "odometry2d headings under max_outliers",
    ),
    ("tdoa::readings", 7, "max_outliers over arrivals"),
    (
        "tdoa::shell",
        7,
        "a pulse's hyperbolic shells as a detection shape",
    ),
    ("tdoa::simulate", 7, "the radar scenario writer"),
    (
        "slam::association",
        8,
        "the shapes part of the association step",
    ),
    (
        "slam::association::tracks",
        8,
        "tracks from the relative evidence",
    ),
    (
        "slam::association::sequential",
        8,
        "the minimum separation inside the passes",
    ),
    (
        "slam::association::scan_map",
        8,
        "scan registration against the closed-world map",
    ),
    (
        "slam::association::scan_pose",
        8,
        "the scan pose in the passes",
    ),
    ("tdoa::shell_step", 8, "the shapes step of the TDOA rounds"),
    ("tdoa::solve", 8, "the TDOA rounds with atmost_nvector"),
    ("slam::rounds", 9, "the physics-guided rounds"),
    ("tdoa::result", 9, "the TDOA result format and score"),
    ("slam::kept", 10, "what the robust propagation keeps"),
    (
        "slam::robust_cliques",
        10,
        "conflicts from pairwise distinct detections",
    ),
    (
        "slam::robust_hitting",
        10,
        "minimum hitting sets of conflicts",
    ),
    (
        "slam::robust_tracks",
        10,
        "track groups that survive false detections",
    ),
    ("slam::outliers", 11, "the robust propagation"),
    (
        "slam::robust_conflicts",
        11,
        "conflict packing under max_outliers",
    ),
    (
        "slam::robust_subsets",
        11,
        "consensus over subsets under max_outliers",
    ),
    ("slam::fixpoint", 12, "which propagation runs"),
    (
        "slam::diagnose",
        13,
        "the diagnosis of an infeasible mission",
    ),
    ("slam::result", 14, "the result format and the score"),
    ("slam::solve", 15, "the entry points"),
    ("slam", 17, "the facade of slam (re-exports)"),
    ("tdoa", 17, "the facade of tdoa (re-exports)"),
    ("", 18, "the crate root (re-exports)"),
];

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
        for (rel, src) in files {
            let rel = rel.trim_end_matches(".rs");
            let mut m: Module = rel.split('/').map(str::to_string).collect();
            if m.last().is_some_and(|l| l == "mod" || l == "lib") {
                m.pop();
            }
            modules.insert(m, strip(src));
        }
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

fn layer(m: &[String]) -> Option<u32> {
    let n = name(m);
    LAYERS
        .iter()
        .filter(|(p, _, _)| {
            p.is_empty() && m.is_empty()
                || !p.is_empty() && (n == *p || n.starts_with(&format!("{p}::")))
        })
        .max_by_key(|(p, _, _)| p.len())
        .map(|&(_, l, _)| l)
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
fn violations(files: &[(String, String)], check_layers: bool) -> Vec<String> {
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
    if check_layers {
        for (m, to) in &g {
            let Some(lm) = layer(m) else {
                bad.push(format!("{} is in no layer: add it to LAYERS", name(m)));
                continue;
            };
            for t in to {
                match layer(t) {
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
    let bad = violations(&files, true);
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
    for krate in ["server", "web", "web-radar", "python", "tests"] {
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
        let bad = violations(&files, false);
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
        ("slam::rounds", "slam::association"),
        ("slam::rounds", "contractors::motion_chain"),
        ("slam::solve", "slam::diagnose"),
        ("slam::fixpoint", "slam::outliers"),
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
    let bad = violations(&files, false);
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
    assert!(violations(&files, false).is_empty());
    // A test module under a compound cfg is a test module too; a
    // `not(test)` one is code.
    let unix =
        "pub fn f() {}\n#[cfg(all(test, unix))]\nmod tests {\n    use super::super::a::*;\n}\n";
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use crate::b::f;\npub fn g() {}\n"),
        file("b.rs", unix),
    ];
    assert!(violations(&files, false).is_empty());
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use crate::b::f;\npub fn g() {}\n"),
        file("b.rs", &unix.replace("all(test, unix)", "not(test)")),
    ];
    assert!(!violations(&files, false).is_empty());
    let files = [
        file("lib.rs", "pub mod a;\npub mod b;\n"),
        file("a.rs", "use super::b::f;\npub fn g() {}\n"),
        file("b.rs", "pub fn f() { super::a::g() }\n"),
    ];
    let bad = violations(&files, false);
    assert!(
        bad.iter()
            .any(|l| l.starts_with("import circle: a -> b -> a")),
        "{bad:?}"
    );
}
