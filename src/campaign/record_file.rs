//! An experiment's record file read in its format — CSV, TDMS, HDF5, MAT or
//! UFF 58, as the campaign's `"format"` states or the file tells — into the
//! series its column keys choose, with the unit the file records for that
//! column checked against the rig output's.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Serialize;

use super::CampaignError;
use super::error::invalid;
use super::raw::{RawData, RawExperiment};
use crate::base::data::{Column, CsvSpec, DataError, Series, decode_record, parse_csv};
use crate::model::compiled::CompiledRig;
use crate::record::lent::Loan;
use crate::record::select::Selection;
use crate::record::{Format, Record, detect};

/// What a fit read from a record, for result.json's `"records"`: the file,
/// its format and the channel with the unit the file records for it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordUse {
    /// The experiment (a channel's problem experiment: `<experiment>.<output>`).
    pub experiment: String,
    /// The record file (result.json gives it as `inputs` does).
    #[serde(skip)]
    pub file: PathBuf,
    /// Its format (`csv`, `tdms`, `hdf5`, `mat`, `uff`; `memory` for arrays
    /// lent from memory).
    pub format: &'static str,
    /// The channels read: the time channel (where the time is one), then
    /// the measured channel.
    pub channels: Vec<RecordedChannel>,
    /// The rig output it is fitted to.
    pub output: String,
    /// The rig output's unit.
    pub output_unit: String,
    /// The SHA-256 of the record as read: its file's bytes, or (a record
    /// lent from memory) [`Loan::digest_bytes`].
    #[serde(skip)]
    pub sha256: [u8; 32],
}

/// One channel a fit read, in result.json's `"records"`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordedChannel {
    /// Its full name in the file (a CSV's column key).
    pub name: String,
    /// `"time"` or `"measured"`.
    pub role: &'static str,
    /// The unit the file records for it, where it records one.
    pub unit: Option<String>,
}

/// What was read of a record beside its series: its format, the channel's
/// full name and the units the file records for it and for its time.
#[derive(Debug, Clone)]
pub(super) struct Recorded {
    pub(super) format: Format,
    pub(super) channel: String,
    pub(super) unit: Option<String>,
    pub(super) time_channel: Option<String>,
    pub(super) time_unit: Option<String>,
    pub(super) sha256: [u8; 32],
}

/// An experiment's record as its channels and its drive column share it: its
/// bytes (or its channels lent from memory), read once with their SHA-256,
/// and (in a format other than CSV) its channels, parsed once.
#[derive(Debug, Default)]
pub(super) struct Shared {
    /// The record, once a first channel has read it.
    pub(super) loan: Option<Loan>,
    /// The SHA-256 of its digest bytes ([`Loan::digest_bytes`]).
    sha256: [u8; 32],
    /// Its channels, once a first reading has parsed them.
    parsed: Option<Arc<Record>>,
}

impl Shared {
    /// Holds `loan` as the experiment's record, for reading alone (no
    /// digest taken).
    pub(super) fn hold(&mut self, loan: Loan) {
        if let Loan::Record(r) = &loan {
            self.parsed = Some(r.clone());
        }
        self.loan = Some(loan);
    }

    /// Holds `loan` as the experiment's record and takes its SHA-256;
    /// returns `digest` extended with it.
    pub(super) fn lend(&mut self, loan: Loan, digest: u64) -> u64 {
        use sha2::Digest as _;
        let bytes = loan.digest_bytes();
        let digest = super::fnv1a(digest, &bytes);
        self.sha256 = sha2::Sha256::digest(&bytes).into();
        drop(bytes);
        self.hold(loan);
        digest
    }
}

/// Reads the record at `file` (its bytes held by `shared`) as `d` states or
/// the file tells, the column `spec.force` against the time `d.time_column`
/// names.
pub(super) fn read(
    shared: &mut Shared,
    file: &Path,
    d: &RawData,
    spec: &CsvSpec,
) -> Result<(Series, Recorded), DataError> {
    let (bytes, in_memory) = match &shared.loan {
        Some(Loan::Record(_)) => (&[][..], true),
        Some(loan) => (loan.bytes(), false),
        None => (&[][..], false),
    };
    let format = match in_memory {
        true => Format::Memory,
        false => Format::of(file, bytes, d.format),
    };
    let sha256 = shared.sha256;
    if format == Format::Csv {
        let text = decode_record(bytes, file, spec)?;
        let series = parse_csv(&text, file, spec)?;
        let recorded = Recorded {
            format,
            channel: column_key(&spec.force),
            unit: named_unit(&spec.force),
            time_channel: Some(column_key(&spec.time)),
            time_unit: named_unit(&spec.time),
            sha256,
        };
        return Ok((series, recorded));
    }
    // A record in memory replaces a file: the file's encoding is not its.
    if !in_memory && (d.encoding.is_some() || d.decimal.is_some()) {
        return Err(DataError::Record {
            file: file.to_path_buf(),
            what: "\"encoding\" and \"decimal\"".into(),
            expected: "them only for a CSV record".into(),
            found: format!("a {format} file"),
        });
    }
    let record = match &mut shared.parsed {
        Some(record) => record,
        parsed => parsed.insert(Arc::new(
            detect::read(format, bytes).map_err(|e| detect::data_error(e, file))?,
        )),
    };
    let sel = Selection {
        // Arrays in memory have no waveform timing: their time is a column,
        // the first unless named, as in a CSV file.
        time: match in_memory {
            true => Some(&spec.time),
            false => d.time_column.as_ref(),
        },
        column: &spec.force,
        time_scale: spec.time_scale,
        scale: spec.force_scale,
    };
    let chosen = record.choose(&sel, file)?;
    let recorded = Recorded {
        format,
        channel: chosen.channel,
        unit: chosen.unit,
        time_channel: chosen.time_channel,
        time_unit: chosen.time_unit,
        sha256,
    };
    Ok((chosen.series, recorded))
}

/// A CSV column as result.json names it: its header name, or its index.
fn column_key(column: &Column) -> String {
    match column {
        Column::Name(n) => n.clone(),
        Column::Index(i) => format!("column {i} (0-based)"),
    }
}

/// The unit a CSV column's name states in brackets (`force [kN]`).
fn named_unit(column: &Column) -> Option<String> {
    match column {
        Column::Name(n) => crate::record::csv::bracketed_unit(n),
        Column::Index(_) => None,
    }
}

/// What experiment `e`'s channel `c` (`x` the campaign's experiment) read
/// from `data_file`, after refusing a record whose recorded units its
/// scales do not turn into the rig's: the measured channel's against the
/// output's unit, the time channel's against seconds.
pub(super) fn check_units(
    campaign: &Path,
    model: &CompiledRig,
    (e, c, x): (usize, usize, &RawExperiment),
    experiment: String,
    recorded: Recorded,
    data_file: &Path,
) -> Result<RecordUse, CampaignError> {
    use crate::record::units::refusal;
    let (output, scale, scale_at) = match &x.channels {
        Some(chs) => {
            let ch = &chs[c];
            let at = format!("experiments[{e}].channels[{c}].scale");
            (ch.output.as_str(), ch.scale, at)
        }
        None => {
            let name = model.desc.outputs.first().map_or("", |o| o.name.as_str());
            (
                name,
                x.data.force_scale,
                format!("experiments[{e}].data.scale"),
            )
        }
    };
    let output_unit = model
        .desc
        .outputs
        .iter()
        .find(|o| o.name == output)
        .map_or(String::new(), |o| o.unit.clone());
    let time_at = format!("experiments[{e}].data.time_scale");
    let checks = [
        (
            &recorded.unit,
            output_unit.as_str(),
            scale,
            output,
            scale_at,
            "scale",
        ),
        (
            &recorded.time_unit,
            "s",
            x.data.time_scale,
            "time",
            time_at,
            "time_scale",
        ),
    ];
    for (unit, expected, scale, what, at, key) in checks {
        let Some(unit) = unit else { continue };
        if expected.is_empty() {
            continue;
        }
        if let Some(why) = refusal(unit, expected, scale, what, key) {
            return Err(invalid(
                campaign,
                at,
                format!("a \"{key}\" that turns the record's unit into the rig's"),
                why,
            ));
        }
    }
    Ok(RecordUse {
        experiment,
        file: data_file.to_path_buf(),
        format: recorded.format.key(),
        channels: recorded
            .time_channel
            .map(|name| RecordedChannel {
                name,
                role: "time",
                unit: recorded.time_unit,
            })
            .into_iter()
            .chain([RecordedChannel {
                name: recorded.channel,
                role: "measured",
                unit: recorded.unit,
            }])
            .collect(),
        output: output.to_string(),
        output_unit,
        sha256: recorded.sha256,
    })
}
