//! The documentation's relative links resolve: every `[text](target)` in
//! README.md, ARCHITECTURE.md and the book under docs/ names a file that exists,
//! and every `#anchor` names a heading of its file (GitHub's slugs). Also: the
//! README stays a front door of at most 300 lines.
//!
//! Standard library only, so it builds without the crate:
//! `CARGO_MANIFEST_DIR=$PWD rustc --edition 2024 --test tests/docs_links.rs -o /tmp/docs_links && /tmp/docs_links`

use std::collections::HashMap;
use std::fs;
use std::path::{Component, Path, PathBuf};

const README_MAX_LINES: usize = 300;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// GitHub's heading anchor: lowercase, punctuation other than `-` and `_`
/// dropped (letters and digits of any script kept), each space a `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .flat_map(char::to_lowercase)
        .filter_map(|c| {
            if c == ' ' {
                Some('-')
            } else if c.is_alphanumeric() || c == '-' || c == '_' {
                Some(c)
            } else {
                None
            }
        })
        .collect()
}

/// A fence opener or closer: up to three spaces, then ``` or ~~~.
fn is_fence(line: &str) -> bool {
    let indent = line.len() - line.trim_start_matches(' ').len();
    let rest = line.trim_start_matches(' ');
    indent <= 3 && (rest.starts_with("```") || rest.starts_with("~~~"))
}

/// The text of an ATX heading (`## Text ##`), if the line is one.
fn heading_text(line: &str) -> Option<&str> {
    let t = line.trim_start_matches(' ');
    if line.len() - t.len() > 3 {
        return None;
    }
    let hashes = t.len() - t.trim_start_matches('#').len();
    if hashes == 0 || hashes > 6 {
        return None;
    }
    let rest = &t[hashes..];
    if !(rest.is_empty() || rest.starts_with(' ') || rest.starts_with('\t')) {
        return None;
    }
    let rest = rest.trim();
    // A closing sequence of #s, preceded by a space, is not part of the text.
    let without_close = rest.trim_end_matches('#');
    let text = if without_close.len() < rest.len()
        && (without_close.is_empty() || without_close.ends_with(' '))
    {
        without_close.trim_end()
    } else {
        rest
    };
    Some(text)
}

/// Renders a heading's inline markdown to the text GitHub slugs: link targets
/// dropped (`[a](b)` → `a`); other markup is punctuation that `slug` drops.
fn heading_plain(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(open) = rest.find('[') {
        let Some(mid) = rest[open..].find("](") else {
            break;
        };
        let Some(close) = rest[open + mid..].find(')') else {
            break;
        };
        out.push_str(&rest[..open]);
        out.push_str(&rest[open + 1..open + mid]);
        rest = &rest[open + mid + close + 1..];
    }
    out.push_str(rest);
    out
}

/// Every heading's anchor in a markdown text, with GitHub's -1, -2 … for repeats.
fn anchors(text: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    let mut in_fence = false;
    for line in text.lines() {
        if is_fence(line) {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        if let Some(h) = heading_text(line) {
            let base = slug(&heading_plain(h));
            let n = seen.entry(base.clone()).or_insert(0);
            out.push(if *n == 0 {
                base.clone()
            } else {
                format!("{base}-{n}")
            });
            *n += 1;
        }
    }
    out
}

/// The line with inline code spans blanked, so that `[a](b)` inside backticks
/// is not read as a link.
fn without_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '`' {
            out.push(c);
            continue;
        }
        let mut ticks = 1;
        while chars.peek() == Some(&'`') {
            chars.next();
            ticks += 1;
        }
        // Find the matching run of the same length; without one, the ticks are text.
        let rest: String = chars.clone().collect();
        let closer = "`".repeat(ticks);
        let mut search = 0;
        let mut found = None;
        while let Some(i) = rest[search..].find(&closer) {
            let at = search + i;
            let after = rest[at + ticks..].starts_with('`');
            if !after {
                found = Some(at);
                break;
            }
            search = at + ticks + rest[at + ticks..].len()
                - rest[at + ticks..].trim_start_matches('`').len();
        }
        match found {
            Some(at) => {
                let skip = rest[..at + ticks].chars().count();
                for _ in 0..skip {
                    chars.next();
                }
                out.push(' ');
            }
            None => out.push_str(&closer),
        }
    }
    out
}

/// The targets of the inline links `[text](target)` and images on a line.
fn link_targets(line: &str) -> Vec<String> {
    let line = without_code_spans(line);
    let mut out = Vec::new();
    let mut rest = line.as_str();
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        // The target runs to the ')' that closes the '(' (balanced parentheses).
        let mut depth = 0usize;
        let mut end = None;
        for (j, c) in after.char_indices() {
            match c {
                '(' => depth += 1,
                ')' if depth == 0 => {
                    end = Some(j);
                    break;
                }
                ')' => depth -= 1,
                _ => {}
            }
        }
        let Some(end) = end else { break };
        let mut target = after[..end].trim();
        if let Some(t) = target.strip_prefix('<') {
            target = t.split('>').next().unwrap_or("");
        } else if let Some(sp) = target.find(char::is_whitespace) {
            target = &target[..sp]; // drop a "title"
        }
        if !target.is_empty() {
            out.push(target.to_string());
        }
        rest = &after[end..];
    }
    out
}

fn is_external(target: &str) -> bool {
    let t = target.to_ascii_lowercase();
    t.starts_with("http://") || t.starts_with("https://") || t.starts_with("mailto:")
}

fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other.as_os_str()),
        }
    }
    out
}

fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            markdown_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "md") {
            out.push(p);
        }
    }
}

fn documents() -> Vec<PathBuf> {
    let root = root();
    let mut files = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    markdown_files(&root.join("docs"), &mut files);
    files
}

/// Every broken link of the given files, as `file:line: target (why)`.
fn broken_links(files: &[PathBuf]) -> Vec<String> {
    let root = root();
    let mut anchor_cache: HashMap<PathBuf, Vec<String>> = HashMap::new();
    let mut problems = Vec::new();
    for file in files {
        let Ok(text) = fs::read_to_string(file) else {
            problems.push(format!("{}: cannot be read", file.display()));
            continue;
        };
        let shown = file
            .strip_prefix(&root)
            .unwrap_or(file)
            .display()
            .to_string();
        let dir = file.parent().unwrap_or(&root).to_path_buf();
        let mut in_fence = false;
        for (n, line) in text.lines().enumerate() {
            if is_fence(line) {
                in_fence = !in_fence;
                continue;
            }
            if in_fence {
                continue;
            }
            for target in link_targets(line) {
                if is_external(&target) {
                    continue;
                }
                let (path_part, anchor) = match target.split_once('#') {
                    Some((p, a)) => (p, Some(a)),
                    None => (target.as_str(), None),
                };
                let dest = if path_part.is_empty() {
                    file.clone()
                } else {
                    normalise(&dir.join(path_part))
                };
                if !dest.exists() {
                    problems.push(format!(
                        "{shown}:{}: {target} (no such file: {})",
                        n + 1,
                        dest.strip_prefix(&root).unwrap_or(&dest).display()
                    ));
                    continue;
                }
                let Some(anchor) = anchor else { continue };
                if dest.extension().is_none_or(|e| e != "md") {
                    continue;
                }
                let list = anchor_cache.entry(dest.clone()).or_insert_with(|| {
                    fs::read_to_string(&dest)
                        .map(|t| anchors(&t))
                        .unwrap_or_default()
                });
                if !list.iter().any(|a| a == anchor) {
                    problems.push(format!(
                        "{shown}:{}: {target} (no heading with anchor #{anchor} in {})",
                        n + 1,
                        dest.strip_prefix(&root).unwrap_or(&dest).display()
                    ));
                }
            }
        }
    }
    problems
}

#[test]
fn slugs_follow_github() {
    assert_eq!(slug("Two commands"), "two-commands");
    assert_eq!(slug("The model: `tensile4`"), "the-model-tensile4");
    assert_eq!(slug("Rigs as data: `\"rig\"`"), "rigs-as-data-rig");
    assert_eq!(
        slug("`inertial_sdof` — an inertial fatigue rig"),
        "inertial_sdof--an-inertial-fatigue-rig"
    );
    assert_eq!(
        slug("Precision: the GPU path against the f64 CPU reference"),
        "precision-the-gpu-path-against-the-f64-cpu-reference"
    );
    assert_eq!(
        slug("What rigfit refuses and what it never does"),
        "what-rigfit-refuses-and-what-it-never-does"
    );
    assert_eq!(
        slug("Pre-calibration: `fit-specimen` and `ringdown`"),
        "pre-calibration-fit-specimen-and-ringdown"
    );
    assert_eq!(slug("Größe & Maß"), "größe--maß");
    assert_eq!(slug("1 − R² by generation"), "1--r²-by-generation");
    assert_ne!(slug("Two commands"), "two commands");
    assert_eq!(heading_text("## Known limits ##"), Some("Known limits"));
    assert_eq!(heading_text("#hashtag"), None);
    assert_eq!(
        heading_plain("See [the guide](guide/x.md) now"),
        "See the guide now"
    );
}

#[test]
fn duplicate_headings_get_numbered_anchors() {
    let text = "# A\n## Wall time\n```\n# not a heading\n```\n## Wall time\n### Wall time\n";
    assert_eq!(
        anchors(text),
        ["a", "wall-time", "wall-time-1", "wall-time-2"]
    );
}

#[test]
fn links_are_found_outside_code() {
    assert_eq!(
        link_targets("see [a](b.md#c) and ![img](d/e.svg \"t\")"),
        ["b.md#c", "d/e.svg"]
    );
    assert!(link_targets("`[not](a link)` here").is_empty());
    assert_eq!(link_targets("[x](<with space.md>)"), ["with space.md"]);
    assert_eq!(link_targets("[f](a_(b).md)"), ["a_(b).md"]);
}

#[test]
fn the_checker_reports_broken_links() {
    // A page with one good and three broken links, written where the checker reads.
    let dir = std::env::temp_dir().join(format!("rigfit-docs-links-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    let page = dir.join("page.md");
    let other = dir.join("other.md");
    fs::write(&other, "# Other page\n## A section\n").unwrap();
    fs::write(
        &page,
        "# Page\n[ok](other.md#a-section)\n[self](#page)\n[gone](missing.md)\n\
        [bad anchor](other.md#no-such)\n[bad self](#nowhere)\n```\n[in code](missing2.md)\n```\n\
        [web](https://example.com/x)\n",
    )
    .unwrap();
    let problems = broken_links(&[page]);
    fs::remove_dir_all(&dir).ok();
    assert_eq!(problems.len(), 3, "{problems:#?}");
    assert!(problems[0].contains(":4: missing.md"), "{problems:#?}");
    assert!(
        problems[1].contains(":5: other.md#no-such"),
        "{problems:#?}"
    );
    assert!(problems[2].contains(":6: #nowhere"), "{problems:#?}");
}

#[test]
fn every_relative_link_and_anchor_resolves() {
    let files = documents();
    assert!(
        files.len() > 2,
        "no docs/ pages found under {}",
        root().display()
    );
    let problems = broken_links(&files);
    assert!(
        problems.is_empty(),
        "{} broken link(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn readme_is_a_front_door() {
    let text = fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines; at most {README_MAX_LINES}: move detail into docs/"
    );
}
