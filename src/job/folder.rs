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
use crate::base::fsutil::{atomic_write, is_temp_name_of};
use crate::campaign::{Campaign, file_stem};

/// The manifest: every file name rigfit has written (or was about to write)
/// in the folder.
pub const MANIFEST_FILE: &str = "rigfit-files.json";

/// The lock file; a job holds an exclusive lock on it from before its first
/// evaluation to its end, and removes it when it ends (a killed job leaves
/// it, unlocked, for the next job to take).
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
    for e in campaign
        .validation
        .iter()
        .flat_map(|v| &v.problem.experiments)
    {
        files.push(super::validation_csv_name(&e.name));
    }
    files.extend(
        [
            "history.csv",
            "fitness.svg",
            crate::report::html::REPORT_FILE,
            CHECKPOINT_FILE,
            super::PROFILE_CHECKPOINT_FILE,
        ]
        .map(String::from),
    );
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
/// file is written: dropping it removes the lock file and releases the lock.
#[derive(Debug)]
pub struct OutputFolder {
    path: PathBuf,
    _lock: Lock,
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
        if let Ok(meta) = fs::metadata(path)
            && !meta.is_dir()
        {
            return Err(bad("it exists and is not a folder".into()));
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
    // Read as an input file is: a FIFO or a device planted under its name is
    // refused, not waited on.
    let text = match crate::base::fsutil::read_description(path) {
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

/// The temporary files of this job's outputs (`.<name>.tmp-<pid>-<token>`,
/// [`crate::base::fsutil::temp_path_for`]): what an atomic write interrupted
/// by a kill leaves. Only a job holding the lock calls this, so no other
/// rigfit job is writing them.
fn remove_stale_temporaries(dir: &Path, files: &[String]) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let manifest = MANIFEST_FILE.to_string();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let ours = files
            .iter()
            .chain([&manifest])
            .any(|f| is_temp_name_of(name, f));
        if ours {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// The folder's lock: the open lock file, and its path, removed when the job
/// ends (in every way but a kill).
#[derive(Debug)]
struct Lock {
    /// Held open: closing it releases the lock.
    _file: File,
    path: PathBuf,
}

impl Drop for Lock {
    fn drop(&mut self) {
        // Removed while still held, so that a job that opened it meanwhile
        // finds, once it has the lock, that the name no longer leads to it
        // and starts again (`lock`).
        let _ = fs::remove_file(&self.path);
    }
}

/// Takes the folder's lock, or says which job holds it. The lock file is
/// created without following a link (one planted under its name is refused,
/// its target untouched) and must be a plain file.
fn lock(dir: &Path) -> Result<Lock, JobError> {
    let path = dir.join(LOCK_FILE);
    let refused = |reason: String| JobError::OutputPath {
        path: dir.to_path_buf(),
        reason,
    };
    for _ in 0..100 {
        let mut options = OpenOptions::new();
        options.read(true).write(true).create(true).truncate(false);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt as _;
            let flags = rustix::fs::OFlags::NOFOLLOW | rustix::fs::OFlags::NONBLOCK;
            options.custom_flags(flags.bits() as i32);
        }
        let mut file = options.open(&path).map_err(|e| {
            let link = fs::symlink_metadata(&path).is_ok_and(|m| m.is_symlink());
            if link {
                refused(format!(
                    "its lock file {LOCK_FILE} is a symbolic link; rigfit never writes \
                     through a link (remove it)"
                ))
            } else {
                refused(format!("cannot create its lock file {LOCK_FILE}: {e}"))
            }
        })?;
        let meta = file
            .metadata()
            .map_err(|e| refused(format!("cannot read its lock file {LOCK_FILE}: {e}")))?;
        if !meta.is_file() {
            return Err(refused(format!(
                "its lock file {LOCK_FILE} exists and is not a plain file"
            )));
        }
        if !try_lock(&file) {
            let mut holder = String::new();
            let _ = file.read_to_string(&mut holder);
            return Err(JobError::OutputLocked {
                path: dir.to_path_buf(),
                holder: holder.trim().chars().take(40).collect(),
            });
        }
        if !same_file(&meta, &path) {
            // The job that held it ended and removed it; lock the new one.
            continue;
        }
        // Who holds it, for the message another job prints; best effort.
        let _ = file.set_len(0);
        let _ = file.rewind();
        let _ = writeln!(file, "pid {}", std::process::id());
        return Ok(Lock { _file: file, path });
    }
    Err(refused(format!(
        "its lock file {LOCK_FILE} keeps changing under other rigfit jobs"
    )))
}

/// Whether `path` still names the file `meta` was read from.
#[cfg(unix)]
fn same_file(meta: &fs::Metadata, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    fs::symlink_metadata(path).is_ok_and(|m| m.dev() == meta.dev() && m.ino() == meta.ino())
}

#[cfg(not(unix))]
fn same_file(_meta: &fs::Metadata, path: &Path) -> bool {
    path.is_file()
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
    fn the_lock_file_goes_with_the_job_and_a_planted_link_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let files = names(&["result.json"]);
        let held = OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap();
        assert!(dir.path().join(LOCK_FILE).is_file());
        drop(held);
        assert!(!dir.path().join(LOCK_FILE).exists());
        // Refused after the lock was taken: the lock file goes all the same.
        fs::write(dir.path().join("result.json"), b"mine").unwrap();
        OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap_err();
        assert!(!dir.path().join(LOCK_FILE).exists());
        fs::remove_file(dir.path().join("result.json")).unwrap();

        let record = dir.path().join("record.csv");
        fs::write(&record, b"t_s,force_N\n").unwrap();
        std::os::unix::fs::symlink(&record, dir.path().join(LOCK_FILE)).unwrap();
        let err = OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap_err();
        assert!(matches!(err, JobError::OutputPath { .. }), "{err}");
        assert!(err.to_string().contains("symbolic link"), "{err}");
        assert_eq!(fs::read(&record).unwrap(), b"t_s,force_N\n");
        assert!(fs::symlink_metadata(dir.path().join(LOCK_FILE)).is_ok_and(|m| m.is_symlink()));
    }

    #[test]
    fn a_fifo_in_place_of_the_manifest_is_refused_unread() {
        let dir = tempfile::tempdir().unwrap();
        let made = std::process::Command::new("mkfifo")
            .arg(dir.path().join(MANIFEST_FILE))
            .status();
        if !made.is_ok_and(|s| s.success()) {
            return;
        }
        let files = names(&["result.json"]);
        let err = OutputFolder::open(dir.path(), &files, &[], FolderMode::New).unwrap_err();
        assert!(err.to_string().contains("expected a regular file"), "{err}");
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
