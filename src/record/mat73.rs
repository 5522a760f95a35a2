//! MATLAB names for the channels of a MATLAB v7.3 MAT-file (an HDF5 file
//! whose datasets carry the attribute `MATLAB_class`), as
//! "MATLAB MAT-File Format" (v7.3, HDF5-based) stores them.
//!
//! MATLAB writes its column-major arrays transposed: a MATLAB R×C array is an
//! HDF5 dataset of shape [C, R]. A vector (1×N or N×1) variable `v` is the
//! channel `v`; a matrix of C ≤ 64 columns gives the channels `v(:,1)` …
//! `v(:,C)` (1-based, as MATLAB users write it), and one of R ≤ 64 < C rows
//! gives its rows, `v(1,:)` …. A struct `s` (a group of class `struct`) gives
//! `s.field`, nested structs `s.a.b`. The objects under `#refs#` and
//! `#subsystem#`, and the classes `char`, `cell`, `logical` and any other
//! non-numeric class, are skipped, as are empty arrays (`MATLAB_empty`),
//! sparse matrices and objects (groups of another class than `struct`).
//! A struct's `char` field `units` or `unit` gives the unit of its numeric
//! fields.

use std::collections::HashMap;

use super::{Found, MOST_SPLIT, hdf5_columns, hdf5_rows};
use crate::record::{Channel, FormatError};

/// The `MATLAB_class` values of numeric arrays.
const NUMERIC_CLASSES: [&str; 10] = [
    "double", "single", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
];

/// The struct fields that name their siblings' unit.
const UNIT_FIELDS: [&str; 2] = ["units", "unit"];

/// The channels of a MATLAB v7.3 MAT-file's datasets, in walk order.
pub(super) fn channels(found: &[Found], file_len: usize) -> Result<Vec<Channel>, FormatError> {
    let units = struct_units(found, file_len)?;
    let mut channels = Vec::new();
    for f in found.iter().filter(|f| is_numeric_variable(f)) {
        let name = f.path.join(".");
        let unit = f.unit.clone().or_else(|| {
            let parent = f.path.split_last().map(|(_, parent)| parent)?;
            units.get(parent).cloned()
        });
        let channel = |name: String, values: Vec<f64>| Channel {
            name,
            unit: unit.clone(),
            values,
            timing: f.timing,
        };
        match f.shape[..] {
            [_] | [1, _] | [_, 1] => channels.push(channel(name, f.values(file_len)?)),
            // HDF5 [C, R]: each HDF5 row is a MATLAB column.
            [columns, rows] if columns <= MOST_SPLIT => {
                let values = f.values(file_len)?;
                for (j, column) in hdf5_rows(&values, rows).into_iter().enumerate() {
                    channels.push(channel(format!("{name}(:,{})", j + 1), column));
                }
            }
            // … and each HDF5 column a MATLAB row.
            [_, rows] if rows <= MOST_SPLIT => {
                let values = f.values(file_len)?;
                for (i, row) in hdf5_columns(&values, rows).into_iter().enumerate() {
                    channels.push(channel(format!("{name}({},:)", i + 1), row));
                }
            }
            _ => {}
        }
    }
    Ok(channels)
}

/// Whether a dataset is a numeric MATLAB variable or struct field.
fn is_numeric_variable(f: &Found) -> bool {
    let hidden = f.path.first().is_some_and(|top| top.starts_with('#'));
    let numeric_class = f
        .matlab_class
        .as_deref()
        .is_none_or(|class| NUMERIC_CLASSES.contains(&class));
    f.numeric && f.in_structs && !hidden && !f.matlab_empty && numeric_class
}

/// The units a struct's `char` field `units` or `unit` gives its numeric
/// fields, by the struct's path.
fn struct_units(
    found: &[Found],
    file_len: usize,
) -> Result<HashMap<Vec<String>, String>, FormatError> {
    let mut units = HashMap::new();
    for f in found {
        let Some((field, parent)) = f.path.split_last() else {
            continue;
        };
        let is_unit_field = UNIT_FIELDS.contains(&field.as_str())
            && f.matlab_class.as_deref() == Some("char")
            && !parent.is_empty()
            && f.in_structs
            && !f.matlab_empty;
        if !is_unit_field || units.contains_key(parent) {
            continue;
        }
        let codes: Vec<u16> = f
            .values(file_len)?
            .into_iter()
            .map(|code| code as u16)
            .collect();
        let text = String::from_utf16_lossy(&codes);
        let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
        if !text.is_empty() {
            units.insert(parent.to_vec(), text.to_string());
        }
    }
    Ok(units)
}

#[cfg(test)]
mod tests {
    use super::super::super::{Format, Record};
    use super::super::read;

    const MAT73: &[u8] = include_bytes!("../../tests/data/records/hdf5_mat73.mat");

    fn bits(values: impl IntoIterator<Item = f64>) -> Vec<u64> {
        values.into_iter().map(f64::to_bits).collect()
    }

    fn t_s(n: i32) -> Vec<u64> {
        bits((0..n).map(|k| f64::from(k) * 0.002))
    }

    fn force_n(n: i32) -> Vec<u64> {
        bits((0..n).map(|k| f64::from((k * k) % 97) / 7.0))
    }

    fn get<'a>(record: &'a Record, name: &str) -> (Vec<u64>, Option<&'a str>) {
        let c = record.channels.iter().find(|c| c.name == name).unwrap();
        assert_eq!(c.timing, None, "{name}");
        (bits(c.values.iter().copied()), c.unit.as_deref())
    }

    #[test]
    fn variables_take_matlab_names_and_skip_char_logical_and_empty() {
        let record = read(MAT73).unwrap();
        assert_eq!(record.format, Format::Hdf5);
        let names: Vec<&str> = record.channels.iter().map(|c| c.name.as_str()).collect();
        let expected = [
            "counts",
            "force_N",
            "m(:,1)",
            "m(:,2)",
            "rec.force",
            "rec.t",
            "t_s",
        ];
        assert_eq!(
            names, expected,
            "no `flag` (logical), `label` (char), `empty`"
        );
        assert_eq!(get(&record, "t_s"), (t_s(50), None), "a 1×N row vector");
        assert_eq!(get(&record, "force_N"), (force_n(50), None));
        assert_eq!(
            get(&record, "counts"),
            (bits([3.0, -4.0, 5.0]), None),
            "int16"
        );
        assert_eq!(
            get(&record, "m(:,1)"),
            (t_s(10), None),
            "a 10×2 matrix's columns"
        );
        assert_eq!(get(&record, "m(:,2)"), (force_n(10), None));
    }

    #[test]
    fn a_structs_char_units_field_gives_its_fields_unit() {
        let record = read(MAT73).unwrap();
        assert_eq!(get(&record, "rec.t"), (t_s(8), Some("kN")));
        assert_eq!(get(&record, "rec.force"), (force_n(8), Some("kN")));
    }
}
