//! The character encodings a measured record's text may come in, and the one
//! decoder every text reader of the crate goes through.
//!
//! Spreadsheets on Windows save "CSV" in Windows-1252 (Latin-1 text is read
//! as Windows-1252, its superset for text), "Unicode text" as UTF-16 with a
//! byte-order mark, and "CSV UTF-8" as UTF-8, often with a byte-order mark.
//! Detection ([`decode`] without a stated encoding): a UTF-8 byte-order mark
//! reads UTF-8, a UTF-16 one UTF-16 in its byte order, bytes that are valid
//! UTF-8 read UTF-8, and anything else Windows-1252 (which maps every byte).
//! A byte-order mark is never part of the text.

use std::fmt;
use std::str::FromStr;

/// A text encoding of a measured record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// UTF-8 (a leading byte-order mark is dropped).
    Utf8,
    /// UTF-16, little-endian (the byte order of Windows' "Unicode text").
    Utf16Le,
    /// UTF-16, big-endian.
    Utf16Be,
    /// Windows-1252, the superset of Latin-1 (ISO-8859-1) for text.
    Windows1252,
}

/// The names [`Encoding::from_str`] accepts (any case), as messages list them.
pub const ENCODING_NAMES: &str =
    "utf-8, utf-16, utf-16le, utf-16be, latin-1, iso-8859-1, windows-1252, cp1252";

impl Encoding {
    /// The encoding's name as messages give it.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Utf8 => "UTF-8",
            Encoding::Utf16Le => "UTF-16LE",
            Encoding::Utf16Be => "UTF-16BE",
            Encoding::Windows1252 => "Windows-1252",
        }
    }
}

impl fmt::Display for Encoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An encoding name that is none of [`ENCODING_NAMES`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("expected an encoding, one of {ENCODING_NAMES} (any case), found '{}'", crate::base::text::echo_bare(.found))]
pub struct EncodingNameError {
    /// The name given.
    pub found: String,
}

impl FromStr for Encoding {
    type Err = EncodingNameError;

    /// `utf-8`, `utf-16` (little-endian unless a byte-order mark says
    /// otherwise), `utf-16le`, `utf-16be`, and `latin-1`, `iso-8859-1`,
    /// `windows-1252`, `cp1252` (all read as Windows-1252); any case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "utf-8" | "utf8" => Ok(Encoding::Utf8),
            "utf-16" | "utf-16le" => Ok(Encoding::Utf16Le),
            "utf-16be" => Ok(Encoding::Utf16Be),
            "latin-1" | "iso-8859-1" | "windows-1252" | "cp1252" => Ok(Encoding::Windows1252),
            _ => Err(EncodingNameError {
                found: s.to_string(),
            }),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Encoding {
    /// A string, one of [`ENCODING_NAMES`].
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// Bytes that contradict the stated encoding (or a UTF-16 byte-order mark).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("at byte {offset}: expected {expected}, found {found}")]
pub struct DecodeError {
    /// 0-based byte offset of the first byte that does not fit.
    pub offset: usize,
    /// What was expected there.
    pub expected: String,
    /// What was found there.
    pub found: String,
}

const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";
const UTF16LE_BOM: &[u8] = b"\xFF\xFE";
const UTF16BE_BOM: &[u8] = b"\xFE\xFF";

/// The text of `bytes` and the encoding it was read in: `stated`, or the one
/// detected (see the module docs) when `None`. A stated UTF-16 follows a
/// byte-order mark's byte order.
///
/// # Errors
/// [`DecodeError`] naming the byte offset where the bytes contradict the
/// encoding: stated UTF-8 but invalid, UTF-16 of odd length or with an unpaired
/// surrogate, a byte-order mark of another encoding than the stated one.
pub fn decode(bytes: &[u8], stated: Option<Encoding>) -> Result<(String, Encoding), DecodeError> {
    let bom = if bytes.starts_with(UTF8_BOM) {
        Some(Encoding::Utf8)
    } else if bytes.starts_with(UTF16LE_BOM) {
        Some(Encoding::Utf16Le)
    } else if bytes.starts_with(UTF16BE_BOM) {
        Some(Encoding::Utf16Be)
    } else {
        None
    };
    let utf16 = |e: Option<Encoding>| matches!(e, Some(Encoding::Utf16Le | Encoding::Utf16Be));
    let encoding = match (stated, bom) {
        (Some(s), Some(b)) if s == b || utf16(Some(s)) && utf16(Some(b)) => b,
        (Some(s), Some(b)) => {
            return Err(DecodeError {
                offset: 0,
                expected: format!("{s} text (the stated encoding)"),
                found: format!("a {b} byte-order mark"),
            });
        }
        (Some(s), None) => s,
        (None, Some(b)) => b,
        (None, None) if std::str::from_utf8(bytes).is_ok() => Encoding::Utf8,
        (None, None) => Encoding::Windows1252,
    };
    let skip = match bom {
        Some(Encoding::Utf8) => UTF8_BOM.len(),
        Some(_) => UTF16LE_BOM.len(),
        None => 0,
    };
    let body = bytes.get(skip..).unwrap_or_default();
    let text = match encoding {
        Encoding::Utf8 => utf8(body, skip)?,
        Encoding::Utf16Le => utf16_text(body, skip, u16::from_le_bytes, encoding)?,
        Encoding::Utf16Be => utf16_text(body, skip, u16::from_be_bytes, encoding)?,
        Encoding::Windows1252 => body.iter().map(|&b| windows_1252(b)).collect(),
    };
    Ok((text, encoding))
}

/// `body` as UTF-8; `skip` bytes (a byte-order mark) came before it.
fn utf8(body: &[u8], skip: usize) -> Result<String, DecodeError> {
    match std::str::from_utf8(body) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let at = e.valid_up_to();
            let found = body
                .get(at..)
                .unwrap_or_default()
                .iter()
                .take(4)
                .map(|b| format!("{b:#04X}"))
                .collect::<Vec<_>>()
                .join(" ");
            Err(DecodeError {
                offset: skip + at,
                expected: "UTF-8 text (the stated encoding)".into(),
                found: format!("the bytes {found}, not UTF-8"),
            })
        }
    }
}

/// `body` as UTF-16 whose code units `unit` reads; `skip` bytes (a byte-order
/// mark) came before it.
fn utf16_text(
    body: &[u8],
    skip: usize,
    unit: fn([u8; 2]) -> u16,
    encoding: Encoding,
) -> Result<String, DecodeError> {
    if !body.len().is_multiple_of(2) {
        return Err(DecodeError {
            offset: skip + body.len() - 1,
            expected: format!("{encoding} text, an even number of bytes"),
            found: format!("{} bytes, a lone last byte", skip + body.len()),
        });
    }
    let (pairs, _) = body.as_chunks::<2>();
    let units = pairs.iter().map(|&p| unit(p));
    let mut text = String::with_capacity(body.len() / 2);
    let mut at = 0;
    for c in char::decode_utf16(units) {
        match c {
            Ok(c) => {
                text.push(c);
                at += c.len_utf16();
            }
            Err(e) => {
                return Err(DecodeError {
                    offset: skip + 2 * at,
                    expected: format!("{encoding} text, surrogates in pairs"),
                    found: format!("the unpaired surrogate {:#06X}", e.unpaired_surrogate()),
                });
            }
        }
    }
    Ok(text)
}

/// The character of Windows-1252 byte `b`: Latin-1's for every byte but
/// 0x80–0x9F, where Windows-1252 places printable characters; its five unused
/// bytes there (0x81, 0x8D, 0x8F, 0x90, 0x9D) keep Latin-1's code points.
fn windows_1252(b: u8) -> char {
    const HIGH: [char; 32] = [
        '\u{20AC}', '\u{0081}', '\u{201A}', '\u{0192}', '\u{201E}', '\u{2026}', '\u{2020}',
        '\u{2021}', '\u{02C6}', '\u{2030}', '\u{0160}', '\u{2039}', '\u{0152}', '\u{008D}',
        '\u{017D}', '\u{008F}', '\u{0090}', '\u{2018}', '\u{2019}', '\u{201C}', '\u{201D}',
        '\u{2022}', '\u{2013}', '\u{2014}', '\u{02DC}', '\u{2122}', '\u{0161}', '\u{203A}',
        '\u{0153}', '\u{009D}', '\u{017E}', '\u{0178}',
    ];
    match b {
        0x80..=0x9F => HIGH
            .get(usize::from(b - 0x80))
            .copied()
            .unwrap_or('\u{FFFD}'),
        _ => char::from(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_in_any_case_and_an_unknown_one_lists_them() {
        for (name, e) in [
            ("UTF-8", Encoding::Utf8),
            ("utf-16", Encoding::Utf16Le),
            ("UTF-16LE", Encoding::Utf16Le),
            ("utf-16be", Encoding::Utf16Be),
            ("Latin-1", Encoding::Windows1252),
            ("ISO-8859-1", Encoding::Windows1252),
            ("windows-1252", Encoding::Windows1252),
            ("CP1252", Encoding::Windows1252),
        ] {
            assert_eq!(name.parse::<Encoding>(), Ok(e), "{name}");
        }
        let e = "ascii7".parse::<Encoding>().unwrap_err().to_string();
        assert!(e.contains(ENCODING_NAMES) && e.contains("'ascii7'"), "{e}");
    }

    #[test]
    fn detection_reads_boms_then_utf8_then_windows_1252() {
        assert_eq!(
            decode(b"\xEF\xBB\xBFt,F", None),
            Ok(("t,F".into(), Encoding::Utf8))
        );
        assert_eq!(
            decode(b"\xFF\xFEt\0,\0\xB5\0", None),
            Ok(("t,µ".into(), Encoding::Utf16Le))
        );
        assert_eq!(
            decode(b"\xFE\xFF\0t\0,\x20\xAC", None),
            Ok(("t,€".into(), Encoding::Utf16Be))
        );
        assert_eq!(
            decode("a [m/s²]".as_bytes(), None),
            Ok(("a [m/s²]".into(), Encoding::Utf8))
        );
        assert_eq!(
            decode(b"a [m/s\xB2],Weg [\xB5m]", None),
            Ok(("a [m/s²],Weg [µm]".into(), Encoding::Windows1252))
        );
    }

    #[test]
    fn windows_1252_maps_its_high_block_and_keeps_latin_1_for_unused_bytes() {
        let (text, e) = decode(b"\x80\x81\x8D\x8F\x90\x9D\x9F\xFF", None).unwrap();
        assert_eq!(e, Encoding::Windows1252);
        assert_eq!(text, "€\u{81}\u{8D}\u{8F}\u{90}\u{9D}Ÿÿ");
        let all: Vec<u8> = (0..=255).collect();
        let (text, _) = decode(&all, Some(Encoding::Windows1252)).unwrap();
        assert_eq!(text.chars().count(), 256);
        assert!(!text.contains('\u{FFFD}'));
    }

    #[test]
    fn a_stated_encoding_wins_over_detection() {
        assert_eq!(
            decode("µ".as_bytes(), Some(Encoding::Windows1252)),
            Ok(("Âµ".into(), Encoding::Windows1252))
        );
        assert_eq!(
            decode(b"t\0", Some(Encoding::Utf16Le)),
            Ok(("t".into(), Encoding::Utf16Le))
        );
        // A byte-order mark sets a stated UTF-16's byte order.
        assert_eq!(
            decode(b"\xFE\xFF\0t", Some(Encoding::Utf16Le)),
            Ok(("t".into(), Encoding::Utf16Be))
        );
    }

    #[test]
    fn stated_utf8_contradicted_names_the_offset() {
        let e = decode(b"t,F\n0,\xB5", Some(Encoding::Utf8)).unwrap_err();
        assert_eq!(e.offset, 6);
        assert!(e.found.contains("0xB5"), "{e}");
        let e = decode(b"\xEF\xBB\xBF\xFF", Some(Encoding::Utf8)).unwrap_err();
        assert_eq!(e.offset, 3, "{e}");
    }

    #[test]
    fn utf16_of_odd_length_or_with_a_lone_surrogate_is_refused() {
        let e = decode(b"\xFF\xFEt\0,", None).unwrap_err();
        assert_eq!(e.offset, 4, "{e}");
        assert!(e.expected.contains("even"), "{e}");
        let e = decode(b"t\0\x00\xD8x\0", Some(Encoding::Utf16Le)).unwrap_err();
        assert_eq!(e.offset, 2, "{e}");
        assert!(e.found.contains("0xD800"), "{e}");
        let e = decode(b"\xFE\xFF\0t\xDC\x00", None).unwrap_err();
        assert_eq!(e.offset, 4, "{e}");
        // A pair is one character.
        assert_eq!(
            decode(b"\x3D\xD8\x00\xDE", Some(Encoding::Utf16Le))
                .unwrap()
                .0,
            "\u{1F600}"
        );
    }

    #[test]
    fn a_byte_order_mark_of_another_encoding_contradicts_the_stated_one() {
        let e = decode(b"\xEF\xBB\xBFt", Some(Encoding::Windows1252)).unwrap_err();
        assert_eq!(e.offset, 0);
        assert!(e.found.contains("UTF-8 byte-order mark"), "{e}");
        let e = decode(b"\xFF\xFEt\0", Some(Encoding::Utf8)).unwrap_err();
        assert!(e.found.contains("UTF-16LE byte-order mark"), "{e}");
    }
}
