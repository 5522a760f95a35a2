//! The library's modules form layers, written in ARCHITECTURE.md: its
//! "Layers" list orders the top-level modules, and its "Compile layers" list
//! the modules inside `compile/` (each lowest first). A module imports only
//! modules below its own, so imports run one way and no two modules import
//! each other. This test reads every file under `src/` (the binary's
//! `main.rs` and `cli/` aside: they sit above every layer and reach the
//! library as `rigfit::`; `lib.rs`, and within `compile/` its `mod.rs`,
//! which only gather and re-export; and unit tests, from a file's `#[cfg(test)]` on), follows
//! each path through `crate::`, `super::` and `self::` (grouped, and over
//! several lines), and fails on an import that runs up a list, naming the
//! file and line.

use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The items of the list that follows the heading `heading` (`## Layers`),
/// each a module name in backticks at the start of its item.
fn layers(architecture: &str, heading: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in architecture.lines() {
        if line.starts_with("## ") {
            inside = line.trim() == heading;
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

/// The module a file under `src/` is, as path segments from the crate root:
/// `model/compiled.rs` is `model::compiled`, `compile/back/c/mod.rs` is
/// `compile::back::c`, `lib.rs` the root.
fn module_of(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The code of `text`, comments removed, up to its unit tests (a line
/// `#[cfg(test)]`: they may build on the layers above), as `(line number,
/// code)`: a `use` that spans lines joined onto its first.
fn statements(text: &str) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut open = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim() == "#[cfg(test)]" {
            break;
        }
        let code = line.find("//").map_or(line, |i| &line[..i]);
        if open {
            let last = out.last_mut().expect("an open statement");
            last.1.push(' ');
            last.1.push_str(code.trim());
        } else {
            out.push((n + 1, code.to_string()));
            let t = code.trim_start();
            open = t.starts_with("use ") || t.starts_with("pub") && t.contains(" use ");
        }
        if open && code.contains(';') {
            open = false;
        }
    }
    out
}

fn identifier(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// Every path of the use tree `s` (`a::b`, `a::{b, c::d}`, `{a, b}`) after
/// `prefix`, into `out`.
fn expand(prefix: &[String], s: &str, out: &mut Vec<Vec<String>>) {
    let mut path = prefix.to_vec();
    let mut rest = s.trim_start();
    loop {
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut start = 0;
            for (j, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        expand(&path, &group[start..j], out);
                        return;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        expand(&path, &group[start..j], out);
                        start = j + 1;
                    }
                    _ => {}
                }
            }
            // A group left open (its text ends first).
            expand(&path, &group[start..], out);
            return;
        }
        let name = identifier(rest);
        if name.is_empty() {
            break;
        }
        path.push(name.to_string());
        match rest[name.len()..].strip_prefix("::") {
            Some(more) => rest = more.trim_start(),
            None => break,
        }
    }
    if path.len() > prefix.len() {
        out.push(path);
    }
}

/// The paths (as segments from the crate root) that `code`, in module
/// `module`, names through `crate::`, `super::` or `self::`.
fn crate_paths(module: &[String], code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = ["crate::", "super::", "self::"]
        .iter()
        .filter_map(|k| rest.find(k))
        .min()
    {
        let before = rest[..i].chars().last();
        let tail = &rest[i..];
        let (skip, base): (usize, Option<Vec<String>>) = if tail.starts_with("crate::") {
            ("crate::".len(), Some(Vec::new()))
        } else if tail.starts_with("self::") {
            ("self::".len(), Some(module.to_vec()))
        } else {
            // `super::super::…`: one level up for each.
            let mut up = 0;
            let mut t = tail;
            while let Some(more) = t.strip_prefix("super::") {
                up += 1;
                t = more;
            }
            let base = (up <= module.len()).then(|| module[..module.len() - up].to_vec());
            (tail.len() - t.len(), base)
        };
        let after = &tail[skip..];
        // `$crate::` in a macro, or a longer identifier ending in `crate`.
        let part_of_name =
            before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$' || c == ':');
        if let (Some(base), false) = (base, part_of_name) {
            expand(&base, after, &mut out);
        }
        rest = after;
    }
    out
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

/// The imports that run up `layers`, the modules directly inside `scope`
/// (the crate root, or `compile`), in the files of `src` under it (relative
/// path, text), as `file:line: message`. A file's own layer is the module
/// of `scope` it is in; an import leaves `scope`'s check where it leads
/// outside it.
fn violations(scope: &[&str], layers: &[String], sources: &[(String, String)]) -> Vec<String> {
    let rank = |m: &str| layers.iter().position(|l| l == m);
    let within = |p: &[String]| {
        (p.len() > scope.len() && p.iter().zip(scope).all(|(a, b)| a == b))
            .then(|| p[scope.len()].clone())
    };
    let shown = |m: &str| {
        let mut s = scope.to_vec();
        s.push(m);
        format!("crate::{}", s.join("::"))
    };
    let mut out = Vec::new();
    for (file, text) in sources {
        let Some(own) = within(&module_of(file)) else {
            continue;
        };
        let Some(own_rank) = rank(&own) else {
            out.push(format!(
                "src/{file}: module `{}` is in no layer",
                shown(&own)
            ));
            continue;
        };
        let module = module_of(file);
        for (n, code) in statements(text) {
            for path in crate_paths(&module, &code) {
                let Some(m) = within(&path) else {
                    continue;
                };
                if m == own {
                    continue;
                }
                match rank(&m) {
                    Some(r) if r < own_rank => {}
                    Some(_) => out.push(format!(
                        "src/{file}:{n}: `{}` imports `{}`, which is not below it",
                        shown(&own),
                        shown(&m)
                    )),
                    None => out.push(format!("src/{file}:{n}: `{}` is in no layer", shown(&m))),
                }
            }
        }
    }
    out
}

/// Every file under `src/` but the binary's, as (relative path, text).
fn sources(src: &Path) -> Vec<(String, String)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files
        .iter()
        .map(|p| {
            let rel = p
                .strip_prefix(src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (rel, std::fs::read_to_string(p).unwrap())
        })
        .filter(|(rel, _)| rel != "main.rs" && rel != "lib.rs" && !rel.starts_with("cli/"))
        .collect()
}

#[test]
fn imports_run_down_the_layer_list() {
    let arch = std::fs::read_to_string(repo().join("ARCHITECTURE.md")).unwrap();
    let src = repo().join("src");
    let sources = sources(&src);
    for (heading, scope, at_least) in [
        ("## Layers", &[][..], 8),
        ("## Compile layers", &["compile"][..], 5),
    ] {
        let layers = layers(&arch, heading);
        assert!(
            layers.len() >= at_least,
            "ARCHITECTURE.md has no \"{heading}\" list: {layers:?}"
        );
        // Every listed layer is a module, and every module is listed.
        let dir = scope.iter().fold(src.clone(), |d, s| d.join(s));
        for l in &layers {
            assert!(
                dir.join(l).is_dir() || dir.join(format!("{l}.rs")).is_file(),
                "layer `{l}` ({heading}) is no module under {}",
                dir.display()
            );
        }
        let bad = violations(scope, &layers, &sources);
        assert!(
            bad.is_empty(),
            "imports up the layers ({heading}):\n  {}",
            bad.join("\n  ")
        );
    }
}

#[test]
fn an_import_up_the_list_or_a_cycle_is_caught() {
    let layers: Vec<String> = ["base", "rig", "model"].map(String::from).to_vec();
    let ok = vec![(
        "model/a.rs".to_string(),
        "use crate::{base::Drive, rig::desc};\nuse crate::model::x; // crate::job".to_string(),
    )];
    assert!(violations(&[], &layers, &ok).is_empty());
    let up = vec![(
        "rig/desc.rs".to_string(),
        "use crate::base::Scale;\n    let x = crate::model::Thing::new();".to_string(),
    )];
    let found = violations(&[], &layers, &up);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("src/rig/desc.rs:2:"), "{found:?}");
    let grouped = vec![(
        "base/x.rs".to_string(),
        "use crate::{text, rig::RigDesc};".to_string(),
    )];
    assert_eq!(violations(&[], &layers, &grouped).len(), 2);
    let unlisted = vec![("job/mod.rs".to_string(), String::new())];
    assert_eq!(violations(&[], &layers, &unlisted).len(), 1);
}

#[test]
fn an_import_up_the_compile_list_is_caught_however_written() {
    let layers: Vec<String> = ["ir", "exec", "back"].map(String::from).to_vec();
    let scope = &["compile"][..];
    let ok = vec![
        (
            "compile/back/c/rk4.rs".to_string(),
            "use super::statements::load;\nuse super::super::wgsl::Emitter;\nuse crate::compile::{exec::lanes::Reg, ir::Op};\nuse crate::base::x;".to_string(),
        ),
        (
            "compile/exec/lanes.rs".to_string(),
            "use super::tape::Tape;\nuse crate::compile::ir::{\n    Id,\n    Op,\n};".to_string(),
        ),
    ];
    assert!(
        violations(scope, &layers, &ok).is_empty(),
        "{:?}",
        violations(scope, &layers, &ok)
    );
    let up = vec![
        (
            "compile/ir.rs".to_string(),
            "use crate::base::x;\n    let y = super::exec::math::exp(x);".to_string(),
        ),
        (
            "compile/exec/lanes.rs".to_string(),
            "use crate::compile::{\n    ir::Op,\n    back::native::Native,\n};\nuse super::super::back::c;".to_string(),
        ),
        ("compile/exec/tape.rs".to_string(), "use crate::{compile::back::c, base::x};".to_string()),
    ];
    let found = violations(scope, &layers, &up);
    assert_eq!(found.len(), 4, "{found:?}");
    assert!(
        found[0].starts_with(
            "src/compile/ir.rs:2: `crate::compile::ir` imports `crate::compile::exec`"
        ),
        "{found:?}"
    );
    assert!(
        found[1].starts_with("src/compile/exec/lanes.rs:1:"),
        "{found:?}"
    );
    assert!(
        found[2].starts_with("src/compile/exec/lanes.rs:5:"),
        "{found:?}"
    );
    assert!(
        found[3].starts_with("src/compile/exec/tape.rs:1:"),
        "{found:?}"
    );
    // A name the compile folder re-exports is no layer: the import says
    // which module it comes from.
    let reexport = vec![(
        "compile/back/x.rs".to_string(),
        "use crate::compile::Tape;".to_string(),
    )];
    assert_eq!(violations(scope, &layers, &reexport).len(), 1);
    // Files outside the scope, and the scope's own `mod.rs`, are not its.
    let outside = vec![
        (
            "model/a.rs".to_string(),
            "use crate::compile::back::c;".to_string(),
        ),
        (
            "compile/mod.rs".to_string(),
            "pub use back::c::Arith;".to_string(),
        ),
    ];
    assert!(violations(scope, &layers, &outside).is_empty());
}

#[test]
fn the_layer_list_is_read_from_its_section() {
    let md = "# x\n\n## Layers\n\nLowest first.\n\n1. `base` — words\n2. `rig` — files\n\n## Compile layers\n\n1. `ir`\n2. `back`\n\n## Other\n\n1. `job`\n";
    assert_eq!(layers(md, "## Layers"), ["base", "rig"]);
    assert_eq!(layers(md, "## Compile layers"), ["ir", "back"]);
}
