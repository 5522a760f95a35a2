//! A CSV record as channels, for `rigfit inspect` and for readers that take
//! any record alike: the header's names (`#0`, `#1`, … without a header),
//! each column's numbers (a cell that is not a number reads as NaN), and the
//! unit a header states in brackets at its end (`force [kN]`, `t (ms)`).
//!
//! A campaign reads a CSV's columns through [`crate::base::data::parse_csv`],
//! which refuses a bad cell with its line; this view only lists.

use super::{Channel, Format, Record};
use crate::base::data::{content_lines, parse_number, separator, split_fields};

/// The channels of CSV `text`.
pub fn read(text: &str) -> Record {
    let mut rows = content_lines(text).peekable();
    let Some(&(_, first)) = rows.peek() else {
        return Record {
            format: Format::Csv,
            channels: Vec::new(),
        };
    };
    let sep = separator(first);
    let cell = |f: &str| f.trim().trim_matches('"').trim().to_string();
    let first_fields: Vec<String> = split_fields(first, sep).into_iter().map(cell).collect();
    let header = first_fields
        .iter()
        .any(|f| parse_number(f, sep, None).is_none());
    let names: Vec<String> = if header {
        rows.next();
        first_fields
    } else {
        (0..first_fields.len()).map(|i| format!("#{i}")).collect()
    };
    let mut channels: Vec<Channel> = names
        .iter()
        .map(|name| Channel {
            name: name.clone(),
            unit: bracketed_unit(name),
            values: Vec::new(),
            timing: None,
        })
        .collect();
    for (_, row) in rows {
        let fields = split_fields(row, sep);
        for (j, c) in channels.iter_mut().enumerate() {
            let value = fields
                .get(j)
                .and_then(|f| parse_number(f.trim().trim_matches('"').trim(), sep, None));
            c.values.push(value.unwrap_or(f64::NAN));
        }
    }
    Record {
        format: Format::Csv,
        channels,
    }
}

/// The unit a column's name states at its end in brackets: `force [kN]` →
/// `kN`, `t (ms)` → `ms`.
pub fn bracketed_unit(name: &str) -> Option<String> {
    let name = name.trim_end();
    let (open, close) = match name.chars().last()? {
        ']' => ('[', ']'),
        ')' => ('(', ')'),
        _ => return None,
    };
    let start = name.rfind(open)?;
    let unit = name[start + open.len_utf8()..name.len() - close.len_utf8()].trim();
    (!unit.is_empty() && start > 0).then(|| unit.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_units_and_bad_cells() {
        let r = read("# note\nt [s];Kraft [kN];x\n0;1,5;a\n0,001;2;3\n");
        let names: Vec<&str> = r.channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["t [s]", "Kraft [kN]", "x"]);
        assert_eq!(r.channels[1].unit.as_deref(), Some("kN"));
        assert_eq!(r.channels[0].values, vec![0.0, 0.001]);
        assert!(r.channels[2].values[0].is_nan());
        let bare = read("0,1\n1,2\n");
        assert_eq!(bare.channels[1].name, "#1");
        assert_eq!(bare.channels[1].values, vec![1.0, 2.0]);
        assert_eq!(bracketed_unit("[N]"), None);
    }
}
