//! Why a campaign was refused. Every message is one line that starts with the
//! campaign file, then the JSON path (or the data file and line), then what was
//! expected and what was found.

use std::path::{Path, PathBuf};

use crate::base::data::DataError;

/// A campaign (or parameter file) that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CampaignError {
    /// The file could not be read.
    #[error("{}: cannot read: {message}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// The system's reason.
        message: String,
    },
    /// The text is not JSON.
    #[error("{}:{line}:{column}: malformed JSON: {message}", file.display())]
    Syntax {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde_json's description.
        message: String,
    },
    /// Valid JSON of the wrong shape: a wrong type, an unknown or missing key.
    #[error("{}:{line}:{column}: {path}: {message}", file.display())]
    Schema {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// JSON path of the offending value (`experiments[0].fit_window`).
        path: String,
        /// serde's description (names the expected type or keys).
        message: String,
    },
    /// A well-formed value that is out of range or inconsistent.
    #[error("{}: {path}: expected {expected}, found {found}", file.display())]
    Invalid {
        /// The file.
        file: PathBuf,
        /// JSON path of the offending value.
        path: String,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// A parameter name the model does not have.
    #[error("{}: {path}: unknown parameter '{name}' for rig {model}{hint}", file.display())]
    UnknownParam {
        /// The file.
        file: PathBuf,
        /// JSON path of the key.
        path: String,
        /// The unknown name.
        name: String,
        /// The model id.
        model: String,
        /// A suggestion (starts with `; `) or empty.
        hint: String,
    },
    /// Parameters without a model default that nobody set.
    #[error(
        "{}: {path}: missing parameter(s) without a model default: {}",
        file.display(),
        names.join(", ")
    )]
    MissingParams {
        /// The file.
        file: PathBuf,
        /// Where they should be set.
        path: String,
        /// Their names.
        names: Vec<String>,
    },
    /// A rig-scope parameter set inside an experiment.
    #[error(
        "{}: {path}: rig parameter '{name}' must be set in the campaign's top-level params",
        file.display()
    )]
    RigParamInExperiment {
        /// The file.
        file: PathBuf,
        /// JSON path of the key.
        path: String,
        /// The parameter.
        name: String,
    },
    /// A measured-data file was refused.
    #[error("{}: {path}: {source}", file.display())]
    Data {
        /// The campaign file.
        file: PathBuf,
        /// JSON path of the experiment's `data` object.
        path: String,
        /// What is wrong with the data file.
        source: Box<DataError>,
    },
    /// The RK4 step cannot be stable for the parameter bounds.
    #[error("{}: {path}: {message}", file.display())]
    Unstable {
        /// The file.
        file: PathBuf,
        /// `solver.substeps`.
        path: String,
        /// The limiting experiment and parameter and a substeps count that works.
        message: String,
    },
    /// One candidate's runs would take too many RK4 steps.
    #[error("{}: {path}: {message}", file.display())]
    TooLong {
        /// The file.
        file: PathBuf,
        /// The experiment that takes longest.
        path: String,
        /// The estimate and the limit.
        message: String,
    },
    /// `run` needs at least one free parameter.
    #[error(
        "{}: params: expected at least one free parameter ({{\"min\", \"max\"}}) to search, \
         found none",
        file.display()
    )]
    NoFreeParameters {
        /// The file.
        file: PathBuf,
    },
}

/// Builds [`CampaignError::Invalid`].
pub(crate) fn invalid(
    file: &Path,
    path: impl Into<String>,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> CampaignError {
    CampaignError::Invalid {
        file: file.to_path_buf(),
        path: path.into(),
        expected: expected.into(),
        found: found.into(),
    }
}

/// Parses JSON into `T`, mapping serde errors to [`CampaignError::Syntax`] or
/// [`CampaignError::Schema`] with the JSON path.
pub(crate) fn parse_json<T: serde::de::DeserializeOwned>(
    text: &str,
    file: &Path,
) -> Result<T, CampaignError> {
    // A byte-order mark, as editors on some systems write it, is not content.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some((at, c)) = text.char_indices().find(|(_, c)| !c.is_whitespace())
        && c != '{'
    {
        let (line, column) = line_column(text, at);
        let found = crate::base::text::echo(&text[at..].chars().take(20).collect::<String>());
        return Err(CampaignError::Schema {
            file: file.to_path_buf(),
            line,
            column,
            path: "(top level)".into(),
            message: format!("expected a JSON object {{…}}, found {found}"),
        });
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = json_path(e.path());
        json_error(file, path, e.into_inner())
    })?;
    // Anything after the first value (a bad merge's second object) is an error,
    // not something to ignore.
    de.end().map_err(|e| json_error(file, String::new(), e))?;
    Ok(value)
}

/// A JSON path as `experiments[0].params.k1`; a key that is not a short plain
/// name is quoted, escaped and cut short (see [`crate::base::text::echo`]).
fn json_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for segment in path.iter() {
        match segment {
            Segment::Seq { index } => out.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !out.is_empty() {
                    out.push('.');
                }
                let plain = key.len() <= crate::base::text::ECHO_CHARS
                    && !key.is_empty()
                    && !key
                        .chars()
                        .any(|c| c.is_control() || c.is_whitespace() || matches!(c, '"' | '`'));
                if plain {
                    out.push_str(key);
                } else {
                    out.push_str(&crate::base::text::echo(key));
                }
            }
            Segment::Unknown => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push('?');
            }
        }
    }
    if out.is_empty() { ".".into() } else { out }
}

/// serde's Rust type names in "expected …" said in JSON's words: `struct
/// RawWindow` is an object, `usize` a whole number.
fn plain_types(message: &str) -> String {
    let Some((head, expected)) = message.rsplit_once("expected ") else {
        return message.to_string();
    };
    let plain = match expected {
        "usize" | "u64" | "u32" | "u16" | "u8" => "a whole number ≥ 0",
        "isize" | "i64" | "i32" => "a whole number",
        "f64" | "f32" => "a number",
        "a boolean" | "bool" => "true or false",
        s if s
            .strip_prefix("struct ")
            .is_some_and(|name| !name.contains(' ')) =>
        {
            "a JSON object {…}"
        }
        _ => return message.to_string(),
    };
    format!("{head}expected {plain}")
}

fn json_error(file: &Path, path: String, inner: serde_json::Error) -> CampaignError {
    let (line, column) = (inner.line(), inner.column());
    let full = inner.to_string();
    let suffix = format!(" at line {line} column {column}");
    // serde quotes values and keys whole: cut them as every echo is cut.
    let mut message = plain_types(&crate::base::text::shorten_quotes(
        full.strip_suffix(&suffix).unwrap_or(&full),
        crate::base::text::ECHO_CHARS,
    ));
    if message == "trailing characters" {
        message = "expected the end of the file after the JSON object, found more text".into();
    }
    if inner.is_syntax() || inner.is_eof() {
        CampaignError::Syntax {
            file: file.to_path_buf(),
            line,
            column,
            message,
        }
    } else {
        CampaignError::Schema {
            file: file.to_path_buf(),
            line,
            column,
            path,
            message,
        }
    }
}

/// 1-based line and column of byte `at` in `text`.
fn line_column(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}
