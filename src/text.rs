//! How messages quote what a user gave: escaped and cut short, so that a file of
//! NUL bytes or a name with a newline cannot flood or split an error line.

/// Characters of a quoted value kept before it is cut.
pub const ECHO_CHARS: usize = 60;

/// `s` in double quotes with control characters (and quotes) escaped as Rust
/// escapes them. A value longer than [`ECHO_CHARS`] characters is cut and its
/// length in bytes follows.
///
/// ```
/// use rigfit::text::echo;
/// assert_eq!(echo("v2"), "\"v2\"");
/// assert_eq!(echo("a\nb"), "\"a\\nb\"");
/// let long = "x".repeat(1000);
/// assert_eq!(echo(&long), format!("\"{}\"… (1000 bytes)", "x".repeat(60)));
/// ```
pub fn echo(s: &str) -> String {
    match s.char_indices().nth(ECHO_CHARS) {
        None => format!("{s:?}"),
        Some((cut, _)) => format!("{:?}… ({} bytes)", &s[..cut], s.len()),
    }
}

/// Like [`echo`] without the quotes: for values embedded in a sentence.
pub fn echo_bare(s: &str) -> String {
    let quoted = echo(s);
    match quoted.strip_prefix('"') {
        Some(rest) => match rest.split_once("\"…") {
            Some((body, tail)) => format!("{body}…{tail}"),
            None => rest.strip_suffix('"').unwrap_or(rest).to_string(),
        },
        None => quoted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nul_bytes_are_escaped_and_cut() {
        let s = "\0".repeat(1 << 20);
        let e = echo(&s);
        assert!(e.len() < 400, "{}", e.len());
        assert!(e.contains("\\0") && e.contains("1048576 bytes"), "{e}");
    }

    #[test]
    fn bare_echo_drops_only_the_quotes() {
        assert_eq!(echo_bare("a\tb"), "a\\tb");
        let long = "y".repeat(70);
        assert_eq!(echo_bare(&long), format!("{}… (70 bytes)", "y".repeat(60)));
    }
}
