//! How messages quote what a user gave: escaped and cut short, so that a file of
//! NUL bytes or a name with a newline cannot flood or split an error line.

/// Characters of a quoted value kept before it is cut.
pub const ECHO_CHARS: usize = 60;

/// `s` in double quotes with control characters (and quotes) escaped as Rust
/// escapes them. A value longer than [`ECHO_CHARS`] characters is cut and its
/// length in bytes follows.
///
/// ```
/// use rigfit::base::text::echo;
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

/// A number as a message shows it: at most six significant digits, in
/// plain notation from 1e-4 to 1e6 and in exponent notation outside, so that
/// a value of 1e300 reads `1e300`, not three hundred digits.
///
/// ```
/// use rigfit::base::text::number;
/// assert_eq!(number(2.5e303), "2.5e303");
/// assert_eq!(number(2.5e-303), "2.5e-303");
/// assert_eq!(number(0.0025000000000000002), "0.0025");
/// assert_eq!(number(-2.0), "-2");
/// assert_eq!(number(123456.7), "123457");
/// assert_eq!(number(1234567.0), "1.23457e6");
/// assert_eq!(number(0.0), "0");
/// assert_eq!(number(f64::INFINITY), "inf");
/// ```
pub fn number(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x == 0.0 {
        return "0".into();
    }
    let trim = |m: &str| -> String {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    let a = x.abs();
    // Rounded to six digits first, so that 999999.7 counts as 1e6.
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if (1e-4..1e6).contains(&rounded.abs()) && (1e-4..1e6).contains(&a) {
        let decimals = (5 - rounded.abs().log10().floor() as i32).max(0) as usize;
        trim(&format!("{rounded:.decimals$}"))
    } else {
        let e = format!("{x:.5e}");
        let (m, exp) = e.split_once('e').unwrap_or((&e, "0"));
        format!("{}e{exp}", trim(m))
    }
}

/// `"1 RK4 step per sample"` or `"n RK4 steps per sample"`.
///
/// ```
/// use rigfit::base::text::steps_per_sample;
/// assert_eq!(steps_per_sample(1), "1 RK4 step per sample");
/// assert_eq!(steps_per_sample(3), "3 RK4 steps per sample");
/// ```
pub fn steps_per_sample(n: usize) -> String {
    let s = if n == 1 { "" } else { "s" };
    format!("{n} RK4 step{s} per sample")
}

/// `message` with every quoted run (between backticks or double quotes)
/// longer than `max` characters cut to `max`, its length in bytes after the
/// closing quote, and control characters inside quotes escaped; an unquoted
/// word longer than four times `max` is cut the same way. For messages of
/// other libraries (serde's "unknown variant `…`") that quote input whole.
///
/// ```
/// use rigfit::base::text::shorten_quotes;
/// let m = format!("unknown variant `{}`, expected `cpu`", "Z".repeat(500));
/// assert_eq!(
///     shorten_quotes(&m, 4),
///     "unknown variant `ZZZZ…` (500 bytes), expected `cpu`"
/// );
/// assert_eq!(shorten_quotes("a \"b\\\"c\" d", 10), "a \"b\\\"c\" d");
/// ```
pub fn shorten_quotes(message: &str, max: usize) -> String {
    let mut out = String::with_capacity(message.len().min(16 * max));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let (before, from) = rest.split_at(open);
        out.push_str(&shorten_words(before, 4 * max));
        let quote = from.chars().next().expect("found above");
        let body = &from[1..];
        let Some(close) = closing(body, quote) else {
            // An unpaired quote: the rest is plain text.
            out.push(quote);
            rest = body;
            continue;
        };
        let inner = &body[..close];
        out.push(quote);
        let escaped = |s: &str| -> String {
            s.chars()
                .flat_map(|c| {
                    let e: Vec<char> = if c.is_control() {
                        c.escape_default().collect()
                    } else {
                        vec![c]
                    };
                    e
                })
                .collect()
        };
        match inner.char_indices().nth(max) {
            None => {
                out.push_str(&escaped(inner));
                out.push(quote);
            }
            Some((cut, _)) => {
                out.push_str(&escaped(&inner[..cut]));
                out.push('…');
                out.push(quote);
                out.push_str(&format!(" ({} bytes)", inner.len()));
            }
        }
        rest = &body[close + 1..];
    }
    out.push_str(&shorten_words(rest, 4 * max));
    out
}

/// Byte index in `body` of the quote that closes a run opened by `quote`;
/// inside double quotes a backslash escapes the next character (Rust's and
/// JSON's string escapes).
fn closing(body: &str, quote: char) -> Option<usize> {
    let mut escaped = false;
    for (i, c) in body.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if quote == '"' => escaped = true,
            c if c == quote => return Some(i),
            _ => {}
        }
    }
    None
}

/// `text` with each whitespace-separated word longer than `max` characters
/// cut, its length in bytes after it.
fn shorten_words(text: &str, max: usize) -> String {
    if text.len() <= max {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len().min(16 * max));
    for (i, word) in text.split(' ').enumerate() {
        if i > 0 {
            out.push(' ');
        }
        match word.char_indices().nth(max) {
            None => out.push_str(word),
            Some((cut, _)) => out.push_str(&format!("{}… ({} bytes)", &word[..cut], word.len())),
        }
    }
    out
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
    fn long_quoted_runs_and_words_are_cut_short_ones_kept() {
        let z = "Z".repeat(5000);
        let m = format!("invalid type: string \"{z}\", expected a number");
        let s = shorten_quotes(&m, ECHO_CHARS);
        assert!(s.len() < 200, "{s}");
        assert!(s.ends_with("…\" (5000 bytes), expected a number"), "{s}");
        let m = format!("unknown field `a\nb`, found {z}");
        let s = shorten_quotes(&m, ECHO_CHARS);
        assert!(s.starts_with("unknown field `a\\nb`, found ZZZ"), "{s}");
        assert!(s.ends_with("… (5000 bytes)"), "{s}");
        let plain = "file `out/v2.csv` exists; the \"a\" key's value";
        assert_eq!(shorten_quotes(plain, ECHO_CHARS), plain);
        assert_eq!(
            shorten_quotes("an `unpaired quote", 3),
            "an `unpaired quote"
        );
    }

    #[test]
    fn bare_echo_drops_only_the_quotes() {
        assert_eq!(echo_bare("a\tb"), "a\\tb");
        let long = "y".repeat(70);
        assert_eq!(echo_bare(&long), format!("{}… (70 bytes)", "y".repeat(60)));
    }
}
