//! What a name and a unit in a rig file may be, and the nearest name for a
//! "did you mean".

/// The name of `names` nearest `name` (edit distance; the first in sorted
/// order of those as near), for a "did you mean".
pub(super) fn nearest<'n>(names: impl IntoIterator<Item = &'n str>, name: &str) -> Option<&'n str> {
    let mut names: Vec<&str> = names.into_iter().collect();
    names.sort_unstable();
    names
        .into_iter()
        .min_by_key(|n| strsim::levenshtein(n, name))
}

/// A name the generated code and every output file can carry as it is.
pub(super) fn ident(s: &str) -> bool {
    !s.is_empty()
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !s.starts_with(|c: char| c.is_ascii_digit())
}

/// Most characters a unit may have.
pub const MAX_UNIT_CHARS: usize = 24;

pub(super) const UNIT_EXPECTED: &str = "a unit of at most 24 characters: letters, digits, \
    '/', '*', '·', '^', '(', ')', '.', '_', '-', '%', '°' and spaces, starting \
    with a letter, a digit, '(', '%' or '°' (\"N\", \"m/s²\", \"N·s/m\")";

/// A unit a CSV header, a spreadsheet and a summary line show as it is: no
/// separators, quotes or line breaks, no formula's leading `=`, `+`, `-`, `@`.
pub(super) fn unit_text(s: &str) -> bool {
    s.chars().count() <= MAX_UNIT_CHARS
        && s.chars()
            .all(|c| c.is_alphanumeric() || "/*·^()._-%° ".contains(c))
        && s.chars()
            .next()
            .is_none_or(|c| c.is_alphanumeric() || "(%°".contains(c))
}
