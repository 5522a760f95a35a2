//! Names that become file names: the campaign's (its default output folder) and
//! each experiment's (`<experiment>.csv`, `fit_<experiment>.svg`). They are
//! checked before any work so that a job never fails at its end on a name the
//! file system refuses, and never writes two outputs to one file.

use std::path::Path;

use super::CampaignError;
use super::error::invalid;
use crate::base::text::echo;

/// Longest campaign or experiment name, in characters. Output file names add at
/// most 8 bytes to it, far below the 255 bytes most file systems allow.
pub const MAX_NAME_CHARS: usize = 100;

/// Output file stems that the job itself uses (compared case-insensitively).
const RESERVED_STEMS: [(&str, &str); 1] = [("history", "the search history, history.csv")];

/// The file-safe stem of an experiment's output files: ASCII letters, digits,
/// `-` and `_` kept, everything else `_`.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Checks what every name needs: non-empty, at most [`MAX_NAME_CHARS`]
/// characters, no control characters, not `.` or `..`, none of `forbidden`
/// (which `expected` lists).
fn check_name(
    file: &Path,
    path: &str,
    name: &str,
    forbidden: &[char],
    expected: &str,
) -> Result<(), CampaignError> {
    let chars = name.chars().count();
    let bad = name.trim().is_empty()
        || name == "."
        || name == ".."
        || name.chars().any(char::is_control)
        || name.contains(forbidden)
        || chars > MAX_NAME_CHARS;
    if bad {
        let expected = format!("{expected}, at most {MAX_NAME_CHARS} characters, not '.' or '..'");
        let found = format!("{} ({chars} characters)", echo(name));
        return Err(invalid(file, path, expected, found));
    }
    Ok(())
}

/// The campaign's name.
pub(crate) fn check_campaign_name(file: &Path, name: &str) -> Result<(), CampaignError> {
    check_name(
        file,
        "name",
        name,
        &['/', '\\'],
        "a non-empty name without '/', '\\' or control characters",
    )
}

/// Every experiment's name, and that no two of them (nor one and the job's own
/// files) write the same output file, even on a case-insensitive file system.
pub(crate) fn check_experiment_names(file: &Path, names: &[&str]) -> Result<(), CampaignError> {
    let mut seen: Vec<(String, usize)> = Vec::new();
    for (e, name) in names.iter().enumerate() {
        let path = format!("experiments[{e}].name");
        check_name(
            file,
            &path,
            name,
            &['.'],
            "a non-empty name without '.' or control characters",
        )?;
        let stem = file_stem(name);
        let key = stem.to_ascii_lowercase();
        if let Some((_, what)) = RESERVED_STEMS.iter().find(|(s, _)| *s == key) {
            let found = format!("{}, whose {stem}.csv would replace {what}", echo(name));
            return Err(invalid(
                file,
                path,
                "a name whose output files differ from the job's own",
                found,
            ));
        }
        if let Some((_, other)) = seen.iter().find(|(k, _)| *k == key) {
            let found = format!(
                "{}, whose output {stem}.csv is also that of experiments[{other}] {} \
                 (names map to ASCII letters, digits, '-' and '_', compared without case)",
                echo(name),
                echo(names[*other])
            );
            return Err(invalid(
                file,
                path,
                "a unique experiment name whose output files differ from every other's",
                found,
            ));
        }
        seen.push((key, e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Result<(), CampaignError> {
        check_experiment_names(Path::new("c.json"), list)
    }

    #[test]
    fn distinct_names_pass() {
        names(&["v2", "v3", "a-b", "a_c"]).unwrap();
    }

    #[test]
    fn names_that_map_to_one_file_are_refused_with_both() {
        for (a, b) in [("a/b", "a_b"), ("V2", "v2"), ("versuch_µ", "versuch_ä")] {
            let msg = names(&[a, b]).unwrap_err().to_string();
            assert!(msg.contains("experiments[1].name"), "{msg}");
            assert!(msg.contains(&format!("{a:?}")), "{msg}");
            assert!(msg.contains(&format!("{b:?}")), "{msg}");
        }
    }

    #[test]
    fn the_history_stem_is_reserved() {
        for n in ["history", "History"] {
            let msg = names(&["v2", n]).unwrap_err().to_string();
            assert!(msg.contains("history.csv"), "{msg}");
        }
    }

    #[test]
    fn long_dot_and_control_names_are_refused() {
        let long = "v".repeat(MAX_NAME_CHARS + 1);
        for n in [long.as_str(), ".", "..", "a\nb", ""] {
            assert!(names(&[n]).is_err(), "{n:?} accepted");
        }
        names(&["v".repeat(MAX_NAME_CHARS).as_str()]).unwrap();
        for n in [".", "..", "a\u{7}", "a/b"] {
            assert!(
                check_campaign_name(Path::new("c.json"), n).is_err(),
                "{n:?}"
            );
        }
    }
}
