//! The library's top-level modules form layers, written in ARCHITECTURE.md
//! (its "Layers" list, lowest first): a module imports only modules below its
//! own, so imports run one way and no two modules import each other. This
//! test reads every file under `src/` (the binary's `main.rs` and `cli/`
//! aside: they sit above every layer and reach the library as `rigfit::`; and
//! unit tests, from a file's `#[cfg(test)]` on) and fails on an import that
//! runs up the list, naming the file and line.

use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The layer list: the items of the list that follows the `## Layers`
/// heading, each a module name in backticks at the start of its item.
fn layers(architecture: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in architecture.lines() {
        if line.starts_with("## ") {
            inside = line.trim() == "## Layers";
            continue;
        }
        if !inside {
            continue;
        }
        let item = line.trim_start();
        let Some(rest) = item
            .strip_prefix("1. ")
            .or_else(|| item.split_once(". ").map(|(_, r)| r))
        else {
            continue;
        };
        if let Some(name) = rest.strip_prefix('`').and_then(|r| r.split('`').next()) {
            out.push(name.to_string());
        }
    }
    out
}

/// The modules a line of Rust imports through `crate::`: `crate::a::…`
/// and each top-level name of `crate::{a::…, b}`. Comments are not code.
fn crate_imports(line: &str) -> Vec<String> {
    let code = match line.find("//") {
        Some(i) => &line[..i],
        None => line,
    };
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        // `$crate::` in a macro, or a longer identifier ending in `crate`.
        let before = rest[..i].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            rest = after;
            continue;
        }
        if let Some(group) = after.strip_prefix('{') {
            let body = group.split('}').next().unwrap_or("");
            let mut depth = 0;
            let mut start = 0;
            for (j, c) in body.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.push(first_segment(&body[start..j]));
                        start = j + 1;
                    }
                    _ => {}
                }
            }
            out.push(first_segment(&body[start..]));
        } else {
            out.push(first_segment(after));
        }
        rest = after;
    }
    out.retain(|m| !m.is_empty());
    out
}

fn first_segment(path: &str) -> String {
    path.trim()
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect()
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The imports that run up `layers` in the files of `src` (relative path,
/// text), as `file:line: message`.
fn violations(layers: &[String], sources: &[(String, String)]) -> Vec<String> {
    let rank = |m: &str| layers.iter().position(|l| l == m);
    let mut out = Vec::new();
    for (file, text) in sources {
        let own = file.split('/').next().unwrap_or("").trim_end_matches(".rs");
        let Some(own_rank) = rank(own) else {
            out.push(format!("src/{file}: module `{own}` is in no layer"));
            continue;
        };
        for (n, line) in text.lines().enumerate() {
            // Unit tests (at a file's end) are no part of the library: they
            // may build on the layers above.
            if line.trim() == "#[cfg(test)]" {
                break;
            }
            for m in crate_imports(line) {
                if m == own {
                    continue;
                }
                match rank(&m) {
                    Some(r) if r < own_rank => {}
                    Some(_) => out.push(format!(
                        "src/{file}:{}: `{own}` imports `crate::{m}`, which is not below it",
                        n + 1
                    )),
                    None => out.push(format!("src/{file}:{}: `crate::{m}` is in no layer", n + 1)),
                }
            }
        }
    }
    out
}

#[test]
fn imports_run_down_the_layer_list() {
    let arch = std::fs::read_to_string(repo().join("ARCHITECTURE.md")).unwrap();
    let layers = layers(&arch);
    assert!(
        layers.len() >= 8,
        "ARCHITECTURE.md has no \"## Layers\" list: {layers:?}"
    );
    let src = repo().join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let sources: Vec<(String, String)> = files
        .iter()
        .map(|p| {
            let rel = p
                .strip_prefix(&src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (rel, std::fs::read_to_string(p).unwrap())
        })
        .filter(|(rel, _)| rel != "main.rs" && rel != "lib.rs" && !rel.starts_with("cli/"))
        .collect();
    // Every listed layer is a module, and every module is listed.
    for l in &layers {
        assert!(
            src.join(l).is_dir() || src.join(format!("{l}.rs")).is_file(),
            "layer `{l}` is no module under src/"
        );
    }
    let bad = violations(&layers, &sources);
    assert!(
        bad.is_empty(),
        "imports up the layers:\n  {}",
        bad.join("\n  ")
    );
}

#[test]
fn an_import_up_the_list_or_a_cycle_is_caught() {
    let layers: Vec<String> = ["base", "rig", "model"].map(String::from).to_vec();
    let ok = vec![(
        "model/a.rs".to_string(),
        "use crate::{base::Drive, rig::desc};\nuse crate::model::x; // crate::job".to_string(),
    )];
    assert!(violations(&layers, &ok).is_empty());
    let up = vec![(
        "rig/desc.rs".to_string(),
        "use crate::base::Scale;\n    let x = crate::model::Thing::new();".to_string(),
    )];
    let found = violations(&layers, &up);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("src/rig/desc.rs:2:"), "{found:?}");
    let grouped = vec![(
        "base/x.rs".to_string(),
        "use crate::{text, rig::RigDesc};".to_string(),
    )];
    assert_eq!(violations(&layers, &grouped).len(), 2);
    let unlisted = vec![("job/mod.rs".to_string(), String::new())];
    assert_eq!(violations(&layers, &unlisted).len(), 1);
}

#[test]
fn the_layer_list_is_read_from_its_section() {
    let md = "# x\n\n## Layers\n\nLowest first.\n\n1. `base` — words\n2. `rig` — files\n\n## Other\n\n1. `job`\n";
    assert_eq!(layers(md), ["base", "rig"]);
}
