//! Every hand-kept WGSL function is registered with its twin in
//! `shaders/TWINS.md`: the f64 reference function (Rust) or C runtime function
//! it must agree with, or `—` where it has none. This test holds the table to
//! the code: each WGSL function must exist in its file, each twin in its file
//! (or under its folder), each test named as the check must exist, and every
//! function in `shaders/**/*.wgsl` must appear in some row, so renaming or
//! removing either side of a pair, or adding a shader function without saying
//! what it mirrors, fails here.

use std::path::{Path, PathBuf};

/// The register, relative to the crate root.
const TABLE: &str = "shaders/TWINS.md";

/// The twin named in a row.
#[derive(Debug, Clone, PartialEq)]
enum Twin {
    /// A Rust function: `name`, or `Type::name` (the type must appear in an
    /// `impl` line of the same file).
    Rust { ty: Option<String>, name: String },
    /// A C function in the C text the native back end compiles.
    C(String),
}

/// One row of a table.
#[derive(Debug, Clone)]
struct Row {
    /// Line in the register (1-based), for messages.
    line: usize,
    wgsl_file: String,
    wgsl_fn: String,
    /// File or folder (ending in `/`) and twin; `None` for `—`.
    twin: Option<(String, Twin)>,
    checked_by: String,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

fn cell(s: &str) -> String {
    s.trim().trim_matches('`').trim().to_string()
}

fn is_none(s: &str) -> bool {
    matches!(s, "—" | "-" | "")
}

fn parse_twin(s: &str) -> Twin {
    if let Some(c) = s.strip_prefix("C ") {
        return Twin::C(c.trim().to_string());
    }
    match s.rsplit_once("::") {
        Some((ty, name)) => Twin::Rust {
            ty: Some(ty.to_string()),
            name: name.to_string(),
        },
        None => Twin::Rust {
            ty: None,
            name: s.to_string(),
        },
    }
}

/// The rows of every table in `text` (header and separator lines skipped);
/// a malformed row is an error naming its line.
fn parse(text: &str) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if !line.starts_with('|') {
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split('|').collect();
        if cells.len() != 5 {
            return Err(format!(
                "{TABLE}:{}: expected 5 cells, found {}",
                i + 1,
                cells.len()
            ));
        }
        let c: Vec<String> = cells.iter().map(|s| cell(s)).collect();
        if c[0] == "WGSL file" || c[0].starts_with("---") {
            continue;
        }
        let twin = match (is_none(&c[2]), is_none(&c[3])) {
            (true, true) => None,
            (false, false) => Some((c[2].clone(), parse_twin(&c[3]))),
            _ => {
                return Err(format!(
                    "{TABLE}:{}: a twin needs both a file and a function, or `—` in both",
                    i + 1
                ));
            }
        };
        rows.push(Row {
            line: i + 1,
            wgsl_file: c[0].clone(),
            wgsl_fn: c[1].clone(),
            twin,
            checked_by: c[4].clone(),
        });
    }
    Ok(rows)
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Whether `text` defines WGSL function `name` (`fn name(`, as WGSL and the
/// emitter's string constants both write it, the latter maybe just after a
/// `\n` escape).
fn defines_wgsl(text: &str, name: &str) -> bool {
    let pat = format!("fn {name}(");
    text.match_indices(&pat).any(|(i, _)| {
        let before = &text[..i];
        !before.ends_with(is_ident) || before.ends_with("\\n")
    })
}

/// Whether `text` defines Rust function `name` (`fn name(` or `fn name<`).
fn defines_rust(text: &str, name: &str) -> bool {
    let pat = format!("fn {name}");
    text.match_indices(&pat).any(|(i, _)| {
        let after = text[i + pat.len()..].chars().next();
        !text[..i].ends_with(is_ident) && matches!(after, Some('(' | '<'))
    })
}

/// Whether some line of `text` opens an `impl` of `ty`.
fn implements(text: &str, ty: &str) -> bool {
    text.lines().any(|l| {
        let l = l.trim_start();
        l.starts_with("impl")
            && l.match_indices(ty).any(|(i, _)| {
                !l[..i].ends_with(is_ident) && !l[i + ty.len()..].starts_with(is_ident)
            })
    })
}

/// Whether `text` defines C function `name`: a type word, then `name(`, its
/// parameter list, then a body `{` (a call is followed by anything else).
fn defines_c(text: &str, name: &str) -> bool {
    let pat = format!("{name}(");
    text.match_indices(&pat).any(|(i, _)| {
        let before = text[..i].trim_end_matches('*');
        let typed = before.len() < text[..i].len() || before.ends_with(char::is_whitespace);
        let typed = typed && before.trim_end().ends_with(is_ident);
        if !typed || text[..i].ends_with(is_ident) {
            return false;
        }
        let mut depth = 0usize;
        for (j, c) in text[i + name.len()..].char_indices() {
            match c {
                '(' => depth += 1,
                ')' => {
                    depth -= 1;
                    if depth == 0 {
                        let rest = text[i + name.len() + j + 1..].trim_start();
                        return rest.starts_with('{');
                    }
                }
                _ => {}
            }
        }
        false
    })
}

/// `path` itself, or every Rust or C source (`.rs`, `.c`, `.h`) under it when
/// it is a folder.
fn sources(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_path_buf()];
    }
    let mut out = Vec::new();
    let mut todo = vec![path.to_path_buf()];
    while let Some(dir) = todo.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x == "rs" || x == "c" || x == "h")
            {
                out.push(p);
            }
        }
    }
    out
}

/// Every problem with `row`, checked against the tree under `root`.
fn check(root: &Path, row: &Row) -> Vec<String> {
    let at = format!("{TABLE}:{}", row.line);
    let mut errs = Vec::new();
    match read(&root.join(&row.wgsl_file)) {
        None => errs.push(format!("{at}: no file {}", row.wgsl_file)),
        Some(text) if !defines_wgsl(&text, &row.wgsl_fn) => errs.push(format!(
            "{at}: {} defines no WGSL `fn {}(`",
            row.wgsl_file, row.wgsl_fn
        )),
        Some(_) => {}
    }
    if let Some((place, twin)) = &row.twin {
        let files = sources(&root.join(place));
        if files.is_empty() {
            errs.push(format!("{at}: no file or folder {place}"));
        }
        let found = files.iter().filter_map(|f| read(f)).any(|text| match twin {
            Twin::Rust { ty, name } => {
                defines_rust(&text, name) && ty.as_deref().is_none_or(|t| implements(&text, t))
            }
            Twin::C(name) => defines_c(&text, name),
        });
        if !files.is_empty() && !found {
            let what = match twin {
                Twin::Rust { ty: Some(t), name } => format!("Rust `{t}::{name}`"),
                Twin::Rust { ty: None, name } => format!("Rust `fn {name}`"),
                Twin::C(name) => format!("C function `{name}`"),
            };
            errs.push(format!("{at}: {place} defines no {what}"));
        }
    } else if !row.checked_by.starts_with("none") {
        errs.push(format!(
            "{at}: a row without a twin says why, starting `none:`"
        ));
    }
    for word in row
        .checked_by
        .split(|c: char| c.is_whitespace() || "(),:;`".contains(c))
    {
        if word.starts_with("tests/") && word.ends_with(".rs") && !root.join(word).is_file() {
            errs.push(format!("{at}: no test {word}"));
        }
    }
    errs
}

/// `(file relative to the root, function)` of every WGSL function under
/// `shaders/`.
fn shader_functions(root: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut todo = vec![root.join("shaders")];
    while let Some(dir) = todo.pop() {
        for e in std::fs::read_dir(&dir)
            .expect("shaders/ is readable")
            .flatten()
        {
            let p = e.path();
            if p.is_dir() {
                todo.push(p);
                continue;
            }
            if p.extension().is_none_or(|x| x != "wgsl") {
                continue;
            }
            let rel = p
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            for line in read(&p).unwrap_or_default().lines() {
                if let Some(rest) = line.trim_start().strip_prefix("fn ") {
                    let name: String = rest.chars().take_while(|&c| is_ident(c)).collect();
                    out.push((rel.clone(), name));
                }
            }
        }
    }
    out.sort();
    out
}

fn table() -> Vec<Row> {
    let text = read(&root().join(TABLE)).expect("shaders/TWINS.md exists");
    parse(&text).unwrap()
}

#[test]
fn every_registered_pair_exists_on_both_sides() {
    let root = root();
    let rows = table();
    assert!(
        rows.len() > 40,
        "{} rows: the tables did not parse",
        rows.len()
    );
    let errs: Vec<String> = rows.iter().flat_map(|r| check(&root, r)).collect();
    assert!(errs.is_empty(), "\n{}", errs.join("\n"));
}

#[test]
fn every_shader_function_is_registered() {
    let rows = table();
    let missing: Vec<String> = shader_functions(&root())
        .into_iter()
        .filter(|(file, name)| {
            !rows
                .iter()
                .any(|r| &r.wgsl_file == file && &r.wgsl_fn == name)
        })
        .map(|(file, name)| format!("{file}: fn {name} has no row in {TABLE}"))
        .collect();
    assert!(!shader_functions(&root()).is_empty());
    assert!(missing.is_empty(), "\n{}", missing.join("\n"));
}

#[test]
fn a_renamed_or_removed_function_is_caught() {
    let root = root();
    let good = |wgsl: &str, place: &str, twin: &str| Row {
        line: 0,
        wgsl_file: "shaders/shared/exp.wgsl".into(),
        wgsl_fn: wgsl.into(),
        twin: Some((place.into(), parse_twin(twin))),
        checked_by: "tests/gpu_exp_matches_std.rs".into(),
    };
    assert!(check(&root, &good("exp_r", "src/compile/math.rs", "exp")).is_empty());
    assert!(check(&root, &good("exp_r", "src/compile/back/", "C dexp")).is_empty());
    // Either side renamed.
    assert_eq!(
        check(&root, &good("exp_q", "src/compile/math.rs", "exp")).len(),
        1
    );
    assert_eq!(
        check(&root, &good("exp_r", "src/compile/math.rs", "exq")).len(),
        1
    );
    assert_eq!(
        check(&root, &good("exp_r", "src/compile/back/", "C dexq")).len(),
        1
    );
    // A method on a type that has no such impl in the file.
    let wrong_type = good("exp_r", "src/compile/math.rs", "Nowhere::exp");
    assert_eq!(check(&root, &wrong_type).len(), 1);
    // A file gone, a test gone.
    assert_eq!(
        check(&root, &good("exp_r", "src/compile/maths.rs", "exp")).len(),
        1
    );
    let mut gone = good("exp_r", "src/compile/math.rs", "exp");
    gone.checked_by = "tests/no_such_test.rs".into();
    assert_eq!(check(&root, &gone).len(), 1);
}

#[test]
fn calls_are_not_taken_for_definitions() {
    let c = "F d dexp(d x) { return x; }\nF d wexp(d x) { return dexp(x); }\n";
    assert!(defines_c(c, "dexp"));
    assert!(defines_c(c, "wexp"));
    assert!(!defines_c("F d wexp(d x) { return dexp(x); }", "dexp"));
    assert!(!defines_c("d y = dexp(x);", "dexp"));
    let rust = "fn expm1(x: f64) -> f64 { exp(x) }\nfn step<C>(c: C) {}";
    assert!(defines_rust(rust, "expm1"));
    assert!(defines_rust(rust, "step"));
    assert!(!defines_rust(rust, "exp"));
    assert!(defines_wgsl("fn rig_sample(kc: RunConsts)", "rig_sample"));
    assert!(!defines_wgsl(
        "fn rig_sample_c(kc: RunConsts)",
        "rig_sample"
    ));
    assert!(!defines_wgsl(
        "fn st_rig_sample(kc: RunConsts)",
        "rig_sample"
    ));
}
