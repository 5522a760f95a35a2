//! No source file of the library, the binary or the Python crate holds more
//! than [`MOST_CODE_LINES`] lines of code: a file past that holds more than
//! one idea and is split by idea.
//!
//! A code line is a non-blank line that is not wholly a comment (`//`,
//! `///`, `//!`, `/* … */`), outside the items marked `#[cfg(test)]` (unit
//! tests sit beside the code they test and do not count against it).
//!
//! Standard library only, so it builds without the crate:
//! `CARGO_MANIFEST_DIR=$PWD rustc --edition 2024 --test tests/file_sizes.rs -o /tmp/file_sizes && /tmp/file_sizes`

use std::path::{Path, PathBuf};

/// Most code lines a source file may hold.
const MOST_CODE_LINES: usize = 600;

/// The folders whose `.rs` files are held to [`MOST_CODE_LINES`].
const SOURCE_FOLDERS: &[&str] = &["src", "python/src"];

/// Where the lexer is: code, or inside a comment, string or character.
#[derive(Clone, Copy, PartialEq)]
enum In {
    Code,
    LineComment,
    /// A block comment, nested this deep.
    BlockComment(usize),
    Str,
    /// A raw string closed by `"` and this many `#`.
    RawStr(usize),
}

/// What the lexer finds in a file: which lines hold code, where each line
/// starts in the text, and the braces and semicolons of its code (string,
/// character and comment contents aside), each with its line.
struct Lexed {
    code: Vec<bool>,
    marks: Vec<(usize, char)>,
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn lex(text: &str) -> Lexed {
    let chars: Vec<char> = text.chars().collect();
    let mut code = vec![false];
    let mut marks = Vec::new();
    let mut state = In::Code;
    let mut line = 0;
    let mut i = 0;
    let at = |k: usize| chars.get(k).copied().unwrap_or('\0');
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            code.push(false);
            if state == In::LineComment {
                state = In::Code;
            }
            i += 1;
            continue;
        }
        match state {
            In::LineComment => i += 1,
            In::BlockComment(depth) => {
                if c == '*' && at(i + 1) == '/' {
                    state = if depth == 1 {
                        In::Code
                    } else {
                        In::BlockComment(depth - 1)
                    };
                    i += 2;
                } else if c == '/' && at(i + 1) == '*' {
                    state = In::BlockComment(depth + 1);
                    i += 2;
                } else {
                    i += 1;
                }
            }
            In::Str => {
                code[line] = true;
                match c {
                    // An escape; a line continuation's newline is counted.
                    '\\' if at(i + 1) != '\n' => i += 2,
                    '"' => {
                        state = In::Code;
                        i += 1;
                    }
                    _ => i += 1,
                }
            }
            In::RawStr(hashes) => {
                code[line] = true;
                if c == '"' && (1..=hashes).all(|h| at(i + h) == '#') {
                    state = In::Code;
                    i += 1 + hashes;
                } else {
                    i += 1;
                }
            }
            In::Code => {
                if c.is_whitespace() {
                    i += 1;
                    continue;
                }
                if c == '/' && at(i + 1) == '/' {
                    state = In::LineComment;
                    i += 2;
                    continue;
                }
                if c == '/' && at(i + 1) == '*' {
                    state = In::BlockComment(1);
                    i += 2;
                    continue;
                }
                code[line] = true;
                // `r"…"`, `r#"…"#`, `br"…"`: a raw string, where the `r`
                // starts a token (or follows a `b` that does).
                let starts_token = |k: usize| k == 0 || !is_ident(chars[k - 1]);
                let raw_start =
                    c == 'r' && (starts_token(i) || (at(i - 1) == 'b' && starts_token(i - 1)));
                if raw_start {
                    let hashes = (i + 1..).take_while(|&k| at(k) == '#').count();
                    if at(i + 1 + hashes) == '"' {
                        state = In::RawStr(hashes);
                        i += 2 + hashes;
                        continue;
                    }
                }
                match c {
                    '"' => state = In::Str,
                    // A character literal (`'x'`, `'\n'`, `'\u{7b}'`); any
                    // other quote starts a lifetime or a label.
                    '\'' if at(i + 1) == '\\' => {
                        let close = (i + 3..chars.len()).find(|&k| chars[k] == '\'');
                        i = close.unwrap_or(i);
                    }
                    '\'' if at(i + 2) == '\'' => i += 2,
                    '{' | '}' | ';' => marks.push((line, c)),
                    _ => {}
                }
                i += 1;
            }
        }
    }
    Lexed { code, marks }
}

/// Code lines of `text`: lines holding code outside comments, each
/// `#[cfg(test)]` item (from its attribute's line through its closing
/// brace or semicolon) left out.
fn code_lines(text: &str) -> usize {
    let lexed = lex(text);
    let lines: Vec<&str> = text.lines().collect();
    let mut counted = lexed.code.clone();
    for (start, l) in lines.iter().enumerate() {
        if !l.trim_start().starts_with("#[cfg(test)]") || !lexed.code[start] {
            continue;
        }
        let mut depth = 0usize;
        let mut end = lines.len().saturating_sub(1);
        for &(line, c) in lexed.marks.iter().filter(|(line, _)| *line >= start) {
            match c {
                ';' if depth == 0 => {
                    end = line;
                    break;
                }
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        end = line;
                        break;
                    }
                }
                _ => {}
            }
        }
        let last = counted.len() - 1;
        for flag in &mut counted[start..=end.min(last)] {
            *flag = false;
        }
    }
    counted.iter().filter(|&&c| c).count()
}

fn rust_files(dir: &Path, found: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, found);
        } else if path.extension().is_some_and(|e| e == "rs") {
            found.push(path);
        }
    }
}

/// Every source file over `most` code lines, with its count, largest first.
fn files_over(most: usize) -> Vec<(usize, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for folder in SOURCE_FOLDERS {
        rust_files(&root.join(folder), &mut files);
    }
    assert!(!files.is_empty(), "no source files found under {root:?}");
    let mut over: Vec<(usize, String)> = files
        .iter()
        .filter_map(|path| {
            let text = std::fs::read_to_string(path).expect("a readable source file");
            let n = code_lines(&text);
            let name = path
                .strip_prefix(root)
                .unwrap_or(path)
                .display()
                .to_string();
            (n > most).then_some((n, name))
        })
        .collect();
    over.sort_by(|a, b| b.cmp(a));
    over
}

#[test]
fn no_source_file_is_over_the_limit() {
    let over = files_over(MOST_CODE_LINES);
    let list: Vec<String> = over
        .iter()
        .map(|(n, name)| format!("  {name}: {n} code lines"))
        .collect();
    assert!(
        over.is_empty(),
        "{} source files hold more than {MOST_CODE_LINES} code lines; split each by idea:\n{}",
        over.len(),
        list.join("\n")
    );
}

#[test]
fn a_lower_limit_names_files() {
    // The walk finds the sources and the count is not stuck at zero.
    assert!(!files_over(50).is_empty());
}

#[test]
fn comments_blank_lines_and_test_items_are_not_code() {
    let text = r##"//! A module.

/// A function.
fn f() -> &'static str {
    /* a block
       comment */
    let s = "// not a comment { ";
    let r = r#"a raw "string" }"#;
    let c = '{';
    s // trailing comment
}

#[cfg(test)]
mod tests {
    fn g() -> char {
        '}'
    }
}

#[cfg(test)]
use std::fmt;

struct S;
"##;
    // `fn f`, `let s`, `let r`, `let c`, `s`, `}` and `struct S`.
    assert_eq!(code_lines(text), 7);
}
