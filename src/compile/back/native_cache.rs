//! Native lane builds kept between runs: the library a build made, under
//! `native/` in rigfit's cache folder (`RIGFIT_CACHE_DIR`, else
//! `$XDG_CACHE_HOME/rigfit`, else `~/.cache/rigfit`), named by a 128-bit hash
//! of everything that made it: the C source, the compiler's command and
//! flags, and what the compiler says of itself and of this processor (its
//! predefined macros under `-march=native`: its version and every
//! instruction-set extension it would use). A later process that would build
//! the same source with the same compiler for the same processor loads it
//! instead of compiling, which on a 2-core machine saves the 0.3–0.8 s a
//! short job otherwise spends interpreting beside the compiler.
//!
//! A kept library is read only through a descriptor opened without
//! following a link and checked to be a plain file of this user's, written
//! by nobody else (not group- or world-writable) and linked nowhere else;
//! its bytes then go into the build's own private folder and are loaded
//! from there, as a library just compiled is, so what was checked is what is
//! loaded. It is kept by writing a private temporary file (mode 0600) and
//! renaming it into place, in a folder of mode 0700; builds are read from
//! and written into that folder only while it is a plain folder of the
//! user's that nobody else may write. A temporary file left by a process
//! killed meanwhile is swept by the next that keeps a build. Linux only;
//! elsewhere every process builds its own.

use std::path::{Path, PathBuf};

/// The folder kept builds go in, under rigfit's cache folder; `None` where
/// no cache folder is set, and off Linux (nothing is kept there, and the
/// compiler is not asked for a key).
pub fn folder() -> Option<PathBuf> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    crate::base::fsutil::cache_dir().map(|d| d.join("native"))
}

/// The name of the kept build for `key` (the text of everything that made
/// it): two 64-bit hashes of it, each seeded differently.
pub fn file_name(key: &str) -> String {
    use std::hash::{Hash as _, Hasher as _};
    let half = |seed: u64| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        seed.hash(&mut h);
        key.hash(&mut h);
        h.finish()
    };
    format!("lanes-{:016x}{:016x}.so", half(1), half(2))
}

/// The bytes of the kept build for `key`, read through a descriptor opened
/// and checked ([`checked_open`]); `None` where there is none or it may not
/// be trusted.
#[cfg(target_os = "linux")]
pub fn find(key: &str) -> Option<Vec<u8>> {
    use std::io::Read as _;
    let dir = folder()?;
    let path = dir.join(file_name(key));
    let read = private_dir(&dir)
        .and_then(|()| checked_open(&path))
        .and_then(|mut f| {
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes)?;
            Ok(bytes)
        });
    match read {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            if e.kind() != std::io::ErrorKind::NotFound {
                log::info!("not loading the kept build {}: {e}", path.display());
            }
            None
        }
    }
}

/// Elsewhere nothing is kept.
#[cfg(not(target_os = "linux"))]
pub fn find(_key: &str) -> Option<Vec<u8>> {
    None
}

/// Whether `dir` is a folder (not a link to one) of this process's user that
/// nobody else may write: the only kind kept builds are read from or written
/// into.
#[cfg(target_os = "linux")]
fn private_dir(dir: &Path) -> std::io::Result<()> {
    let meta = std::fs::symlink_metadata(dir)?;
    let why = if meta.is_dir() {
        not_private(&meta)
    } else {
        Some("not a folder")
    };
    match why {
        Some(why) => Err(std::io::Error::other(format!("{}: {why}", dir.display()))),
        None => Ok(()),
    }
}

/// Why what `meta` describes is not this process's user's alone to write:
/// another user's, or writable by group or others; `None` where it is.
#[cfg(target_os = "linux")]
fn not_private(meta: &std::fs::Metadata) -> Option<&'static str> {
    use std::os::unix::fs::MetadataExt as _;
    if meta.uid() != rustix::process::geteuid().as_raw() {
        Some("owned by another user")
    } else if meta.mode() & 0o022 != 0 {
        Some("writable by others")
    } else {
        None
    }
}

/// `path` opened without following a link at it, if it is a plain file
/// owned by this process's user, writable by nobody else and linked
/// nowhere else.
#[cfg(target_os = "linux")]
pub fn checked_open(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::{MetadataExt as _, OpenOptionsExt as _};
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(rustix::fs::OFlags::NOFOLLOW.bits() as i32)
        .open(path)?;
    let meta = file.metadata()?;
    let why = if !meta.is_file() {
        Some("not a plain file")
    } else if meta.nlink() != 1 {
        Some("linked elsewhere too")
    } else {
        not_private(&meta)
    };
    match why {
        Some(why) => Err(std::io::Error::other(why)),
        None => Ok(file),
    }
}

/// Keeps the library at `lib` (just built and loaded) as the build for
/// `key`: into a private temporary file of the folder (made mode 0700 where
/// it is not there), then renamed into place. Failing leaves nothing kept
/// and is only logged: the build itself is done.
#[cfg(target_os = "linux")]
pub fn keep(key: &str, lib: &Path) {
    let Some(dir) = folder() else { return };
    if let Err(e) = keep_in(&dir, &file_name(key), lib) {
        log::info!("native lane code not kept in {}: {e}", dir.display());
    }
}

/// Elsewhere nothing is kept.
#[cfg(not(target_os = "linux"))]
pub fn keep(_key: &str, _lib: &Path) {}

#[cfg(target_os = "linux")]
fn keep_in(dir: &Path, name: &str, lib: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::DirBuilderExt as _;
    if let Some(parent) = dir.parent() {
        std::fs::create_dir_all(parent)?;
    }
    match std::fs::DirBuilder::new().mode(0o700).create(dir) {
        Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => return Err(e),
        _ => {}
    }
    private_dir(dir)?;
    static SWEPT: std::sync::Once = std::sync::Once::new();
    SWEPT.call_once(|| sweep_temporaries(dir));
    let bytes = std::fs::read(lib)?;
    crate::base::fsutil::atomic_write_private(&dir.join(name), &bytes)
}

/// Removes the temporary files of `dir` that a process killed while keeping
/// a build left (`.lanes-<hash>.so.tmp-<pid>-<token>`, its process gone, a
/// plain file of this user's).
#[cfg(target_os = "linux")]
fn sweep_temporaries(dir: &Path) {
    use std::os::unix::fs::MetadataExt as _;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some((_, pid)) = crate::base::fsutil::temp_name_parts(name)
            .filter(|(base, _)| base.starts_with("lanes-") && base.ends_with(".so"))
        else {
            continue;
        };
        let alive = Path::new("/proc").join(pid).exists();
        let path = entry.path();
        let ours = std::fs::symlink_metadata(&path)
            .is_ok_and(|m| m.is_file() && m.uid() == rustix::process::geteuid().as_raw());
        if !alive && ours {
            let _ = std::fs::remove_file(&path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_differ_with_any_part_of_the_key_and_repeat_for_the_same() {
        assert_eq!(file_name("a|b"), file_name("a|b"));
        assert_ne!(file_name("a|b"), file_name("a|c"));
        assert_eq!(file_name("x").len(), "lanes-".len() + 32 + ".so".len());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn only_a_private_plain_file_of_ours_opens() {
        use std::os::unix::fs::PermissionsExt as _;
        let dir = tempfile::tempdir().unwrap();
        let lib = dir.path().join("built.so");
        std::fs::write(&lib, b"not really a library").unwrap();
        let kept = dir.path().join("kept");
        keep_in(&kept, "lanes-x.so", &lib).unwrap();
        let path = kept.join("lanes-x.so");
        let mode = |p: &Path| std::fs::symlink_metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&kept), 0o700);
        assert_eq!(mode(&path), 0o600);
        assert!(checked_open(&path).is_ok());
        // A link to it, a second name for it, or a file others may write is
        // refused.
        let link = kept.join("link.so");
        std::os::unix::fs::symlink(&path, &link).unwrap();
        assert!(checked_open(&link).is_err());
        let hard = kept.join("hard.so");
        std::fs::hard_link(&path, &hard).unwrap();
        assert!(checked_open(&path).is_err());
        std::fs::remove_file(&hard).unwrap();
        assert!(checked_open(&path).is_ok());
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o620)).unwrap();
        assert!(checked_open(&path).is_err());
        // Kept again, it is private again, and nothing temporary is left.
        keep_in(&kept, "lanes-x.so", &lib).unwrap();
        assert_eq!(mode(&path), 0o600);
        let names: Vec<_> = std::fs::read_dir(&kept)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        // A temporary file of a process that is gone is swept; a live
        // process's, and anything not of that shape, stay.
        let gone = kept.join(".lanes-x.so.tmp-999999999-0123456789abcdef");
        let live = kept.join(format!(
            ".lanes-x.so.tmp-{}-0123456789abcdef",
            std::process::id()
        ));
        let other = kept.join(".notes.tmp-999999999-0123456789abcdef");
        for p in [&gone, &live, &other] {
            std::fs::write(p, b"").unwrap();
        }
        sweep_temporaries(&kept);
        assert!(!gone.exists() && live.exists() && other.exists());
        // A folder others may write, or a link planted in the folder's place,
        // is neither written into nor read from.
        std::fs::set_permissions(&kept, std::fs::Permissions::from_mode(0o777)).unwrap();
        assert!(keep_in(&kept, "lanes-y.so", &lib).is_err());
        assert!(!kept.join("lanes-y.so").exists());
        assert!(private_dir(&kept).is_err());
        std::fs::set_permissions(&kept, std::fs::Permissions::from_mode(0o700)).unwrap();
        let planted = dir.path().join("planted");
        std::os::unix::fs::symlink(&kept, &planted).unwrap();
        assert!(keep_in(&planted, "lanes-z.so", &lib).is_err());
        assert!(!kept.join("lanes-z.so").exists());
        assert!(private_dir(&planted).is_err());
    }
}
