//! The core's layers: each top-level module of `src/` uses only the modules
//! listed before it (the order of `src/lib.rs`'s module doc), so a scan can
//! be followed from the sensor to the pixel and no two modules import each
//! other. Read from the source text: every `crate::NAME` path (and
//! `super::NAME` one level down) outside comments.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Lowest first; `bindings` may use everything.
const LAYERS: [&str; 15] = [
    "error", "geometry", "world", "sensors", "scenes", "grid", "inverse", "mapping", "slam",
    "poses", "render", "io", "apps", "bench", "bindings",
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a file of `src/` belongs to.
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_str()?;
    let name = first.strip_suffix(".rs").unwrap_or(first);
    (name != "lib").then(|| name.to_string())
}

/// The top-level modules a file's code names as `crate::NAME`.
fn uses(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let after = &rest[at + "crate::".len()..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                found.insert(name);
            }
            rest = after;
        }
    }
    found
}

fn edges() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let Some(module) = module_of(&src, &file) else {
            continue;
        };
        let text = fs::read_to_string(&file).unwrap();
        let used = uses(&text)
            .into_iter()
            .filter(|m| *m != module && LAYERS.contains(&m.as_str()))
            .collect::<BTreeSet<_>>();
        edges.entry(module).or_default().extend(used);
    }
    edges
}

#[test]
fn every_top_level_module_is_a_listed_layer() {
    for module in edges().keys() {
        assert!(
            LAYERS.contains(&module.as_str()),
            "src/{module} is not in the layer list"
        );
    }
}

#[test]
fn lower_layers_never_use_higher_ones() {
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m).unwrap();
    let mut wrong = Vec::new();
    for (module, used) in edges() {
        for u in used {
            if rank(&u) > rank(&module) {
                wrong.push(format!("{module} uses {u}"));
            }
        }
    }
    assert!(wrong.is_empty(), "imports that run upwards: {wrong:?}");
}

/// The checker itself: it finds a path in code and skips one in a comment.
#[test]
fn the_checker_reads_code_paths_and_skips_comments() {
    let found = uses("use crate::grid::LogOddsGrid;\n// crate::apps is only mentioned\nlet x = crate::io::carmen::read;");
    assert_eq!(
        found,
        ["grid", "io"]
            .iter()
            .map(|s| s.to_string())
            .collect::<BTreeSet<_>>()
    );
}

// No import circle between files: within a layer too, each file uses only
// files that do not use it back, directly or through others, so that every
// file can be read after the ones it uses.

/// The module path of a file of `src/` (`apps/real_log/pane.rs` is
/// `["apps", "real_log", "pane"]`; a `mod.rs` is its folder's module).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_str().unwrap().to_string())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.strip_suffix(".rs").unwrap().to_string();
    if stem != "mod" && stem != "lib" {
        parts.push(stem);
    }
    parts
}

/// The file that holds module path `path`, or the nearest ancestor module
/// that does (an item's path names the file that defines or re-exports it).
fn file_of(src: &Path, path: &[String]) -> Option<PathBuf> {
    for n in (1..=path.len()).rev() {
        let rel: PathBuf = path[..n].iter().collect();
        for candidate in [
            src.join(&rel).with_extension("rs"),
            src.join(&rel).join("mod.rs"),
        ] {
            if candidate.is_file() {
                return Some(candidate);
            }
        }
    }
    None
}

/// Every path a file's code names from `crate::`, `super::` or `self::`,
/// with `use` groups (`use super::{a::X, b}`) expanded, as module paths
/// from the crate's root.
fn named_paths(module: &[String], text: &str) -> Vec<Vec<String>> {
    let code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let starts = |w: &str| {
            code_at(&chars, i, w)
                && (i == 0
                    || !(chars[i - 1].is_alphanumeric()
                        || chars[i - 1] == '_'
                        || chars[i - 1] == ':'))
        };
        if starts("crate::") || starts("super::") || starts("self::") {
            let (paths, end) = read_path(&chars, i);
            for p in paths {
                if let Some(abs) = absolute(module, &p) {
                    out.push(abs);
                }
            }
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

fn code_at(chars: &[char], i: usize, word: &str) -> bool {
    word.chars()
        .enumerate()
        .all(|(k, c)| chars.get(i + k) == Some(&c))
}

/// The paths of a `use` tree or path expression starting at `i`, and
/// where it ends.
fn read_path(chars: &[char], mut i: usize) -> (Vec<Vec<String>>, usize) {
    let mut segments = Vec::new();
    loop {
        let start = i;
        while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
            i += 1;
        }
        if i > start {
            segments.push(chars[start..i].iter().collect::<String>());
        }
        if code_at(chars, i, "::{") {
            // A group: each member is a path under the segments so far.
            i += 3;
            let mut paths = Vec::new();
            loop {
                while i < chars.len() && (chars[i].is_whitespace() || chars[i] == ',') {
                    i += 1;
                }
                if i >= chars.len() || chars[i] == '}' {
                    return (paths, i + 1);
                }
                let (inner, end) = read_path(chars, i);
                for p in inner {
                    paths.push(segments.iter().cloned().chain(p).collect());
                }
                i = end.max(i + 1);
            }
        } else if code_at(chars, i, "::") {
            i += 2;
        } else {
            return (vec![segments], i);
        }
    }
}

/// `path` (beginning `crate`, `super` or `self`, or relative inside a
/// group) from the crate's root, seen from `module`.
fn absolute(module: &[String], path: &[String]) -> Option<Vec<String>> {
    let mut base: Vec<String> = module.to_vec();
    // A file's module path ends in its own name (a `mod.rs` in its
    // folder's): `super` climbs one module.
    let mut rest = path;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &rest[1..];
        }
        Some("self") => rest = &rest[1..],
        Some("super") => {
            while rest.first().map(String::as_str) == Some("super") {
                base.pop()?;
                rest = &rest[1..];
            }
        }
        _ => return None,
    }
    Some(base.into_iter().chain(rest.iter().cloned()).collect())
}

/// Every file of `src/` and the files it uses (a file's own folder's
/// `mod.rs` and the ones above it not counted: a module reaching its
/// parent's items is inside the parent's room).
fn file_edges() -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut edges = BTreeMap::new();
    for file in &files {
        let module = module_path(&src, file);
        let text = fs::read_to_string(file).unwrap();
        let ancestors: BTreeSet<PathBuf> = (0..module.len())
            .filter_map(|n| file_of(&src, &module[..n]))
            .collect();
        let used: BTreeSet<PathBuf> = named_paths(&module, &text)
            .iter()
            .filter_map(|p| file_of(&src, p))
            .filter(|f| f != file && !ancestors.contains(f) && !f.ends_with("lib.rs"))
            .collect();
        edges.insert(file.clone(), used);
    }
    edges
}

/// The circles of `edges`, each as the files around it.
fn circles(edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    // Depth-first search from every file; a file seen again on the current
    // path closes a circle.
    fn visit(
        at: &PathBuf,
        edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        path: &mut Vec<PathBuf>,
        done: &mut BTreeSet<PathBuf>,
        found: &mut Vec<Vec<PathBuf>>,
    ) {
        if let Some(i) = path.iter().position(|p| p == at) {
            found.push(path[i..].to_vec());
            return;
        }
        if done.contains(at) {
            return;
        }
        path.push(at.clone());
        for next in edges.get(at).into_iter().flatten() {
            visit(next, edges, path, done, found);
        }
        path.pop();
        done.insert(at.clone());
    }
    let (mut done, mut found) = (BTreeSet::new(), Vec::new());
    for file in edges.keys() {
        visit(file, edges, &mut Vec::new(), &mut done, &mut found);
    }
    found
}

#[test]
fn no_two_files_use_each_other_even_through_others() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let found: Vec<String> = circles(&file_edges())
        .iter()
        .map(|c| {
            c.iter()
                .map(|f| f.strip_prefix(&src).unwrap().display().to_string())
                .collect::<Vec<_>>()
                .join(" -> ")
        })
        .collect();
    assert!(found.is_empty(), "import circles between files: {found:#?}");
}

/// The file checker itself: a group is expanded, `super` climbs from a
/// file's folder, and a circle of two files is found.
#[test]
fn the_file_checker_expands_groups_and_finds_a_circle() {
    let module: Vec<String> = ["apps", "real_log", "pane"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let paths = named_paths(
        &module,
        "use super::{budget::{at_pose, X}, map::LogMap};\nlet g = crate::grid::Grid::new();",
    );
    let as_text: Vec<String> = paths.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        as_text,
        [
            "apps::real_log::budget::at_pose",
            "apps::real_log::budget::X",
            "apps::real_log::map::LogMap",
            "crate::grid::Grid::new".trim_start_matches("crate::"),
        ]
    );
    let (a, b, c) = (
        PathBuf::from("a.rs"),
        PathBuf::from("b.rs"),
        PathBuf::from("c.rs"),
    );
    let mut edges = BTreeMap::new();
    edges.insert(a.clone(), BTreeSet::from([b.clone()]));
    edges.insert(b.clone(), BTreeSet::from([a.clone()]));
    edges.insert(c.clone(), BTreeSet::from([a.clone()]));
    assert_eq!(circles(&edges), vec![vec![a, b]]);
}

/// Every file of `src/` and `widgets/` stays under 900 lines: past that a
/// file holds more than one idea, and a newcomer reads it in pieces.
#[test]
fn no_file_of_the_core_or_the_widgets_reaches_900_lines() {
    fn files(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                files(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs" || e == "js") {
                out.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut all = Vec::new();
    files(&root.join("src"), &mut all);
    files(&root.join("widgets"), &mut all);
    let long: Vec<String> = all
        .iter()
        .filter_map(|f| {
            let n = fs::read_to_string(f).unwrap().lines().count();
            (n >= 900).then(|| format!("{} ({n} lines)", f.strip_prefix(root).unwrap().display()))
        })
        .collect();
    assert!(long.is_empty(), "files of 900 lines or more: {long:?}");
}
