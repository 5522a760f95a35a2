//! Which format a record file is in — stated by the campaign, or told by its
//! first bytes, or by its extension — and the reader that reads it.

use std::path::Path;
use std::str::FromStr;

use super::{Format, FormatError, Record};
use crate::base::data::DataError;

impl FromStr for Format {
    type Err = String;

    /// A format's name as campaigns and `rigfit inspect --format` state it.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "csv" | "tsv" | "txt" | "text" => Format::Csv,
            "tdms" => Format::Tdms,
            "hdf5" | "h5" => Format::Hdf5,
            "mat" | "matlab" => Format::Mat,
            "uff" | "unv" | "uff58" => Format::Uff,
            _ => return Err(NAMES.into()),
        })
    }
}

impl<'de> serde::Deserialize<'de> for Format {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        name.parse()
            .map_err(|names| serde::de::Error::custom(format!("expected {names}, found {name:?}")))
    }
}

/// The names [`Format::from_str`] accepts, for messages.
pub const NAMES: &str = "\"csv\", \"tdms\", \"hdf5\", \"mat\" or \"uff\"";

impl Format {
    /// The name a campaign's `"format"` states it by.
    pub fn key(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Tdms => "tdms",
            Format::Hdf5 => "hdf5",
            Format::Mat => "mat",
            Format::Uff => "uff",
            Format::Memory => "memory",
        }
    }

    /// The format of `bytes` read from `path`: `stated` where given; else
    /// told by a binary format's signature (TDMS, HDF5 and MAT v7.3, MAT
    /// level 5); else by the extension (`.uff`, `.unv`); else by a dataset 58
    /// block; else CSV.
    pub fn of(path: &Path, bytes: &[u8], stated: Option<Format>) -> Format {
        if let Some(f) = stated {
            return f;
        }
        if super::tdms::is_tdms(bytes) {
            return Format::Tdms;
        }
        if super::mat::is_mat73(bytes) || super::mat::is_mat5(bytes) {
            return Format::Mat;
        }
        if super::hdf5::is_hdf5(bytes) {
            return Format::Hdf5;
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("uff" | "unv" | "uf") => Format::Uff,
            Some("tdms") => Format::Tdms,
            Some("h5" | "hdf5" | "hdf" | "he5") => Format::Hdf5,
            Some("mat") => Format::Mat,
            _ if super::uff::is_uff(bytes) => Format::Uff,
            _ => Format::Csv,
        }
    }
}

/// Reads `bytes` as `format`, one of the binary or UFF formats (a CSV is read
/// by [`crate::base::data::parse_csv`] against its column keys).
pub fn read(format: Format, bytes: &[u8]) -> Result<Record, FormatError> {
    match format {
        Format::Tdms => super::tdms::read(bytes),
        Format::Hdf5 => super::hdf5::read(bytes),
        Format::Mat if super::mat::is_mat73(bytes) => {
            let mut record = super::hdf5::read(bytes)?;
            record.format = Format::Mat;
            Ok(record)
        }
        Format::Mat => super::mat::read(bytes),
        Format::Uff => super::uff::read(bytes),
        Format::Csv | Format::Memory => Err(FormatError {
            format,
            at: "file".into(),
            expected: "a binary record (CSV is read against its column keys)".into(),
            found: format.to_string(),
        }),
    }
}

/// Reads `bytes` (the file at `file`) as `format` into channels, a CSV
/// included (in its detected encoding, see [`super::csv`]).
pub fn read_any(format: Format, bytes: &[u8], file: &Path) -> Result<Record, DataError> {
    match format {
        Format::Csv => {
            let spec = crate::base::data::CsvSpec::default();
            let text = crate::base::data::decode_record(bytes, file, &spec)?;
            Ok(super::csv::read(&text))
        }
        other => read(other, bytes).map_err(|e| data_error(e, file)),
    }
}

/// A reader's error as the data error of `file`.
pub fn data_error(e: FormatError, file: &Path) -> DataError {
    DataError::Record {
        file: file.to_path_buf(),
        what: format!("{} {}", e.format, e.at),
        expected: e.expected,
        found: e.found,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stated_format_wins_then_signatures_then_extensions() {
        let p = Path::new("r.csv");
        assert_eq!(Format::of(p, b"TDSm....", None), Format::Tdms);
        assert_eq!(Format::of(p, b"TDSm....", Some(Format::Csv)), Format::Csv);
        assert_eq!(Format::of(Path::new("r.unv"), b"x", None), Format::Uff);
        assert_eq!(Format::of(p, b"t,f\n0,1\n", None), Format::Csv);
        assert_eq!("HDF5".parse::<Format>(), Ok(Format::Hdf5));
        assert!("xlsx".parse::<Format>().unwrap_err().contains("\"tdms\""));
    }
}
