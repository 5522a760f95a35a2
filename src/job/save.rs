//! A finished result's files written again into a folder (the Python
//! package's `FitResult.save`), by the rules a job's own outputs follow: the
//! folder locked and checked first ([`OutputFolder`]: never over a file
//! rigfit did not write, never through a link), and every file written
//! whole to a temporary sibling before any is renamed into place, so a
//! failure part way (a full disk) leaves the folder as it was.

use std::fs;
use std::path::{Component, Path, PathBuf};

use super::{FolderMode, JobError, LOCK_FILE, MANIFEST_FILE, OutputFolder};
use crate::base::fsutil::{sync_parent, write_temporary};

/// Writes `files` (name, bytes) into `folder` (created if missing) as one
/// set: `mode` [`FolderMode::New`] refuses a folder that already holds a
/// result, [`FolderMode::Overwrite`] replaces rigfit's own earlier files.
/// A manifest among `files` is not copied: the folder's own records the
/// names written. A name that is not a plain file name in the folder is
/// refused before anything is written.
pub fn save_files(
    folder: &Path,
    files: &[(String, Vec<u8>)],
    mode: FolderMode,
) -> Result<(), JobError> {
    let files: Vec<&(String, Vec<u8>)> = files
        .iter()
        .filter(|(name, _)| name != MANIFEST_FILE)
        .collect();
    for (name, _) in &files {
        check_name(folder, name)?;
    }
    let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    let out = OutputFolder::open(folder, &names, &[], mode)?;
    let mut written: Vec<(PathBuf, PathBuf)> = Vec::with_capacity(files.len());
    for (name, bytes) in &files {
        let target = out.path().join(name);
        match write_temporary(&target, bytes) {
            Ok(tmp) => written.push((tmp, target)),
            Err(source) => {
                for (tmp, _) in &written {
                    let _ = fs::remove_file(tmp);
                }
                return Err(JobError::Write {
                    path: target,
                    source,
                });
            }
        }
    }
    let mut failed = None;
    for (tmp, target) in &written {
        if failed.is_some() {
            let _ = fs::remove_file(tmp);
            continue;
        }
        if let Err(source) = fs::rename(tmp, target) {
            let _ = fs::remove_file(tmp);
            failed = Some(JobError::Write {
                path: target.clone(),
                source,
            });
        }
    }
    if let Some((_, target)) = written.first() {
        sync_parent(target);
    }
    failed.map_or(Ok(()), Err)
}

/// A name a result may hold: one plain component, not hidden, not the lock.
fn check_name(folder: &Path, name: &str) -> Result<(), JobError> {
    let mut parts = Path::new(name).components();
    let plain = matches!(parts.next(), Some(Component::Normal(_))) && parts.next().is_none();
    if plain && !name.starts_with('.') && name != LOCK_FILE && !name.contains('\0') {
        return Ok(());
    }
    Err(JobError::OutputPath {
        path: folder.to_path_buf(),
        reason: format!(
            "a result's file must be a plain name in the folder, found {name:?}; \
             rigfit writes nothing outside it"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(text: &str) -> Vec<(String, Vec<u8>)> {
        ["result.json", "history.csv", "v1.csv"]
            .iter()
            .map(|n| (n.to_string(), format!("{n}: {text}").into_bytes()))
            .collect()
    }

    #[test]
    fn writes_every_file_and_its_manifest() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r");
        save_files(&out, &files("a"), FolderMode::New).unwrap();
        assert_eq!(fs::read(out.join("v1.csv")).unwrap(), b"v1.csv: a");
        let manifest = fs::read_to_string(out.join(MANIFEST_FILE)).unwrap();
        assert!(manifest.contains("history.csv"), "{manifest}");
        // A second save: refused as new, replaces rigfit's files as overwrite.
        let again = save_files(&out, &files("b"), FolderMode::New).unwrap_err();
        assert!(matches!(again, JobError::OutputInUse { .. }), "{again}");
        save_files(&out, &files("b"), FolderMode::Overwrite).unwrap();
        assert_eq!(fs::read(out.join("v1.csv")).unwrap(), b"v1.csv: b");
    }

    #[test]
    fn never_replaces_a_file_rigfit_did_not_write() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r");
        save_files(&out, &files("a"), FolderMode::New).unwrap();
        let mut more = files("b");
        more.push(("notes.csv".into(), b"ours".to_vec()));
        fs::write(out.join("notes.csv"), b"the user's").unwrap();
        let e = save_files(&out, &more, FolderMode::Overwrite).unwrap_err();
        assert!(matches!(e, JobError::ForeignFile { .. }), "{e}");
        assert_eq!(fs::read(out.join("notes.csv")).unwrap(), b"the user's");
        assert_eq!(fs::read(out.join("v1.csv")).unwrap(), b"v1.csv: a");
    }

    #[cfg(unix)]
    #[test]
    fn never_writes_through_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r");
        fs::create_dir(&out).unwrap();
        let victim = dir.path().join("campaign.json");
        fs::write(&victim, b"precious").unwrap();
        std::os::unix::fs::symlink(&victim, out.join("result.json")).unwrap();
        let dangling = dir.path().join("nowhere.csv");
        std::os::unix::fs::symlink(&dangling, out.join("history.csv")).unwrap();
        for mode in [FolderMode::New, FolderMode::Overwrite] {
            assert!(save_files(&out, &files("a"), mode).is_err());
        }
        assert_eq!(fs::read(&victim).unwrap(), b"precious");
        assert!(!dangling.exists());
    }

    #[test]
    fn refuses_names_outside_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r");
        for bad in [
            "../x.csv",
            "/tmp/x.csv",
            "a/b.csv",
            ".hidden",
            "",
            LOCK_FILE,
        ] {
            let e = save_files(&out, &[(bad.into(), vec![])], FolderMode::New).unwrap_err();
            assert!(matches!(e, JobError::OutputPath { .. }), "{bad}: {e}");
        }
        assert!(!out.exists(), "nothing is created for a refused name");
    }

    #[test]
    fn a_failed_write_leaves_the_folder_as_it_was() {
        // A name whose temporary sibling is longer than a file name may be
        // stands in for a full disk: it fails after the files before it were
        // written to their temporaries, and the set is written all or nothing.
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r");
        save_files(&out, &files("a"), FolderMode::New).unwrap();
        let mut more = files("b");
        more.insert(1, (format!("{}.csv", "x".repeat(240)), b"long".to_vec()));
        let e = save_files(&out, &more, FolderMode::Overwrite).unwrap_err();
        assert!(matches!(e, JobError::Write { .. }), "{e}");
        assert_eq!(
            fs::read(out.join("result.json")).unwrap(),
            b"result.json: a"
        );
        assert_eq!(fs::read(out.join("v1.csv")).unwrap(), b"v1.csv: a");
        let left: Vec<_> = fs::read_dir(&out)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
    }
}
