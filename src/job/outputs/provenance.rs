//! What result.json says of where a fit came from and what it found beside
//! the numbers: every input file with its SHA-256, and the rig's natural
//! frequencies at the fitted values.

use sha2::{Digest, Sha256};

use super::summary::{InputDigest, NaturalFrequencies, RecordDigest};
use crate::campaign::Campaign;
use crate::model::modes::ModeReport;

/// Every file `campaign` was read from with its SHA-256: a record's as it
/// was read when the campaign was built (a record lent from memory
/// included), any other file's read again now; a file that no longer reads
/// is left out. A path inside the campaign's folder is given relative to
/// it, as the campaign names it.
pub(super) fn input_digests(campaign: &Campaign) -> Vec<InputDigest> {
    let dir = campaign.path.parent().filter(|d| !d.as_os_str().is_empty());
    let records = campaign
        .records
        .iter()
        .chain(campaign.validation.iter().flat_map(|v| v.records.iter()));
    let read: Vec<_> = records.map(|r| (&r.file, r.sha256)).collect();
    campaign
        .inputs
        .iter()
        .enumerate()
        .filter_map(|(i, path)| {
            let sha256 = match read.iter().find(|(f, _)| *f == path) {
                Some((_, sha)) => *sha,
                None => Sha256::digest(crate::base::fsutil::read_record(path).ok()?).into(),
            };
            let shown = match dir {
                Some(d) if i > 0 => path.strip_prefix(d).unwrap_or(path),
                _ => path.as_path(),
            };
            Some(InputDigest {
                path: shown.display().to_string(),
                sha256: hex(&sha256),
            })
        })
        .collect()
}

/// What each experiment read of its record, with the record's SHA-256 as
/// read when the campaign was built.
pub(super) fn record_digests(campaign: &Campaign) -> Vec<RecordDigest> {
    let dir = campaign.path.parent().filter(|d| !d.as_os_str().is_empty());
    campaign
        .records
        .iter()
        .map(|r| {
            let shown = match dir {
                Some(d) => r.file.strip_prefix(d).unwrap_or(&r.file),
                None => r.file.as_path(),
            };
            RecordDigest {
                path: shown.display().to_string(),
                sha256: hex(&r.sha256),
                read: r.clone(),
            }
        })
        .collect()
}

fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    bytes.iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// Each experiment's undamped natural frequencies (Hz) at `full` (the
/// parameters and clock offset of each experiment), linearised where
/// `rigfit modes` linearises (the engaged, unbroken rig at rest); an
/// experiment whose linearisation is not finite is left out.
pub(super) fn natural_frequencies(
    campaign: &Campaign,
    full: &[(Vec<f64>, f64)],
) -> Vec<NaturalFrequencies> {
    campaign
        .problem
        .experiments
        .iter()
        .zip(full)
        .filter_map(|(exp, (params, _))| {
            let lin = campaign.model.linearise(params, &exp.drive);
            let report = ModeReport::new(&lin).ok()?;
            Some(NaturalFrequencies {
                experiment: exp.name.clone(),
                hz: report.modes.iter().map(|m| m.frequency_hz).collect(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn sha256_of_abc_is_the_standard_one() {
        use sha2::Digest as _;
        assert_eq!(
            super::hex(&sha2::Sha256::digest(b"abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
