//! The private directory a native build is made in, and the checks before
//! its library is loaded.

use std::path::{Path, PathBuf};

use super::NativeError;

/// The prefix of the build directories under the temporary folder:
/// `rigfit-native-<pid>-<token>`.
const SCRATCH_PREFIX: &str = "rigfit-native-";

/// A new directory of this process's own under the temporary folder:
/// created by this call (never one that was there), private (mode 0700),
/// under a name no other process can guess, and never named alike twice in
/// one process (the dynamic loader takes a library path it has loaded before
/// for that library, even once the file is gone). The first call in a
/// process also removes the build directories of processes that are gone
/// (a kill during a build leaves one).
pub(super) fn scratch_dir() -> Result<Scratch, NativeError> {
    static SWEPT: std::sync::Once = std::sync::Once::new();
    let base = std::env::temp_dir();
    for _ in 0..100 {
        let token: u64 = rand::random();
        let dir = base.join(format!(
            "{SCRATCH_PREFIX}{}-{token:016x}",
            std::process::id()
        ));
        match create_private_dir(&dir) {
            Ok(scratch) => {
                SWEPT.call_once(|| sweep_stale(&base, &scratch));
                return Ok(scratch);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(source) => {
                return Err(NativeError::Io {
                    what: "creating",
                    path: dir,
                    source,
                });
            }
        }
    }
    Err(NativeError::Io {
        what: "creating",
        path: base,
        source: std::io::Error::other("no free rigfit-native-* name"),
    })
}

/// A build directory this process created, and what it was when created.
#[derive(Debug)]
pub(super) struct Scratch {
    pub(super) path: PathBuf,
    meta: std::fs::Metadata,
}

/// Creates `dir` (not following anything at its name: `mkdir` fails on an
/// existing link) with mode 0700, whatever the umask.
fn create_private_dir(dir: &Path) -> std::io::Result<Scratch> {
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::{DirBuilderExt as _, PermissionsExt as _};
        builder.mode(0o700);
        builder.create(dir)?;
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))?;
    }
    #[cfg(not(unix))]
    builder.create(dir)?;
    let meta = std::fs::symlink_metadata(dir)?;
    Ok(Scratch {
        path: dir.to_path_buf(),
        meta,
    })
}

/// Checks, before the library in `scratch` is loaded, that the directory is
/// still the private one this process made (so that nobody else can have
/// reached into it, whatever the umask gave the compiler's output) and that
/// `lib` is a plain file in it of the same owner, linked nowhere else.
pub(super) fn check_before_loading(scratch: &Scratch, lib: &Path) -> std::io::Result<()> {
    let refuse = |why: &str| Err(std::io::Error::other(why.to_string()));
    let dir = std::fs::symlink_metadata(&scratch.path)?;
    let file = std::fs::symlink_metadata(lib)?;
    if !dir.is_dir() || !file.is_file() {
        return refuse(
            "the build directory or the library is no longer a plain directory and file",
        );
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let made = &scratch.meta;
        if dir.dev() != made.dev() || dir.ino() != made.ino() || dir.mode() & 0o777 != 0o700 {
            return refuse("the build directory was replaced or opened to others");
        }
        if file.uid() != made.uid() || file.nlink() != 1 {
            return refuse("the library is not this process's own private file");
        }
    }
    Ok(())
}

/// Removes the build directories under `base` of processes that no longer
/// run, owned by the user this process runs as (the owner of `ours`).
fn sweep_stale(base: &Path, ours: &Scratch) {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::MetadataExt as _;
        let Ok(entries) = std::fs::read_dir(base) else {
            return;
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(SCRATCH_PREFIX)) else {
                continue;
            };
            let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
                continue;
            };
            let path = entry.path();
            let Ok(meta) = std::fs::symlink_metadata(&path) else {
                continue;
            };
            let alive = Path::new("/proc").join(pid.to_string()).exists();
            if !alive && meta.is_dir() && meta.uid() == ours.meta.uid() && path != ours.path {
                log::debug!(
                    "removing {}, left by a build that was killed",
                    path.display()
                );
                let _ = std::fs::remove_dir_all(&path);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (base, ours);
}

/// [`NativeError::Io`] of `what` was done to `path`, from its cause.
pub(super) fn io(what: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> NativeError {
    let path = path.to_path_buf();
    move |source| NativeError::Io { what, path, source }
}

/// Writes `bytes` into a new file at `path` (failing where anything is
/// there already).
pub(super) fn write_new(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .and_then(|mut f| std::io::Write::write_all(&mut f, bytes))
}
