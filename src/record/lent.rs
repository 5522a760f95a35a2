//! Records a caller holds in memory, lent to a campaign under the paths its
//! `"data"` keys name: a record's channels as arrays (the Python package's
//! DataFrames, never written out as text) or a file's bytes read once
//! before (so that an edited campaign is rebuilt from exactly the bytes it
//! was first built from). A path lent is never read from disk; every other
//! path is.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{Format, Record};

/// One record lent under a path.
#[derive(Debug, Clone)]
pub enum Loan {
    /// A record file's bytes, read in its format as the file would be.
    Bytes(Arc<[u8]>),
    /// A record's channels (in [`Format::Memory`]); a campaign's column keys
    /// choose among them as among a CSV file's columns.
    Record(Arc<Record>),
}

/// The records lent to one campaign build, by path.
#[derive(Debug, Clone, Default)]
pub struct Lent {
    loans: Vec<(PathBuf, Loan)>,
}

impl Lent {
    /// Nothing lent: every record is read from its file.
    pub fn none() -> Lent {
        Lent::default()
    }

    /// Lends `loan` under `path` (replacing an earlier loan of that path).
    pub fn lend(&mut self, path: PathBuf, loan: Loan) {
        match self.loans.iter_mut().find(|(p, _)| *p == path) {
            Some((_, l)) => *l = loan,
            None => self.loans.push((path, loan)),
        }
    }

    /// What is lent under `path`, if anything.
    pub fn get(&self, path: &Path) -> Option<&Loan> {
        self.loans.iter().find(|(p, _)| p == path).map(|(_, l)| l)
    }

    /// The record at `path`: lent, or read from its file through
    /// [`crate::base::fsutil::read_record`] (a regular file within the
    /// record size limit).
    pub fn read(&self, path: &Path) -> io::Result<Loan> {
        match self.get(path) {
            Some(loan) => Ok(loan.clone()),
            None => Ok(Loan::Bytes(crate::base::fsutil::read_record(path)?.into())),
        }
    }
}

impl Loan {
    /// The bytes a digest of this record is taken over: a file's own, or a
    /// record's channels in the layout of `record/bits.rs`, so two records
    /// digest alike exactly when they hold the same names, units, timings
    /// and bits.
    pub fn digest_bytes(&self) -> std::borrow::Cow<'_, [u8]> {
        match self {
            Loan::Bytes(b) => std::borrow::Cow::Borrowed(b),
            Loan::Record(r) => std::borrow::Cow::Owned(canonical(r)),
        }
    }

    /// The bytes of a file loan (empty for a record in memory).
    pub fn bytes(&self) -> &[u8] {
        match self {
            Loan::Bytes(b) => b,
            Loan::Record(_) => &[],
        }
    }
}

/// A record from named columns of equal length, in [`Format::Memory`]: the
/// channels a caller's arrays make, each with the unit its name states in
/// brackets as a CSV header's does (`force [kN]`), none with a timing.
/// `None` when the names and columns do not pair up or differ in length.
pub fn record_of(names: Vec<String>, columns: Vec<Vec<f64>>) -> Option<Record> {
    let n = columns.first().map_or(0, Vec::len);
    if names.len() != columns.len() || columns.iter().any(|c| c.len() != n) {
        return None;
    }
    let channels = names
        .into_iter()
        .zip(columns)
        .map(|(name, values)| super::Channel {
            unit: super::csv::bracketed_unit(&name),
            name,
            values,
            timing: None,
        })
        .collect();
    Some(Record {
        format: Format::Memory,
        channels,
    })
}

fn canonical(r: &Record) -> Vec<u8> {
    let values: usize = r.channels.iter().map(|c| c.values.len()).sum();
    let mut out = Vec::with_capacity(8 * values + 64 * r.channels.len());
    super::bits::channels(&mut out, &r.channels);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(names: &[&str], columns: &[&[f64]]) -> Record {
        record_of(
            names.iter().map(|s| s.to_string()).collect(),
            columns.iter().map(|c| c.to_vec()).collect(),
        )
        .unwrap()
    }

    #[test]
    fn a_lent_path_is_not_read_from_disk_and_another_is() {
        let mut lent = Lent::none();
        let path = PathBuf::from("/nonexistent/rigfit-lent.csv");
        lent.lend(path.clone(), Loan::Bytes(Arc::from(&b"t,f\n0,1\n"[..])));
        assert_eq!(lent.read(&path).unwrap().bytes(), b"t,f\n0,1\n");
        assert!(lent.read(Path::new("/nonexistent/other.csv")).is_err());
        lent.lend(path.clone(), Loan::Bytes(Arc::from(&b"x"[..])));
        assert_eq!(lent.read(&path).unwrap().bytes(), b"x");
    }

    #[test]
    fn records_digest_alike_only_with_the_same_names_and_bits() {
        let digest = |r: Record| Loan::Record(Arc::new(r)).digest_bytes().into_owned();
        let a = digest(record(&["t", "f"], &[&[0.0, 1.0], &[2.0, 3.0]]));
        assert_eq!(a, digest(record(&["t", "f"], &[&[0.0, 1.0], &[2.0, 3.0]])));
        assert_ne!(a, digest(record(&["t", "g"], &[&[0.0, 1.0], &[2.0, 3.0]])));
        assert_ne!(a, digest(record(&["t", "f"], &[&[0.0, 1.0], &[2.0, -3.0]])));
        assert_ne!(a, digest(record(&["t", "f"], &[&[-0.0, 1.0], &[2.0, 3.0]])));
        // A name's end is not confused with the next channel's start.
        assert_ne!(
            digest(record(&["ab", "c"], &[&[], &[]])),
            digest(record(&["a", "bc"], &[&[], &[]]))
        );
    }

    #[test]
    fn columns_that_do_not_pair_up_make_no_record() {
        assert!(record_of(vec!["t".into()], vec![vec![0.0], vec![1.0]]).is_none());
        assert!(record_of(vec!["t".into(), "f".into()], vec![vec![0.0], vec![]]).is_none());
    }
}
