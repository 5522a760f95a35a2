//! HDF5 record files, MATLAB v7.3 MAT-files included (HDF5 behind a 512-byte
//! user block), read through the system's libhdf5.
//!
//! Every numeric dataset (integer or floating-point class) anywhere in the
//! file becomes channels, the groups walked in name order and only hard links
//! followed: a 1-D dataset `/g/x` is the channel `/g/x`; a 2-D dataset of
//! N rows and M ≤ 64 columns gives the channels `/g/x[:,0]` … `/g/x[:,M-1]`
//! (0-based), and one of N ≤ 64 < M gives its rows, `/g/x[0,:]` ….
//! Scalars, datasets of more than two dimensions, empty datasets, strings,
//! compounds, references and enumerations are skipped.
//!
//! A channel's unit is the dataset's string attribute `units`, `unit`,
//! `Unit` or `UNITS`. Its timing comes from numeric attributes on the
//! dataset, else on its group: the sample interval `dt`, `increment`,
//! `wf_increment` or `sample_interval` (s), or the sample rate
//! `sample_rate`, `sampling_rate`, `fs` or `rate` (Hz); the start `t0`,
//! `start`, `wf_start_offset` or `start_time` (s, 0 when absent or not a
//! number). An interval or rate that is not a positive finite number states
//! no timing.
//!
//! When any object carries the attribute `MATLAB_class` the file is a MATLAB
//! v7.3 MAT-file and its channels take MATLAB names (`v`, `v(:,1)`, `s.field`;
//! see the module `mat73`).
//!
//! libhdf5 reads files, not memory, through the safe API: the bytes go to a
//! private temporary file (mode 0600, created new in the system's temporary
//! folder) that is removed on every path out of [`read`].
//!
//! Where the program has asked for it ([`super::hdf5_child::read_in_child`],
//! as the `rigfit` binary does), [`read`] reads in a child process, so that
//! a crash inside libhdf5 is an error about the file; otherwise in process.

use super::{Format, FormatError, Record};

/// MATLAB v7.3 naming, a child of this module (it needs the walk's findings).
#[cfg(feature = "hdf5")]
#[path = "mat73.rs"]
mod mat73;

#[cfg(feature = "hdf5")]
pub(super) use library::MOST_FILTER_RATIO;
#[cfg(feature = "hdf5")]
use library::{Found, MOST_SPLIT, hdf5_columns, hdf5_rows};

/// The HDF5 format signature ("HDF5 File Format Specification", superblock).
const SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Whether `bytes` hold the HDF5 signature where the format allows the
/// superblock: at byte 0, 512, 1024, 2048, … (after a user block).
pub fn is_hdf5(bytes: &[u8]) -> bool {
    let mut at = 0usize;
    loop {
        let Some(end) = at.checked_add(SIGNATURE.len()) else {
            return false;
        };
        match bytes.get(at..end) {
            Some(found) if found == SIGNATURE => return true,
            Some(_) => {}
            None => return false,
        }
        at = if at == 0 { 512 } else { at.saturating_mul(2) };
    }
}

/// Reads an HDF5 file's (or a MATLAB v7.3 MAT-file's) numeric datasets as
/// channels: in a child process where one is asked for (see the module's
/// text), else in this one.
pub fn read(bytes: &[u8]) -> Result<Record, FormatError> {
    #[cfg(feature = "hdf5")]
    if let Some(exe) = super::hdf5_child::child_exe()
        && is_hdf5(bytes)
    {
        return super::hdf5_child::read(exe, bytes);
    }
    read_in_process(bytes)
}

/// Reads as [`read`] does, in this process whatever was asked for.
pub(crate) fn read_in_process(bytes: &[u8]) -> Result<Record, FormatError> {
    if !is_hdf5(bytes) {
        return Err(file_error(format!(
            "no HDF5 signature at byte 0, 512, 1024, 2048, … of its {} bytes",
            bytes.len()
        )));
    }
    library::read(bytes)
}

fn file_error(found: String) -> FormatError {
    file_error_expecting("an HDF5 file", found)
}

fn file_error_expecting(expected: &str, found: String) -> FormatError {
    FormatError {
        format: Format::Hdf5,
        at: "file".to_string(),
        expected: expected.to_string(),
        found,
    }
}

/// A build without the cargo feature `hdf5` has no libhdf5 to read with.
#[cfg(not(feature = "hdf5"))]
mod library {
    use super::{FormatError, Record, file_error_expecting};

    /// The error every HDF5 file gives in such a build.
    pub(super) fn read(_bytes: &[u8]) -> Result<Record, FormatError> {
        Err(file_error_expecting(
            "a build of rigfit with the default feature `hdf5` (needs libhdf5-dev)",
            "this build of rigfit, which reads no HDF5".to_string(),
        ))
    }

    #[cfg(test)]
    mod tests {
        #[test]
        fn an_hdf5_file_is_an_error_naming_the_feature() {
            let e = super::super::read(super::super::SIGNATURE).unwrap_err();
            assert_eq!(e.at, "file");
            assert!(e.expected.contains("feature `hdf5`"), "{e}");
            let e = super::super::read(b"no signature").unwrap_err();
            assert!(e.found.contains("no HDF5 signature"), "{e}");
        }
    }
}

/// The reading itself, through libhdf5.
#[cfg(feature = "hdf5")]
mod library {
    use std::collections::HashSet;
    use std::fs::OpenOptions;
    use std::io::Write;
    use std::path::{Path, PathBuf};
    use std::sync::atomic::{AtomicU64, Ordering};

    use h5::types::{FixedAscii, FixedUnicode, TypeDescriptor, VarLenAscii, VarLenUnicode};
    use hdf5_metno as h5;

    use super::super::{Channel, Format, FormatError, Record, Waveform};
    use super::mat73;
    use super::{file_error, file_error_expecting};

    /// The most channels one 2-D dataset is split into, along either axis.
    pub(super) const MOST_SPLIT: usize = 64;

    /// The deepest group nesting walked.
    const MOST_DEPTH: usize = 64;

    /// The largest ratio of a filtered (compressed) dataset's samples to the
    /// file's bytes that is accepted: DEFLATE's maximum compression ratio.
    pub(in crate::record) const MOST_FILTER_RATIO: usize = 1032;

    /// The longest fixed-length string attribute read, in bytes.
    const MOST_TEXT: usize = 256;

    const UNIT_ATTRS: [&str; 4] = ["units", "unit", "Unit", "UNITS"];
    const INTERVAL_ATTRS: [&str; 4] = ["dt", "increment", "wf_increment", "sample_interval"];
    const RATE_ATTRS: [&str; 4] = ["sample_rate", "sampling_rate", "fs", "rate"];
    const START_ATTRS: [&str; 4] = ["t0", "start", "wf_start_offset", "start_time"];

    /// Reads a file that holds the HDF5 signature.
    pub(super) fn read(bytes: &[u8]) -> Result<Record, FormatError> {
        // Declared first, so dropped last: after every libhdf5 handle.
        let temp = TempFile::holding(bytes)?;
        let file = h5::File::open(temp.path()).map_err(|e| file_error(one_line(&e)))?;
        let mut walk = Walk {
            seen: HashSet::new(),
            found: Vec::new(),
            datasets: 0,
            matlab: false,
        };
        walk.group(&file, &mut Vec::new(), &Parent::root(), 0)?;
        let channels = if walk.matlab {
            mat73::channels(&walk.found, bytes.len())?
        } else {
            plain_channels(&walk.found, bytes.len())?
        };
        if channels.is_empty() {
            return Err(file_error_expecting(
                "at least one numeric dataset (integer or floating point, 1-D or 2-D, not empty)",
                format!("none among its {} datasets", walk.datasets),
            ));
        }
        Ok(Record {
            format: record_format(walk.matlab),
            channels,
        })
    }

    /// The format a record read here reports: HDF5 for plain files and MATLAB
    /// v7.3 alike (the one place to tell them apart, should a format be added).
    fn record_format(_matlab: bool) -> Format {
        Format::Hdf5
    }

    /// A dataset the walk found, with what its attributes say.
    pub(super) struct Found {
        /// Its path's names below the root group.
        pub(super) path: Vec<String>,
        /// The open dataset.
        pub(super) dataset: h5::Dataset,
        /// Its dimensions (HDF5 order, slowest first).
        pub(super) shape: Vec<usize>,
        /// Whether its datatype is of the integer or floating-point class.
        pub(super) numeric: bool,
        /// Its `MATLAB_class` attribute.
        pub(super) matlab_class: Option<String>,
        /// Whether its `MATLAB_empty` attribute is set (the data is then the
        /// empty array's dimensions, not samples).
        pub(super) matlab_empty: bool,
        /// Whether every group above it (the root aside) is a MATLAB struct.
        pub(super) in_structs: bool,
        /// Its unit attribute.
        pub(super) unit: Option<String>,
        /// Its sample timing, from its attributes or its group's.
        pub(super) timing: Option<Waveform>,
    }

    impl Found {
        /// Where errors about it point: `dataset /g/x`.
        pub(super) fn at(&self) -> String {
            format!("dataset /{}", self.path.join("/"))
        }

        /// Its samples, converted to `f64` by libhdf5, in HDF5 (row-major) order.
        pub(super) fn values(&self, file_len: usize) -> Result<Vec<f64>, FormatError> {
            let fail = |expected: &str, found: String| FormatError {
                format: Format::Hdf5,
                at: self.at(),
                expected: expected.to_string(),
                found,
            };
            let readable = "a readable dataset";
            let dcpl = self
                .dataset
                .dcpl()
                .map_err(|e| fail(readable, one_line(&e)))?;
            let stored_here = matches!(
                dcpl.layout(),
                h5::dataset::Layout::Compact
                    | h5::dataset::Layout::Contiguous
                    | h5::dataset::Layout::Chunked
            );
            if !stored_here {
                let found = "a virtual dataset drawing on other files".to_string();
                return Err(fail("samples stored in this file", found));
            }
            if let Some(external) = dcpl.external().first() {
                let found = format!("samples in the external file `{}`", external.name);
                return Err(fail("samples stored in this file", found));
            }
            let item = self
                .dataset
                .dtype()
                .map_err(|e| fail(readable, one_line(&e)))?
                .size();
            let count = self.shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
            let (most, bound) = if dcpl.has_filters() {
                let most = file_len.saturating_mul(MOST_FILTER_RATIO);
                (
                    most,
                    format!("{MOST_FILTER_RATIO} times the file's {file_len} bytes"),
                )
            } else {
                (file_len, format!("the file's {file_len} bytes"))
            };
            let Some(count) = count.filter(|n| n.checked_mul(item).is_some_and(|b| b <= most))
            else {
                let found = format!("shape {:?} of {item}-byte samples", self.shape);
                return Err(fail(&format!("at most {bound} of samples"), found));
            };
            let values = self
                .dataset
                .read_raw::<f64>()
                .map_err(|e| fail("samples libhdf5 can read as numbers", one_line(&e)))?;
            if values.len() != count {
                let found = format!("{} samples", values.len());
                return Err(fail(
                    &format!("{count} samples (shape {:?})", self.shape),
                    found,
                ));
            }
            Ok(values)
        }
    }

    /// What a group hands down to its members.
    struct Parent {
        /// The group's sample interval (s), from its attributes.
        increment: Option<f64>,
        /// The group's start (s), from its attributes.
        start: Option<f64>,
        /// Whether it and every group above it (the root aside) is a MATLAB struct.
        in_structs: bool,
    }

    impl Parent {
        fn root() -> Self {
            Self {
                increment: None,
                start: None,
                in_structs: true,
            }
        }
    }

    /// The walk over the file's groups.
    struct Walk {
        /// The objects already visited (hard links may name one twice).
        seen: HashSet<String>,
        /// The datasets found, in walk order.
        found: Vec<Found>,
        /// How many datasets the walk met.
        datasets: usize,
        /// Whether any object has a `MATLAB_class` attribute.
        matlab: bool,
    }

    impl Walk {
        fn group(
            &mut self,
            group: &h5::Group,
            path: &mut Vec<String>,
            parent: &Parent,
            depth: usize,
        ) -> Result<(), FormatError> {
            let here = format!("group /{}", path.join("/"));
            let fail = |found: String| FormatError {
                format: Format::Hdf5,
                at: here.clone(),
                expected: "a readable group".to_string(),
                found,
            };
            let mut links = group
                .links(h5::IndexType::Name, h5::IterationOrder::Increasing)
                .map_err(|e| fail(one_line(&e)))?;
            links.sort_by(|a, b| a.0.cmp(&b.0));
            for (name, link) in links {
                if link.link_type != h5::LinkType::Hard {
                    continue;
                }
                let info = group
                    .loc_info_by_name(&name)
                    .map_err(|e| fail(one_line(&e)))?;
                if !self.seen.insert(format!("{:?}", info.token)) {
                    continue;
                }
                path.push(name.clone());
                let outcome = match info.loc_type {
                    h5::LocationType::Group => match group.group(&name) {
                        Ok(child) if depth < MOST_DEPTH => {
                            let parent = self.group_attrs(&child, parent);
                            self.group(&child, path, &parent, depth + 1)
                        }
                        Ok(_) => Err(FormatError {
                            format: Format::Hdf5,
                            at: here.clone(),
                            expected: format!("groups nested at most {MOST_DEPTH} deep"),
                            found: "deeper nesting".to_string(),
                        }),
                        Err(e) => Err(fail(one_line(&e))),
                    },
                    h5::LocationType::Dataset => match group.dataset(&name) {
                        Ok(dataset) => {
                            self.dataset(dataset, path, parent);
                            Ok(())
                        }
                        Err(e) => Err(FormatError {
                            format: Format::Hdf5,
                            at: format!("dataset /{}", path.join("/")),
                            expected: "a readable dataset".to_string(),
                            found: one_line(&e),
                        }),
                    },
                    _ => Ok(()),
                };
                path.pop();
                outcome?;
            }
            Ok(())
        }

        /// What a group's attributes hand down to its members.
        fn group_attrs(&mut self, group: &h5::Group, parent: &Parent) -> Parent {
            let names = group.attr_names().unwrap_or_default();
            let class = text_attr(group, &names, &["MATLAB_class"]);
            self.matlab |= class.is_some();
            Parent {
                increment: increment_attr(group, &names),
                start: number_attr(group, &names, &START_ATTRS),
                in_structs: parent.in_structs && class.as_deref() == Some("struct"),
            }
        }

        fn dataset(&mut self, dataset: h5::Dataset, path: &[String], parent: &Parent) {
            self.datasets += 1;
            let names = dataset.attr_names().unwrap_or_default();
            let matlab_class = text_attr(&dataset, &names, &["MATLAB_class"]);
            self.matlab |= matlab_class.is_some();
            let numeric = dataset
                .dtype()
                .and_then(|t| t.to_descriptor())
                .is_ok_and(|d| is_number(&d));
            let shape = dataset.shape();
            let candidate = numeric && matches!(shape.len(), 1 | 2) && !shape.contains(&0);
            if !candidate {
                return;
            }
            let timing = increment_attr(&dataset, &names)
                .map(|increment| (increment, number_attr(&dataset, &names, &START_ATTRS)))
                .or_else(|| parent.increment.map(|increment| (increment, parent.start)))
                .map(|(increment, start)| Waveform {
                    start: start.unwrap_or(0.0),
                    increment,
                });
            self.found.push(Found {
                path: path.to_vec(),
                unit: text_attr(&dataset, &names, &UNIT_ATTRS),
                matlab_empty: number_attr(&dataset, &names, &["MATLAB_empty"])
                    .is_some_and(|v| v != 0.0),
                dataset,
                shape,
                numeric,
                matlab_class,
                in_structs: parent.in_structs,
                timing,
            });
        }
    }

    /// The channels of a plain HDF5 file.
    fn plain_channels(found: &[Found], file_len: usize) -> Result<Vec<Channel>, FormatError> {
        let mut channels = Vec::new();
        for f in found {
            let name = format!("/{}", f.path.join("/"));
            let channel = |name: String, values: Vec<f64>| Channel {
                name,
                unit: f.unit.clone(),
                values,
                timing: f.timing,
            };
            match f.shape[..] {
                [_] => channels.push(channel(name, f.values(file_len)?)),
                [_, columns] if columns <= MOST_SPLIT => {
                    let values = f.values(file_len)?;
                    for (j, column) in hdf5_columns(&values, columns).into_iter().enumerate() {
                        channels.push(channel(format!("{name}[:,{j}]"), column));
                    }
                }
                [rows, columns] if rows <= MOST_SPLIT => {
                    let values = f.values(file_len)?;
                    for (i, row) in hdf5_rows(&values, columns).into_iter().enumerate() {
                        channels.push(channel(format!("{name}[{i},:]"), row));
                    }
                }
                _ => {}
            }
        }
        Ok(channels)
    }

    /// The rows of row-major `values` with `columns` columns.
    pub(super) fn hdf5_rows(values: &[f64], columns: usize) -> Vec<Vec<f64>> {
        values.chunks(columns.max(1)).map(<[f64]>::to_vec).collect()
    }

    /// The columns of row-major `values` with `columns` columns.
    pub(super) fn hdf5_columns(values: &[f64], columns: usize) -> Vec<Vec<f64>> {
        (0..columns)
            .map(|j| values.iter().skip(j).step_by(columns).copied().collect())
            .collect()
    }

    fn is_number(descriptor: &TypeDescriptor) -> bool {
        matches!(
            descriptor,
            TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) | TypeDescriptor::Float(_)
        )
    }

    /// The sample interval an object's attributes state (s), from an interval
    /// or a rate; `None` unless positive and finite.
    fn increment_attr(loc: &h5::Location, names: &[String]) -> Option<f64> {
        number_attr(loc, names, &INTERVAL_ATTRS)
            .or_else(|| number_attr(loc, names, &RATE_ATTRS).map(|rate| 1.0 / rate))
            .filter(|increment| increment.is_finite() && *increment > 0.0)
    }

    /// The first of the attributes `wanted` that holds one number.
    fn number_attr(loc: &h5::Location, names: &[String], wanted: &[&str]) -> Option<f64> {
        wanted.iter().find_map(|&name| {
            if !names.iter().any(|n| n == name) {
                return None;
            }
            let attr = loc.attr(name).ok()?;
            let descriptor = attr.dtype().ok()?.to_descriptor().ok()?;
            if attr.size() != 1 || !is_number(&descriptor) {
                return None;
            }
            attr.read_raw::<f64>().ok()?.first().copied()
        })
    }

    /// The first of the attributes `wanted` that holds one non-empty string
    /// (text or bytes, fixed or variable length).
    fn text_attr(loc: &h5::Location, names: &[String], wanted: &[&str]) -> Option<String> {
        wanted.iter().find_map(|&name| {
            if !names.iter().any(|n| n == name) {
                return None;
            }
            let attr = loc.attr(name).ok()?;
            if attr.size() != 1 {
                return None;
            }
            let bytes = match attr.dtype().ok()?.to_descriptor().ok()? {
                TypeDescriptor::VarLenUnicode => attr
                    .read_raw::<VarLenUnicode>()
                    .ok()?
                    .first()?
                    .as_bytes()
                    .to_vec(),
                TypeDescriptor::VarLenAscii => attr
                    .read_raw::<VarLenAscii>()
                    .ok()?
                    .first()?
                    .as_bytes()
                    .to_vec(),
                TypeDescriptor::FixedAscii(_) => {
                    let text = attr.read_raw::<FixedAscii<MOST_TEXT>>().ok()?;
                    text.first()?.as_bytes().to_vec()
                }
                TypeDescriptor::FixedUnicode(_) => {
                    let text = attr.read_raw::<FixedUnicode<MOST_TEXT>>().ok()?;
                    text.first()?.as_bytes().to_vec()
                }
                _ => return None,
            };
            let text = String::from_utf8_lossy(&bytes);
            let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
            (!text.is_empty()).then(|| text.to_string())
        })
    }

    /// A libhdf5 error as one line.
    fn one_line(error: &h5::Error) -> String {
        let text = error.to_string();
        let lines: Vec<&str> = text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        if lines.is_empty() {
            "an error libhdf5 does not describe".to_string()
        } else {
            lines.join("; ")
        }
    }

    /// A private temporary copy of a file's bytes, removed when dropped.
    struct TempFile {
        path: PathBuf,
    }

    /// Tells apart the temporary files of one process.
    static TEMP_SERIAL: AtomicU64 = AtomicU64::new(0);

    impl TempFile {
        /// Writes `bytes` to a new file only this user may read.
        fn holding(bytes: &[u8]) -> Result<Self, FormatError> {
            let dir = std::env::temp_dir();
            let fail = |e: std::io::Error| {
                let expected = format!(
                    "a private temporary file in {} to hand to libhdf5",
                    dir.display()
                );
                file_error_expecting(&expected, e.to_string())
            };
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.subsec_nanos());
            let mut last = None;
            for _ in 0..16 {
                let serial = TEMP_SERIAL.fetch_add(1, Ordering::Relaxed);
                let path = dir.join(format!("rigfit-{}-{serial}-{nanos}.h5", std::process::id()));
                let mut options = OpenOptions::new();
                options.write(true).create_new(true);
                #[cfg(unix)]
                std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
                match options.open(&path) {
                    Ok(mut file) => {
                        let temp = Self { path };
                        file.write_all(bytes).map_err(fail)?;
                        return Ok(temp);
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
                    Err(e) => return Err(fail(e)),
                }
            }
            Err(fail(last.unwrap_or_else(|| {
                std::io::ErrorKind::AlreadyExists.into()
            })))
        }

        fn path(&self) -> &Path {
            &self.path
        }
    }

    impl Drop for TempFile {
        fn drop(&mut self) {
            // Nothing more to do when it is already gone.
            let _ = std::fs::remove_file(&self.path);
        }
    }

    #[cfg(test)]
    mod tests {
        use super::super::{SIGNATURE, is_hdf5, read};
        use super::*;
        use proptest::prelude::*;

        const TENSILE: &[u8] = include_bytes!("../../tests/data/records/hdf5_tensile.h5");
        const STRINGS_ONLY: &[u8] = include_bytes!("../../tests/data/records/hdf5_strings_only.h5");
        const UNWRITTEN: &[u8] = include_bytes!("../../tests/data/records/hdf5_unwritten.h5");
        const MAT73: &[u8] = include_bytes!("../../tests/data/records/hdf5_mat73.mat");

        /// The bit patterns of `values`, so that comparisons are bit for bit.
        fn bits(values: impl IntoIterator<Item = f64>) -> Vec<u64> {
            values.into_iter().map(f64::to_bits).collect()
        }

        fn channel<'a>(record: &'a Record, name: &str) -> &'a Channel {
            let found = record.channels.iter().find(|c| c.name == name);
            found.unwrap_or_else(|| panic!("no channel {name} in {:?}", names(record)))
        }

        fn names(record: &Record) -> Vec<&str> {
            record.channels.iter().map(|c| c.name.as_str()).collect()
        }

        #[test]
        fn reads_every_numeric_dataset_in_name_order_bit_for_bit() {
            let record = read(TENSILE).unwrap();
            assert_eq!(record.format, Format::Hdf5);
            let mut expected = vec!["/daq/strain", "/grid/wide[0,:]", "/grid/wide[1,:]"];
            expected.extend(["/grid/xyz[:,0]", "/grid/xyz[:,1]", "/grid/xyz[:,2]"]);
            expected.extend(["/tensile/force_N", "/tensile/t_s"]);
            assert_eq!(names(&record), expected);

            let t = channel(&record, "/tensile/t_s");
            assert_eq!(
                bits(t.values.iter().copied()),
                bits((0..50).map(|k| f64::from(k) * 0.002))
            );
            assert_eq!((t.unit.as_deref(), t.timing), (Some("s"), None));

            let force = channel(&record, "/tensile/force_N");
            let expected = (0..50).map(|k: i32| f64::from((k * k) % 97) / 7.0);
            assert_eq!(bits(force.values.iter().copied()), bits(expected));
            assert_eq!(force.unit.as_deref(), Some("N"));
            let timing = Waveform {
                start: 0.25,
                increment: 0.002,
            };
            assert_eq!(force.timing, Some(timing));

            let strain = channel(&record, "/daq/strain");
            let expected = (0..50).map(|k: i32| f64::from((k * 37) % 200 - 100));
            assert_eq!(bits(strain.values.iter().copied()), bits(expected));
            assert_eq!(
                strain.unit.as_deref(),
                Some("ue"),
                "a fixed-length byte string"
            );
            let timing = Waveform {
                start: 0.0,
                increment: 1.0 / 2000.0,
            };
            assert_eq!(
                strain.timing,
                Some(timing),
                "the group's rate; a text start is 0"
            );

            for j in 0..3 {
                let xyz = channel(&record, &format!("/grid/xyz[:,{j}]"));
                let expected = (0..20).map(|i| f64::from((f64::from(i * 10 + j) / 4.0) as f32));
                assert_eq!(bits(xyz.values.iter().copied()), bits(expected));
                assert_eq!((xyz.unit.as_deref(), xyz.timing), (Some("mm"), None));
            }
            for i in 0..2 {
                let wide = channel(&record, &format!("/grid/wide[{i},:]"));
                let expected = (0..80).map(|c| f64::from(i * 1000 + c));
                assert_eq!(bits(wide.values.iter().copied()), bits(expected));
                assert_eq!(wide.unit, None);
            }
        }

        #[test]
        fn a_file_without_numeric_datasets_is_an_error_saying_so() {
            let e = read(STRINGS_ONLY).unwrap_err();
            assert_eq!(e.at, "file");
            assert!(e.expected.contains("at least one numeric dataset"), "{e}");
            assert_eq!(e.found, "none among its 2 datasets", "{e}");
        }

        #[test]
        fn bytes_without_the_signature_are_not_hdf5() {
            let e = read(b"time,force\n0,1\n").unwrap_err();
            assert_eq!(
                (e.at.as_str(), e.expected.as_str()),
                ("file", "an HDF5 file")
            );
            assert!(
                e.found.contains("no HDF5 signature") && e.found.contains("15 bytes"),
                "{e}"
            );
        }

        #[test]
        fn a_truncated_file_is_an_error_libhdf5_describes_on_one_line() {
            let e = read(&TENSILE[..TENSILE.len() / 2]).unwrap_err();
            assert_eq!(
                (e.at.as_str(), e.expected.as_str()),
                ("file", "an HDF5 file"),
                "{e}"
            );
            assert!(!e.found.is_empty() && !e.found.contains('\n'), "{e}");
        }

        #[test]
        fn a_dataset_larger_than_the_file_is_refused_before_it_is_allocated() {
            let e = read(UNWRITTEN).unwrap_err();
            assert_eq!(e.at, "dataset /big", "{e}");
            let bound = format!("at most the file's {} bytes of samples", UNWRITTEN.len());
            assert_eq!(e.expected, bound, "{e}");
            assert_eq!(e.found, "shape [1000000] of 8-byte samples", "{e}");
        }

        #[test]
        fn the_signature_is_found_at_0_and_after_a_user_block() {
            assert!(is_hdf5(TENSILE));
            assert!(!TENSILE.starts_with(b"MATLAB") && MAT73.starts_with(b"MATLAB 7.3"));
            assert!(is_hdf5(MAT73), "after the 512-byte user block");
            let mut shifted = vec![0u8; 100];
            shifted.extend_from_slice(TENSILE);
            assert!(!is_hdf5(&shifted), "byte 100 is no superblock offset");
            assert!(!is_hdf5(&[]) && !is_hdf5(&SIGNATURE[..7]));
        }

        #[test]
        fn the_temporary_copy_is_private_and_removed_when_dropped() {
            let temp = TempFile::holding(b"abc").unwrap();
            let path = temp.path().to_path_buf();
            assert_eq!(std::fs::read(&path).unwrap(), b"abc");
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                let mode = std::fs::metadata(&path).unwrap().permissions().mode();
                assert_eq!(mode & 0o777, 0o600);
            }
            let other = TempFile::holding(b"").unwrap();
            assert_ne!(other.path(), path, "each copy is a new file");
            drop(temp);
            assert!(!path.exists());
        }

        #[test]
        fn rows_and_columns_split_row_major_values() {
            let values = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
            assert_eq!(
                hdf5_rows(&values, 3),
                [vec![1.0, 2.0, 3.0], vec![4.0, 5.0, 6.0]]
            );
            assert_eq!(
                hdf5_columns(&values, 3),
                [vec![1.0, 4.0], vec![2.0, 5.0], vec![3.0, 6.0]]
            );
            assert!(hdf5_columns(&values, 0).is_empty());
        }

        /// 32 cases from a fixed seed: each goes through libhdf5, and Debian 12's
        /// libhdf5 1.10.8 itself crashes (SIGSEGV, in `H5A__close`) on about one
        /// in 200 MAT-files with one byte flipped in an attribute message (HDF5
        /// 2.0 reports an error instead), which no safe Rust can catch: a random
        /// seed would make this test flaky on such a library.
        fn config() -> ProptestConfig {
            ProptestConfig {
                cases: 32,
                rng_seed: proptest::test_runner::RngSeed::Fixed(0x4844_4635),
                failure_persistence: None,
                ..ProptestConfig::default()
            }
        }

        proptest! {
            #![proptest_config(config())]

            #[test]
            fn truncated_files_never_panic(len in 0..TENSILE.len(), mat in any::<bool>()) {
                let bytes = if mat { MAT73 } else { TENSILE };
                let _ = read(&bytes[..len.min(bytes.len())]);
            }

            #[test]
            fn flipped_bytes_never_panic(at in 0..TENSILE.len(), mask in 1u8..=255) {
                let mut bytes = TENSILE.to_vec();
                bytes[at] ^= mask;
                let _ = read(&bytes);
            }
        }
    }
}
