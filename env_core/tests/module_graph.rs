//! The core's modules form no circle, and its layers import only along the arrows of
//! `docs/DESIGN.md` §1.1: `planner/ ─► episode/, scene/, settings/`,
//! `episode/ ─► gpis/, scene/, settings/`, `scene/ ─► settings/`,
//! `gpis/` and `settings/` import nothing of ours. The Rust side of
//! `tests/test_import_graph.py`.
//!
//! The graph is read from the source text, not from the compiler: every `use` (also inside
//! functions and test modules) and every path that starts with `crate::`, `super::`,
//! `self::` or a child module's name, with comments and string literals left out. A path
//! to an item a module re-exports (`crate::gpis::GridSpec`) leads to the module that
//! defines it (`gpis::grid`), so a facade's `pub use` lines make no circle of their own; a
//! macro exported at the root (`crate::choice!`) leads to the module that defines it.
//!
//! A node is a file directly under a layer's folder (`episode::probe`) or a folder of its
//! own (`episode::maps`, `gpis::map`, with everything below them): a folder's files are one
//! concept's parts, and a child may use its parent's private items. Each layer's `mod.rs`
//! and `lib.rs` (`crate`) are nodes too.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path from the crate root (`["episode", "probe"]`; the root is `[]`).
type ModulePath = Vec<String>;

/// Edges between nodes, each with where it was first seen (file and line).
type Graph = BTreeMap<String, BTreeMap<String, String>>;

/// Which layers each layer may import (`docs/DESIGN.md` §1.1). `crate` (`lib.rs`) and
/// `bindings` sit above the core and may import any layer. `allocator` is the global
/// allocator: `lib.rs` installs it and the bindings read its counters; nothing in the core
/// imports it (every allocation reaches it through `std`), and it imports nothing of ours.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "crate",
        &[
            "allocator",
            "bindings",
            "episode",
            "gpis",
            "planner",
            "scene",
            "settings",
        ],
    ),
    (
        "bindings",
        &[
            "allocator",
            "episode",
            "gpis",
            "planner",
            "scene",
            "settings",
        ],
    ),
    ("planner", &["episode", "scene", "settings"]),
    ("episode", &["gpis", "scene", "settings"]),
    ("scene", &["settings"]),
    ("gpis", &[]),
    ("settings", &[]),
    ("allocator", &[]),
];

/// Every `.rs` file under `src`, with its module path.
fn source_files(src: &Path) -> Vec<(ModulePath, PathBuf)> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .expect("src is readable")
            .map(|entry| entry.expect("src is readable").path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, found);
            } else if path.extension().is_some_and(|e| e == "rs") {
                found.push(path);
            }
        }
    }
    let mut paths = Vec::new();
    walk(src, &mut paths);
    paths
        .into_iter()
        .map(|path| {
            let relative = path
                .strip_prefix(src)
                .expect("under src")
                .with_extension("");
            let mut module: ModulePath = relative
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if matches!(module.last().map(String::as_str), Some("mod" | "lib")) {
                module.pop();
            }
            (module, path)
        })
        .collect()
}

/// `text` with comments, string literals and char literals blanked (newlines kept, so
/// offsets keep their line numbers).
fn strip_comments_and_literals(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(chars[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && matches!(next, Some('"' | '#')) && (i == 0 || !is_ident(chars[i - 1]))
        {
            // A raw string r"…" or r#"…"# (or a raw identifier r#name, kept as it is).
            let mut j = i + 1;
            while chars.get(j) == Some(&'#') {
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            let hashes = j - i - 1;
            i = j + 1;
            while i < chars.len() {
                if chars[i] == '"' && (1..=hashes).all(|h| chars.get(i + h) == Some(&'#')) {
                    i += 1 + hashes;
                    break;
                }
                out.push(blank(chars[i]));
                i += 1;
            }
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    i += 1;
                }
                if let Some(&c) = chars.get(i) {
                    out.push(blank(c));
                }
                i += 1;
            }
            i += 1;
        } else if c == '\'' && next == Some('\\') {
            // An escaped char literal, '\n' or '\u{..}'.
            i += 2;
            while i < chars.len() && chars[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else if c == '\'' && chars.get(i + 2) == Some(&'\'') {
            i += 3;
        } else {
            // Code, a lifetime's quote included.
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The tokens that matter for paths: identifiers (`$crate` and macro variables included),
/// `::`, braces, `,`, `;`, `*`, `(`, `)`; everything else is one token per character. Each
/// with its line.
fn tokens(code: &str) -> Vec<(String, usize)> {
    let chars: Vec<char> = code.chars().collect();
    let mut found = Vec::new();
    let mut line = 1;
    let mut i = 0;
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if is_ident(c) || (c == '$' && chars.get(i + 1).is_some_and(|&n| is_ident(n))) {
            let start = i;
            i += 1;
            while i < chars.len() && is_ident(chars[i]) {
                i += 1;
            }
            found.push((chars[start..i].iter().collect(), line));
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            found.push(("::".to_string(), line));
            i += 2;
        } else {
            found.push((c.to_string(), line));
            i += 1;
        }
    }
    found
}

/// One path a `use` names: its segments, and the name it binds (`None` for a glob).
#[derive(Debug, Clone, PartialEq)]
struct UsePath {
    path: Vec<String>,
    name: Option<String>,
}

/// Parses the use tree starting at `tokens[i]` under `prefix`; returns the index after it.
fn use_tree(
    tokens: &[(String, usize)],
    mut i: usize,
    prefix: &[String],
    out: &mut Vec<UsePath>,
) -> usize {
    let token = |i: usize| tokens.get(i).map_or("", |(t, _)| t.as_str());
    if token(i) == "::" {
        i += 1;
    }
    match token(i) {
        "{" => {
            i += 1;
            while !matches!(token(i), "}" | "") {
                i = use_tree(tokens, i, prefix, out);
                if token(i) == "," {
                    i += 1;
                }
            }
            i + 1
        }
        "*" => {
            out.push(UsePath {
                path: prefix.to_vec(),
                name: None,
            });
            i + 1
        }
        segment => {
            let (path, mut name) = if segment == "self" && !prefix.is_empty() {
                (prefix.to_vec(), prefix.last().cloned())
            } else {
                let mut path = prefix.to_vec();
                path.push(segment.to_string());
                (path, Some(segment.to_string()))
            };
            i += 1;
            if token(i) == "::" {
                return use_tree(tokens, i + 1, &path, out);
            }
            if token(i) == "as" {
                name = Some(token(i + 1).to_string());
                i += 2;
            }
            out.push(UsePath { path, name });
            i
        }
    }
}

/// What one module's text refers to.
#[derive(Debug, Default)]
struct References {
    /// Every path used, from the module (inline modules included) it was used in, with its
    /// line.
    paths: Vec<(ModulePath, Vec<String>, usize)>,
    /// Names re-exported by a `pub` (any visibility) `use`, per module: name -> path.
    reexports: Vec<(ModulePath, String, Vec<String>)>,
    /// Inline modules (`mod tests { … }`).
    inline_modules: Vec<ModulePath>,
    /// Macros exported at the crate's root (`#[macro_export]`), with the module that
    /// defines them.
    exported_macros: Vec<(String, ModulePath)>,
}

/// The paths, re-exports and inline modules of the file of module `module`.
fn references(module: &ModulePath, code: &str) -> References {
    let tokens = tokens(code);
    let token = |i: usize| tokens.get(i).map_or("", |(t, _)| t.as_str());
    let mut found = References::default();
    // Inline modules open at a brace depth.
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let current = |inline: &[(String, usize)]| {
        let mut path = module.clone();
        path.extend(inline.iter().map(|(name, _)| name.clone()));
        path
    };
    let mut i = 0;
    while i < tokens.len() {
        let line = tokens[i].1;
        match token(i) {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if inline.last().is_some_and(|&(_, d)| d == depth) {
                    inline.pop();
                }
            }
            "macro_rules" if token(i + 1) == "!" => {
                // Exported when `#[macro_export]` is among its attributes, which run back to
                // the end of the item before it.
                let exported = (0..i)
                    .rev()
                    .map(&token)
                    .take_while(|t| !matches!(*t, "}" | ";"))
                    .any(|t| t == "macro_export");
                if exported {
                    found
                        .exported_macros
                        .push((token(i + 2).to_string(), current(&inline)));
                }
            }
            "mod" if token(i + 2) == "{" => {
                inline.push((token(i + 1).to_string(), depth));
                found.inline_modules.push(current(&inline));
                // The name and the brace are read on the next turns.
                i += 2;
                continue;
            }
            "use" => {
                let public = token(i.wrapping_sub(1)) == "pub"
                    || (token(i.wrapping_sub(1)) == ")"
                        && (2..6).any(|back| {
                            token(i.wrapping_sub(back)) == "pub"
                                && token(i.wrapping_sub(back - 1)) == "("
                        }));
                let mut paths = Vec::new();
                let end = use_tree(&tokens, i + 1, &[], &mut paths);
                let here = current(&inline);
                for UsePath { path, name } in paths {
                    if public {
                        if let Some(name) = &name {
                            found
                                .reexports
                                .push((here.clone(), name.clone(), path.clone()));
                        }
                    }
                    found.paths.push((here.clone(), path, line));
                }
                i = end;
                continue;
            }
            first if token(i + 1) == "::" && token(i.wrapping_sub(1)) != "::" => {
                let mut path = vec![first.to_string()];
                let mut j = i + 1;
                while token(j) == "::"
                    && tokens.get(j + 1).is_some_and(|(t, _)| {
                        t.chars()
                            .next()
                            .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$')
                    })
                {
                    path.push(token(j + 1).to_string());
                    j += 2;
                }
                found.paths.push((current(&inline), path, line));
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    found
}

/// The crate's modules and what they refer to, and the graph between nodes.
struct Crate {
    /// Modules that are files.
    files: BTreeSet<ModulePath>,
    /// Every module, inline ones included.
    modules: BTreeSet<ModulePath>,
    /// Re-exports: module -> name -> path (relative to that module).
    reexports: BTreeMap<ModulePath, BTreeMap<String, Vec<String>>>,
    /// Macros exported at the root (`crate::name!`) -> the module that defines them.
    exported_macros: BTreeMap<String, ModulePath>,
}

impl Crate {
    /// The module `segments` names from module `from`, through re-exports to the module
    /// that defines the item; `None` for a path outside the crate (or a local item).
    fn resolve(&self, from: &[String], segments: &[String], hops: usize) -> Option<ModulePath> {
        let (first, rest) = segments.split_first()?;
        let mut absolute: ModulePath = match first.as_str() {
            "crate" | "$crate" => Vec::new(),
            "self" => from.to_vec(),
            "super" => from[..from.len().checked_sub(1)?].to_vec(),
            name => {
                let mut child = from.to_vec();
                child.push(name.to_string());
                if !self.modules.contains(&child) {
                    return None;
                }
                from.to_vec()
            }
        };
        let mut rest = if matches!(first.as_str(), "crate" | "$crate" | "self" | "super") {
            rest
        } else {
            segments
        };
        while rest.first().is_some_and(|s| s == "super") {
            absolute.pop()?;
            rest = &rest[1..];
        }
        let mut module = absolute;
        let mut used = 0;
        for segment in rest {
            module.push(segment.clone());
            if !self.modules.contains(&module) {
                module.pop();
                break;
            }
            used += 1;
        }
        if let Some(item) = rest.get(used) {
            if module.is_empty() {
                if let Some(defined_in) = self.exported_macros.get(item) {
                    return Some(defined_in.clone());
                }
            }
            let target = self
                .reexports
                .get(&module)
                .and_then(|names| names.get(item));
            if let (Some(target), true) = (target, hops < 16) {
                return self.resolve(&module.clone(), target, hops + 1);
            }
        }
        Some(module)
    }

    /// The node a module belongs to: its file's module, cut to a layer's folder and one
    /// level below it.
    fn node(&self, module: &[String]) -> String {
        let mut file = module.to_vec();
        while !self.files.contains(&file) && !file.is_empty() {
            file.pop();
        }
        file.truncate(2);
        if file.is_empty() {
            "crate".to_string()
        } else {
            file.join("::")
        }
    }
}

/// The graph between nodes of the crate whose files are `sources` (module path, name to
/// show, text).
fn module_graph(sources: &[(ModulePath, String, String)]) -> Graph {
    let read: Vec<_> = sources
        .iter()
        .map(|(module, shown, text)| {
            (
                module,
                shown,
                references(module, &strip_comments_and_literals(text)),
            )
        })
        .collect();
    let files: BTreeSet<ModulePath> = sources.iter().map(|(m, _, _)| m.clone()).collect();
    let mut modules = files.clone();
    let mut reexports: BTreeMap<ModulePath, BTreeMap<String, Vec<String>>> = BTreeMap::new();
    let mut exported_macros = BTreeMap::new();
    for (_, _, found) in &read {
        modules.extend(found.inline_modules.iter().cloned());
        exported_macros.extend(found.exported_macros.iter().cloned());
        for (module, name, path) in &found.reexports {
            reexports
                .entry(module.clone())
                .or_default()
                .insert(name.clone(), path.clone());
        }
    }
    let krate = Crate {
        files,
        modules,
        reexports,
        exported_macros,
    };
    let mut graph = Graph::new();
    for (module, shown, found) in &read {
        let from = krate.node(module);
        graph.entry(from.clone()).or_default();
        for (inside, path, line) in &found.paths {
            let Some(target) = krate.resolve(inside, path, 0) else {
                continue;
            };
            let to = krate.node(&target);
            if to != from {
                graph
                    .entry(from.clone())
                    .or_default()
                    .entry(to)
                    .or_insert_with(|| format!("{shown}:{line}: {}", path.join("::")));
            }
        }
    }
    graph
}

/// The graph of `env_core/src`.
fn crate_graph() -> Graph {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let sources: Vec<_> = source_files(&src)
        .into_iter()
        .map(|(module, path)| {
            let shown = path
                .strip_prefix(env!("CARGO_MANIFEST_DIR"))
                .expect("under the crate")
                .display()
                .to_string();
            let text = std::fs::read_to_string(&path).expect("a source file is readable");
            (module, shown, text)
        })
        .collect();
    module_graph(&sources)
}

/// The strongly connected components of more than one node (Tarjan's algorithm), each
/// sorted.
fn circles(graph: &Graph) -> Vec<Vec<String>> {
    struct Search<'a> {
        graph: &'a Graph,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<Vec<String>>,
    }
    impl<'a> Search<'a> {
        fn visit(&mut self, node: &'a str) {
            let number = self.index.len();
            self.index.insert(node, number);
            self.low.insert(node, number);
            self.stack.push(node);
            self.on_stack.insert(node);
            let graph = self.graph;
            for successor in graph.get(node).into_iter().flat_map(|edges| edges.keys()) {
                let successor = successor.as_str();
                if !self.index.contains_key(successor) {
                    self.visit(successor);
                    let low = self.low[node].min(self.low[successor]);
                    self.low.insert(node, low);
                } else if self.on_stack.contains(successor) {
                    let low = self.low[node].min(self.index[successor]);
                    self.low.insert(node, low);
                }
            }
            if self.low[node] == self.index[node] {
                let mut component = Vec::new();
                loop {
                    let member = self.stack.pop().expect("the node is on the stack");
                    self.on_stack.remove(member);
                    component.push(member.to_string());
                    if member == node {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    self.found.push(component);
                }
            }
        }
    }
    let mut search = Search {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for node in graph.keys() {
        if !search.index.contains_key(node.as_str()) {
            search.visit(node);
        }
    }
    search.found
}

/// One circle through the first node of `component`, each arrow with where it was seen.
fn describe_circle(graph: &Graph, component: &[String]) -> String {
    let inside: BTreeSet<&str> = component.iter().map(String::as_str).collect();
    let start = component[0].as_str();
    // Breadth first from the start back to itself, inside the component.
    let mut came_from: BTreeMap<&str, &str> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    'search: while let Some(node) = queue.pop_front() {
        for next in graph[node].keys().map(String::as_str) {
            if !inside.contains(next) || came_from.contains_key(next) {
                continue;
            }
            came_from.insert(next, node);
            if next == start {
                break 'search;
            }
            queue.push_back(next);
        }
    }
    let mut path = vec![start];
    let mut node = came_from[start];
    while node != start {
        path.push(node);
        node = came_from[node];
    }
    path.push(start);
    path.reverse();
    path.windows(2)
        .map(|w| format!("  {} -> {}   ({})", w[0], w[1], graph[w[0]][w[1]]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The arrows that go against `LAYERS`, described.
fn layer_breaches(graph: &Graph) -> Vec<String> {
    let layer = |node: &str| node.split("::").next().unwrap_or(node).to_string();
    let mut breaches = Vec::new();
    for (from, edges) in graph {
        let Some((_, allowed)) = LAYERS.iter().find(|(name, _)| *name == layer(from)) else {
            breaches.push(format!(
                "{from}: a layer docs/DESIGN.md §1.1 and LAYERS here do not know"
            ));
            continue;
        };
        for (to, seen) in edges {
            let target = layer(to);
            if target != layer(from) && !allowed.contains(&target.as_str()) {
                breaches.push(format!("{from} -> {to}   ({seen})"));
            }
        }
    }
    breaches
}

/// A synthetic crate from `(file path under src, text)` pairs.
fn synthetic(files: &[(&str, &str)]) -> Graph {
    let sources: Vec<_> = files
        .iter()
        .map(|(path, text)| {
            let mut module: ModulePath = path
                .trim_end_matches(".rs")
                .split('/')
                .map(str::to_string)
                .collect();
            if matches!(module.last().map(String::as_str), Some("mod" | "lib")) {
                module.pop();
            }
            (module, path.to_string(), text.to_string())
        })
        .collect();
    module_graph(&sources)
}

#[test]
fn the_circle_finder_finds_a_circle_through_three_nodes() {
    let graph: Graph = [
        ("a", &["b"][..]),
        ("b", &["c"]),
        ("c", &["a"]),
        ("d", &["a"]),
    ]
    .into_iter()
    .map(|(node, to)| {
        let edges = to.iter().map(|t| (t.to_string(), String::new())).collect();
        (node.to_string(), edges)
    })
    .collect();
    assert_eq!(circles(&graph), [["a", "b", "c"]]);
    let text = describe_circle(&graph, &circles(&graph)[0]);
    assert!(text.contains("a -> b") && text.contains("c -> a"), "{text}");
}

#[test]
fn a_circle_through_a_facades_reexport_is_found() {
    let files = [
        ("lib.rs", "pub mod layer;"),
        (
            "layer/mod.rs",
            "mod one;\nmod two;\npub use one::One;\npub use two::{Two, self as again};",
        ),
        ("layer/one.rs", "use super::two::Two;\npub struct One(Two);"),
        (
            "layer/two.rs",
            "// crate::layer::one::One in a comment is no arrow\n\
             pub struct Two;\nfn f() -> Option<crate::layer::One> { None }",
        ),
    ];
    let graph = synthetic(&files);
    assert_eq!(circles(&graph), [["layer::one", "layer::two"]]);
    // The facade's re-exports are arrows from it, never to it.
    assert!(graph["layer"].contains_key("layer::one"));
    assert!(!graph["layer::two"].contains_key("layer"));

    // Without the path in `two`'s code, and with only a comment and a string naming
    // `one`, there is no circle.
    let mut files = files;
    files[3].1 =
        "// use crate::layer::one;\npub struct Two;\nconst S: &str = \"crate::layer::one\";";
    assert!(circles(&synthetic(&files)).is_empty());
}

#[test]
fn inline_test_modules_and_child_folders_belong_to_their_node() {
    let graph = synthetic(&[
        ("lib.rs", "pub mod layer;"),
        (
            "layer/mod.rs",
            "pub mod map;\npub mod user;\npub use map::Map;",
        ),
        (
            "layer/map/mod.rs",
            "mod part;\npub struct Map;\nuse part::helper;",
        ),
        (
            "layer/map/part.rs",
            "use super::Map;\npub(super) fn helper(_: &Map) {}",
        ),
        (
            "layer/user.rs",
            "use crate::layer::Map;\n#[cfg(test)]\nmod tests {\n    use super::*;\n}",
        ),
    ]);
    assert!(circles(&graph).is_empty(), "{graph:?}");
    assert!(graph["layer::user"].contains_key("layer::map"));
    assert!(!graph.contains_key("layer::map::part"));
}

#[test]
fn an_exported_macro_leads_to_the_module_that_defines_it() {
    let graph = synthetic(&[
        ("lib.rs", "pub mod layer;"),
        ("layer/mod.rs", "mod one;\nmod two;"),
        (
            "layer/one.rs",
            "/// Doc.\n#[macro_export]\nmacro_rules! made { () => { $crate::__helper!() }; }\n\
             #[doc(hidden)]\n#[macro_export]\nmacro_rules! __helper { () => {}; }",
        ),
        ("layer/two.rs", "crate::made!();"),
    ]);
    assert!(graph["layer::two"].contains_key("layer::one"), "{graph:?}");
    assert!(graph["layer::one"].is_empty(), "{graph:?}");
    assert!(!graph["layer::two"].contains_key("crate"), "{graph:?}");
}

#[test]
fn an_arrow_against_the_layers_is_reported() {
    let graph = synthetic(&[
        ("lib.rs", "pub mod gpis;\npub mod scene;"),
        ("gpis/mod.rs", "mod grid;"),
        ("gpis/grid.rs", "use crate::scene::Jar;"),
        ("scene/mod.rs", "pub struct Jar;"),
    ]);
    let breaches = layer_breaches(&graph);
    assert_eq!(breaches.len(), 1, "{breaches:?}");
    assert!(
        breaches[0].starts_with("gpis::grid -> scene"),
        "{breaches:?}"
    );
}

#[test]
fn no_module_circle_inside_env_core_src() {
    let graph = crate_graph();
    // The reading sees the crate: known arrows, one of them through a facade's re-export.
    assert!(graph.len() > 40, "{} nodes", graph.len());
    assert!(graph["episode::config"].contains_key("scene::config"));
    assert!(graph["episode::maps"].contains_key("gpis::map"));
    let found = circles(&graph);
    let described: Vec<String> = found.iter().map(|c| describe_circle(&graph, c)).collect();
    assert!(
        found.is_empty(),
        "module circles inside env_core/src:\n{}",
        described.join("\n\n")
    );
}

#[test]
fn the_core_layers_import_only_along_the_design_arrows() {
    let breaches = layer_breaches(&crate_graph());
    assert!(
        breaches.is_empty(),
        "arrows against docs/DESIGN.md §1.1:\n{}",
        breaches.join("\n")
    );
}
