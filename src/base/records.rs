//! Records held in memory instead of on disk: a caller with a record already
//! in memory (the Python package's `set_data`) lends it under a file name for
//! the length of one call, and [`crate::base::fsutil::read_record`] reads it
//! from there. The loan is per thread and ends with the call, so nothing
//! outlives it and no other thread sees it.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

thread_local! {
    static LENT: RefCell<Vec<(PathBuf, Vec<u8>)>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with `records` (path, CSV bytes) readable as if they were files
/// at those paths; a path on disk with the same name is not read meanwhile.
pub fn with_records<R>(records: &[(PathBuf, Vec<u8>)], f: impl FnOnce() -> R) -> R {
    struct Restore(Vec<(PathBuf, Vec<u8>)>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let before = std::mem::take(&mut self.0);
            LENT.with(|l| *l.borrow_mut() = before);
        }
    }
    let before = LENT.with(|l| std::mem::replace(&mut *l.borrow_mut(), records.to_vec()));
    let _restore = Restore(before);
    f()
}

/// The bytes lent under `path` by an enclosing [`with_records`], if any.
pub(crate) fn lent(path: &Path) -> Option<Vec<u8>> {
    LENT.with(|l| {
        l.borrow()
            .iter()
            .find(|(p, _)| p == path)
            .map(|(_, b)| b.clone())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lent_record_is_read_only_inside_the_call() {
        let path = PathBuf::from("/nonexistent/rigfit-lent.csv");
        let got = with_records(&[(path.clone(), b"t,f\n0,1\n".to_vec())], || {
            crate::base::fsutil::read_record(&path)
        });
        assert_eq!(got.unwrap(), b"t,f\n0,1\n");
        assert!(crate::base::fsutil::read_record(&path).is_err());
    }
}
