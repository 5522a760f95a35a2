//! The output folder a job owns: the files it writes there, the manifest of the
//! files rigfit has written, and the lock that keeps a second job out.
//!
//! rigfit never replaces a file it did not write. Before any work a job lists
//! the files it will write ([`output_files`]) and refuses when one of them
//! exists but is not in the folder's manifest (`rigfit-files.json`), or is one
//! of the campaign's own input files. The manifest is written before the first
//! result file, so a job killed at any moment leaves a folder the next job
//! recognises as its own.

use std::collections::BTreeSet;
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Seek, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{CHECKPOINT_FILE, JobError};
use crate::base::fsutil::atomic_write;
use crate::campaign::{Campaign, file_stem};

/// The manifest: every file name rigfit has written (or was about to write)
/// in the folder.
pub const MANIFEST_FILE: &str = "rigfit-files.json";

/// The lock file; a job holds an exclusive lock on it from before its first
/// evaluation to its end.
pub const LOCK_FILE: &str = ".rigfit.lock";

/// The files a job of `campaign` writes into its output folder, in the order of
/// the README's table.
pub fn output_files(campaign: &Campaign) -> Vec<String> {
    let mut files = vec!["result.json".to_string()];
    for e in &campaign.problem.experiments {
        let stem = file_stem(&e.name);
        files.push(format!("{stem}.csv"));
        files.push(format!("fit_{stem}.svg"));
    }
    files.extend(["history.csv", "fitness.svg", CHECKPOINT_FILE].map(String::from));
    files
}

#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    /// Says what the file is to someone who finds it.
    about: String,
    /// File names, relative to the folder.
    files: BTreeSet<String>,
}

const ABOUT: &str = "files written by rigfit in this folder; rigfit replaces only these";

/// What a job may do with a folder that already holds results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FolderMode {
    /// A new job: the folder must hold no earlier result or checkpoint.
    New,
    /// `--overwrite`: rigfit's own earlier files may be replaced.
    Overwrite,
    /// `--resume`: the folder must hold a checkpoint.
    Resume,
}

/// An output folder, created, locked and checked. Hold it until the job's last
/// file is written: dropping it releases the lock.
#[derive(Debug)]
pub struct OutputFolder {
    path: PathBuf,
    _lock: File,
}

impl OutputFolder {
    /// Creates `path` if needed, locks it against other rigfit jobs and checks
    /// that every file in `files` either does not exist or was written by
    /// rigfit and is none of `inputs`; then records `files` in the manifest and
    /// removes temporary files that a killed job left behind.
    pub fn open(
        path: &Path,
        files: &[String],
        inputs: &[PathBuf],
        mode: FolderMode,
    ) -> Result<OutputFolder, JobError> {
        let bad = |reason: String| JobError::OutputPath {
            path: path.to_path_buf(),
            reason,
        };
        if path.as_os_str().as_encoded_bytes().contains(&0) {
            return Err(bad("a path cannot hold a NUL character".into()));
        }
        if let Ok(meta) = fs::metadata(path) {
            if !meta.is_dir() {
                return Err(bad("it exists and is not a folder".into()));
            }
        }
        let checkpoint = path.join(CHECKPOINT_FILE);
        if mode == FolderMode::Resume && !checkpoint.is_file() {
            // Checked again under the lock below; this keeps a mistyped folder
            // from being created.
            return Err(JobError::NoCheckpoint { path: checkpoint });
        }
        fs::create_dir_all(path).map_err(|e| bad(format!("cannot create it: {e}")))?;
        let lock = lock(path)?;

        let manifest_path = path.join(MANIFEST_FILE);
        let mut manifest = read_manifest(&manifest_path)?;
        let inputs: Vec<PathBuf> = inputs
            .iter()
            .filter_map(|p| p.canonicalize().ok())
            .collect();
        for name in files {
            let target = path.join(name);
            let Ok(meta) = fs::symlink_metadata(&target) else {
                continue;
            };
            let input = target.canonicalize().is_ok_and(|t| inputs.contains(&t));
            if input {
                return Err(JobError::ForeignFile {
                    path: target,
                    what: "is one of the campaign's input files".into(),
                });
            }
            if !meta.is_file() {
                return Err(JobError::ForeignFile {
                    path: target,
                    what: "exists and is not a plain file".into(),
                });
            }
            if !manifest.files.contains(name) {
                return Err(JobError::ForeignFile {
                    path: target,
                    what: format!(
                        "exists and was not written by rigfit (it is not in {MANIFEST_FILE})"
                    ),
                });
            }
        }
        match mode {
            FolderMode::Resume if !checkpoint.is_file() => {
                return Err(JobError::NoCheckpoint { path: checkpoint });
            }
            FolderMode::New => {
                for found in [CHECKPOINT_FILE, "result.json"] {
                    if path.join(found).exists() {
                        return Err(JobError::OutputInUse {
                            path: path.to_path_buf(),
                            found: found.to_string(),
                        });
                    }
                }
            }
            _ => {}
        }
        remove_stale_temporaries(path, files);
        let before = manifest.files.len();
        manifest.files.extend(files.iter().cloned());
        if before != manifest.files.len() || manifest.about != ABOUT {
            manifest.about = ABOUT.into();
            let text = serde_json::to_string_pretty(&manifest).expect("manifest serialises") + "\n";
            atomic_write(&manifest_path, text.as_bytes()).map_err(|source| JobError::Write {
                path: manifest_path.clone(),
                source,
            })?;
        }
        Ok(OutputFolder {
            path: path.to_path_buf(),
            _lock: lock,
        })
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

fn read_manifest(path: &Path) -> Result<Manifest, JobError> {
    let text = match fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Manifest::default()),
        Err(e) => {
            return Err(JobError::ForeignFile {
                path: path.to_path_buf(),
                what: format!("cannot be read ({e})"),
            });
        }
    };
    serde_json::from_str(&text).map_err(|e| JobError::ForeignFile {
        path: path.to_path_buf(),
        what: format!("is not a rigfit manifest ({e})"),
    })
}

/// `.<name>.tmp-<pid>` files of this job's outputs: what an atomic write
/// interrupted by a kill leaves. Only a job holding the lock calls this, so no
/// other rigfit job is writing them.
fn remove_stale_temporaries(dir: &Path, files: &[String]) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let manifest = MANIFEST_FILE.to_string();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some((base, pid)) = name.strip_prefix('.').and_then(|n| n.rsplit_once(".tmp-")) else {
            continue;
        };
        let ours = files.iter().chain([&manifest]).any(|f| f == base);
        if ours && !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Takes the folder's lock, or says which job holds it.
fn lock(dir: &Path) -> Result<File, JobError> {
    let path = dir.join(LOCK_FILE);
    let mut file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(|e| JobError::OutputPath {
            path: dir.to_path_buf(),
            reason: format!("cannot create its lock file {LOCK_FILE}: {e}"),
        })?;
    if !try_lock(&file) {
        let mut holder = String::new();
        let _ = file.read_to_string(&mut holder);
        return Err(JobError::OutputLocked {
            path: dir.to_path_buf(),
            holder: holder.trim().chars().take(40).collect(),
        });
    }
    // Who holds it, for the message another job prints; best effort.
    let _ = file.set_len(0);
    let _ = file.rewind();
    let _ = writeln!(file, "pid {}", std::process::id());
    Ok(file)
}

#[cfg(unix)]
fn try_lock(file: &File) -> bool {
    use rustix::fs::{FlockOperation, flock};
    flock(file, FlockOperation::NonBlockingLockExclusive).is_ok()
}

#[cfg(not(unix))]
fn try_lock(_file: &File) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_second_open_of_a_locked_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let files = names(&["result.json"]);
        let first = OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap();
        let err = OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap_err();
        assert!(matches!(err, JobError::OutputLocked { .. }), "{err}");
        drop(first);
        OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap();
    }

    #[test]
    fn a_foreign_file_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("v2.csv"), b"mine").unwrap();
        let files = names(&["result.json", "v2.csv"]);
        for mode in [FolderMode::New, FolderMode::Overwrite] {
            let err = OutputFolder::open(dir.path(), &files, &[], mode).unwrap_err();
            assert!(err.to_string().contains("not written by rigfit"), "{err}");
        }
        assert_eq!(fs::read(dir.path().join("v2.csv")).unwrap(), b"mine");
        assert!(!dir.path().join(MANIFEST_FILE).exists());
    }

    #[test]
    fn files_in_the_manifest_may_be_replaced_and_stale_temporaries_go() {
        let dir = tempfile::tempdir().unwrap();
        let files = names(&["result.json", "v2.csv"]);
        drop(OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap());
        fs::write(dir.path().join("v2.csv"), b"old result").unwrap();
        fs::write(dir.path().join(".v2.csv.tmp-123"), b"torn").unwrap();
        fs::write(dir.path().join(".notes.tmp-123"), b"not ours").unwrap();
        drop(OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap());
        assert!(!dir.path().join(".v2.csv.tmp-123").exists());
        assert!(dir.path().join(".notes.tmp-123").exists());
    }

    #[test]
    fn an_input_file_is_never_a_target() {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("data.csv");
        fs::write(&data, b"t,f\n").unwrap();
        let files = names(&["data.csv"]);
        // Even a manifest that lists it does not make the record replaceable.
        let m = Manifest {
            about: ABOUT.into(),
            files: files.iter().cloned().collect(),
        };
        fs::write(
            dir.path().join(MANIFEST_FILE),
            serde_json::to_string(&m).unwrap(),
        )
        .unwrap();
        let err =
            OutputFolder::open(dir.path(), &files, &[data], FolderMode::Overwrite).unwrap_err();
        assert!(err.to_string().contains("input"), "{err}");
    }

    #[test]
    fn a_file_in_place_of_the_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("out");
        fs::write(&file, b"x").unwrap();
        for p in [file.clone(), file.join("sub")] {
            let err = OutputFolder::open(&p, &[], &[], FolderMode::New).unwrap_err();
            assert!(matches!(err, JobError::OutputPath { .. }), "{err}");
        }
    }
}
