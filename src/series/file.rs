//! The series file: what a series runs, read and checked before any work.
//!
//! ```json
//! {
//!   "name": "aa2024-rates",
//!   "campaign": "aa2024_t3_synthetic.json",
//!   "tests": "tests.csv",
//!   "search": {"generations": 120},
//!   "output": "results/aa2024-rates"
//! }
//! ```
//!
//! or, for a list of campaigns, `"campaigns": ["a.json", "more/*.json"]`
//! in place of `"campaign"` and `"tests"`. Paths are relative to the series
//! file's folder; a `*` or `?` in a campaign's file name matches as a shell
//! would (in the last part of the path only).

use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_json::{Map, Value};

use super::SeriesError;
use super::table::{TestRow, read_table};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSeries {
    name: String,
    description: Option<String>,
    campaign: Option<PathBuf>,
    tests: Option<PathBuf>,
    campaigns: Option<Vec<PathBuf>>,
    search: Option<Map<String, Value>>,
    output: Option<PathBuf>,
}

/// Where a series' tests come from.
#[derive(Debug, Clone, PartialEq)]
pub enum SeriesSource {
    /// One campaign and a table of tests.
    Table {
        /// The campaign every test starts from (absolute).
        campaign: PathBuf,
        /// The table (absolute).
        table: PathBuf,
        /// Its covariate columns, in order.
        covariates: Vec<String>,
        /// Its rows.
        rows: Vec<TestRow>,
    },
    /// A list of campaigns, each one test (absolute, in the list's order, a
    /// pattern's matches sorted).
    Campaigns(Vec<PathBuf>),
}

/// A series file, read and checked.
#[derive(Debug, Clone, PartialEq)]
pub struct SeriesFile {
    /// The file (absolute).
    pub path: PathBuf,
    /// `"name"`: names the default output folder; letters, digits, `.`,
    /// `_` and `-`.
    pub name: String,
    /// `"description"`: free text.
    pub description: Option<String>,
    /// The tests.
    pub source: SeriesSource,
    /// `"search"`: keys set in every test's campaign `"search"` (its
    /// `population`, `generations`, …), over the campaign's own.
    pub search: Map<String, Value>,
    /// `"output"`: the series' folder (default `results/<name>` beside the
    /// file), absolute.
    pub output: PathBuf,
}

impl SeriesFile {
    /// Reads and checks a series file: its keys, its table, its campaigns'
    /// existence.
    pub fn load(path: &Path) -> Result<SeriesFile, SeriesError> {
        let text =
            crate::base::fsutil::read_description(path).map_err(|e| SeriesError::io(path, e))?;
        let path = absolute(path);
        let dir = path.parent().unwrap_or(Path::new("/")).to_path_buf();
        let de = &mut serde_json::Deserializer::from_str(&text);
        let raw: RawSeries = serde_path_to_error::deserialize(de).map_err(|e| {
            let place = match e.path().to_string() {
                p if p == "." => "(file)".to_string(),
                p => p,
            };
            SeriesError::input(&path, place, e.inner().to_string())
        })?;
        check_name(&raw.name).map_err(|r| SeriesError::input(&path, "name", r))?;
        let source = match (raw.campaign, raw.tests, raw.campaigns) {
            (Some(campaign), Some(table), None) => {
                let campaign = existing(&path, "campaign", &dir.join(campaign))?;
                let table = existing(&path, "tests", &dir.join(table))?;
                let (covariates, rows) = read_table(&table)?;
                SeriesSource::Table {
                    campaign,
                    table,
                    covariates,
                    rows,
                }
            }
            (None, None, Some(list)) => {
                let mut files = Vec::new();
                for (i, pattern) in list.iter().enumerate() {
                    let found = expand(&dir.join(pattern))
                        .map_err(|r| SeriesError::input(&path, format!("campaigns[{i}]"), r))?;
                    files.extend(found);
                }
                if files.is_empty() {
                    return Err(SeriesError::input(
                        &path,
                        "campaigns",
                        "the list is empty; expected at least one campaign file",
                    ));
                }
                SeriesSource::Campaigns(files)
            }
            (Some(_), None, None) => {
                return Err(SeriesError::input(
                    &path,
                    "tests",
                    "\"campaign\" needs \"tests\": the table of tests (a CSV file)",
                ));
            }
            (None, Some(_), None) => {
                return Err(SeriesError::input(
                    &path,
                    "campaign",
                    "\"tests\" needs \"campaign\": the campaign every test starts from",
                ));
            }
            (None, None, None) => {
                return Err(SeriesError::input(
                    &path,
                    "(file)",
                    "expected \"campaign\" and \"tests\" (one campaign, a table of tests) or \"campaigns\" (a list of campaign files)",
                ));
            }
            _ => {
                return Err(SeriesError::input(
                    &path,
                    "campaigns",
                    "give either \"campaign\" and \"tests\" or \"campaigns\", not both",
                ));
            }
        };
        let output = match raw.output {
            Some(o) => dir.join(o),
            None => dir.join("results").join(&raw.name),
        };
        Ok(SeriesFile {
            path,
            name: raw.name,
            description: raw.description,
            source,
            search: raw.search.unwrap_or_default(),
            output,
        })
    }
}

/// A name that can name a folder and a file: letters, digits, `.`, `_`,
/// `-`, not starting with `.`, at most 100 characters.
pub(crate) fn check_name(name: &str) -> Result<(), String> {
    let ok = !name.is_empty()
        && name.len() <= 100
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'));
    if ok {
        Ok(())
    } else {
        Err(format!(
            "expected a name of letters, digits, '.', '_' and '-' (not starting with '.', at most 100 characters), found {}",
            crate::base::text::echo(name)
        ))
    }
}

/// `path` made absolute against the working folder, `.` and `..` kept.
pub(crate) fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

fn existing(file: &Path, key: &str, path: &Path) -> Result<PathBuf, SeriesError> {
    if path.is_file() {
        Ok(absolute(path))
    } else {
        Err(SeriesError::input(
            file,
            key,
            format!("`{}` is not a file", path.display()),
        ))
    }
}

/// The files a path names: itself, or where its last part holds `*` or `?`,
/// the files of its folder that match, sorted.
fn expand(path: &Path) -> Result<Vec<PathBuf>, String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if !name.contains(['*', '?']) {
        return if path.is_file() {
            Ok(vec![absolute(path)])
        } else {
            Err(format!("`{}` is not a file", path.display()))
        };
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    if dir.to_string_lossy().contains(['*', '?']) {
        return Err("a pattern may hold '*' and '?' in its file name only".into());
    }
    let entries = std::fs::read_dir(dir).map_err(|e| format!("`{}`: {e}", dir.display()))?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter(|e| matches(name.as_bytes(), e.file_name().to_string_lossy().as_bytes()))
        .map(|e| absolute(&e.path()))
        .collect();
    found.sort();
    if found.is_empty() {
        return Err(format!("`{}` matches no file", path.display()));
    }
    Ok(found)
}

/// Whether `name` matches `pattern` (`*` any run, `?` one character).
fn matches(pattern: &[u8], name: &[u8]) -> bool {
    match (pattern.first(), name.first()) {
        (None, None) => true,
        (Some(b'*'), _) => {
            matches(&pattern[1..], name) || (!name.is_empty() && matches(pattern, &name[1..]))
        }
        (Some(b'?'), Some(_)) => matches(&pattern[1..], &name[1..]),
        (Some(p), Some(n)) if p == n => matches(&pattern[1..], &name[1..]),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_match_as_a_shell_would() {
        assert!(matches(b"*.json", b"a.json"));
        assert!(matches(b"rate_?.json", b"rate_1.json"));
        assert!(!matches(b"rate_?.json", b"rate_10.json"));
        assert!(!matches(b"*.json", b"a.csv"));
        assert!(matches(b"*", b""));
    }

    #[test]
    fn names_that_cannot_name_a_folder_are_refused() {
        assert!(check_name("t01_2mps").is_ok());
        for bad in ["", ".hidden", "a/b", "a b", "ü"] {
            assert!(check_name(bad).is_err(), "{bad}");
        }
    }
}
