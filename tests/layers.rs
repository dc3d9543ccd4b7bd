//! The core's layers: each top-level module of `src/` uses only the modules
//! listed before it (the order of `src/lib.rs`'s module doc), so a scan can
//! be followed from the sensor to the pixel and no two modules import each
//! other. Read from the source text: every `crate::NAME` path (and
//! `super::NAME` one level down) outside comments.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Lowest first; `bindings` may use everything.
const LAYERS: [&str; 14] = [
    "error", "geometry", "world", "sensors", "scenes", "grid", "inverse", "mapping", "poses",
    "render", "io", "apps", "bench", "bindings",
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
