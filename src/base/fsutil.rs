//! File-system helpers: atomic writes that never follow a planted link, and
//! the one reader of a user's input files (rig, campaign, parameter and data
//! files), which refuses what is not a regular file and caps what it reads.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// Most bytes a rig, campaign or parameter file may hold (64 MiB).
pub const MAX_DESCRIPTION_BYTES: u64 = 64 << 20;

/// Most bytes a measured record (a CSV file) may hold (512 MiB).
pub const MAX_RECORD_BYTES: u64 = 512 << 20;

/// rigfit's cache folder: `RIGFIT_CACHE_DIR`, else `$XDG_CACHE_HOME/rigfit`,
/// else `~/.cache/rigfit`; `None` when none of them is set. It holds what
/// rigfit measured and built on this machine (the backend trials, the native
/// lane builds), never a user's results.
pub fn cache_dir() -> Option<PathBuf> {
    let var = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    var("RIGFIT_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("rigfit")))
        .or_else(|| var("HOME").map(|d| d.join(".cache").join("rigfit")))
}

/// Writes `bytes` to `path` so that a reader (or a crash) sees either the old file
/// or the complete new one, never a torn mix.
///
/// The bytes go to a temporary file in the same directory (so the final rename
/// stays on one file system), which is flushed and `fsync`ed, then renamed over
/// `path`; on Unix the directory is `fsync`ed too so the rename itself survives a
/// power cut. On error the temporary file is removed and `path` is untouched.
///
/// The temporary file is created exclusively (`O_CREAT | O_EXCL`, and
/// `O_NOFOLLOW`): whatever already stands under its name, a planted symbolic
/// link included, makes the write fail rather than be followed. Its name
/// ([`temp_path_for`]) holds a random token drawn once per process, so another
/// process cannot plant anything under it in advance. A link standing at
/// `path` itself is replaced by the rename, never written through.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("out.txt");
/// rigfit::base::fsutil::atomic_write(&path, b"hello").unwrap();
/// assert_eq!(std::fs::read(&path).unwrap(), b"hello");
/// ```
pub fn atomic_write(path: &Path, bytes: &[u8]) -> io::Result<()> {
    atomic_write_mode(path, bytes, 0o666)
}

/// [`atomic_write`] of a file its owner alone may read and write (mode
/// 0600 on Unix, created so: never readable by others, even for a moment).
pub fn atomic_write_private(path: &Path, bytes: &[u8]) -> io::Result<()> {
    atomic_write_mode(path, bytes, 0o600)
}

/// [`atomic_write`], the temporary file created with `mode` (less the
/// umask) on Unix.
fn atomic_write_mode(path: &Path, bytes: &[u8], mode: u32) -> io::Result<()> {
    let tmp = write_temporary_mode(path, bytes, mode)?;
    if let Err(e) = fs::rename(&tmp, path) {
        // The temporary file is the one created above, never someone else's.
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    sync_parent(path);
    Ok(())
}

/// The first half of [`atomic_write`]: `bytes` written and synced to a new
/// temporary sibling of `path` ([`temp_path_for`]), whose path is returned
/// for the caller to rename over `path` (or remove). Nothing is left behind
/// when it fails. Several files written this way and renamed only once all
/// are complete make a set of files that is replaced all or nothing.
pub fn write_temporary(path: &Path, bytes: &[u8]) -> io::Result<PathBuf> {
    write_temporary_mode(path, bytes, 0o666)
}

fn write_temporary_mode(path: &Path, bytes: &[u8], mode: u32) -> io::Result<PathBuf> {
    let tmp = temp_path_for(path)?;
    let mut file = create_exclusive(&tmp, mode)?;
    if let Err(e) = write_synced(&mut file, bytes) {
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    Ok(tmp)
}

/// The temporary name [`atomic_write`] uses for `path`: a hidden sibling,
/// `.<name>.tmp-<pid>-<token>`, never equal to `path` itself. The token is
/// drawn from the operating system's randomness once per process.
pub fn temp_path_for(path: &Path) -> io::Result<PathBuf> {
    static TOKEN: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    let token = *TOKEN.get_or_init(rand::random::<u64>);
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("not a file path: {}", path.display()),
        )
    })?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".tmp-{}-{token:016x}", std::process::id()));
    Ok(path.with_file_name(tmp_name))
}

/// Whether `name` is a temporary name [`atomic_write`] gives `base` (or gave
/// it in earlier versions: `.<base>.tmp-<pid>`), in any process.
pub fn is_temp_name_of(name: &str, base: &str) -> bool {
    temp_name_parts(name).is_some_and(|(b, _)| b == base)
}

/// The file a temporary name of [`atomic_write`]'s stands for and the
/// process id that wrote it (`.<base>.tmp-<pid>-<token>`, or
/// `.<base>.tmp-<pid>` from earlier versions); `None` for any other name.
pub fn temp_name_parts(name: &str) -> Option<(&str, &str)> {
    let (base, rest) = name.strip_prefix('.')?.rsplit_once(".tmp-")?;
    let (pid, token) = rest.split_once('-').unwrap_or((rest, ""));
    let digits = !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit());
    let hex =
        token.is_empty() || (token.len() == 16 && token.bytes().all(|b| b.is_ascii_hexdigit()));
    (digits && hex).then_some((base, pid))
}

/// Creates `path` for writing, failing when anything (a link included) is
/// there.
fn create_exclusive(path: &Path, mode: u32) -> io::Result<File> {
    let mut options = OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        options
            .mode(mode)
            .custom_flags(rustix::fs::OFlags::NOFOLLOW.bits() as i32);
    }
    #[cfg(not(unix))]
    let _ = mode;
    options.open(path)
}

fn write_synced(file: &mut File, bytes: &[u8]) -> io::Result<()> {
    file.write_all(bytes)?;
    file.flush()?;
    file.sync_all()
}

/// Reads a rig, campaign or parameter file: [`read_input`] with
/// [`MAX_DESCRIPTION_BYTES`], as UTF-8 text, a leading byte-order mark (what
/// a Windows editor's "UTF-8 with BOM" writes) dropped.
pub fn read_description(path: &Path) -> io::Result<String> {
    let bytes = read_input(path, MAX_DESCRIPTION_BYTES)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "expected UTF-8 text, found an invalid byte at offset {}",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// Reads a measured record: [`read_input`] with [`MAX_RECORD_BYTES`].
pub fn read_record(path: &Path) -> io::Result<Vec<u8>> {
    read_input(path, MAX_RECORD_BYTES)
}

/// Reads a user's input file whole, refusing before reading anything what is
/// not a regular file (a FIFO would block for ever, `/dev/zero` never ends)
/// and a file of more than `limit` bytes. The refusal says why; the caller's
/// error names the file.
pub fn read_input(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    check_regular(&fs::metadata(path)?, limit)?;
    let mut options = OpenOptions::new();
    options.read(true);
    // Checked again on the opened file, in case the path changed between the
    // two; a FIFO swapped in meanwhile opens without blocking.
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let file = options.open(path)?;
    let meta = file.metadata()?;
    check_regular(&meta, limit)?;
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

fn check_regular(meta: &fs::Metadata, limit: u64) -> io::Result<()> {
    if !meta.is_file() {
        let found = kind_of(&meta.file_type());
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("expected a regular file, found {found}"),
        ));
    }
    if meta.len() > limit {
        return Err(too_large(meta.len(), limit));
    }
    Ok(())
}

fn too_large(len: u64, limit: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "expected at most {} MiB, found {:.1} MiB",
            limit >> 20,
            len as f64 / f64::from(1 << 20)
        ),
    )
}

/// What a file that is not a regular file is, for a message.
fn kind_of(t: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "something that is not a file"
    }
}

/// Syncs the folder holding `path`, so that a rename into it survives a
/// crash (best effort).
#[cfg(unix)]
pub fn sync_parent(path: &Path) {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // Not all file systems allow syncing a directory; the data is already safe.
    if let Ok(dir) = File::open(parent) {
        let _ = dir.sync_all();
    }
}

/// Syncs the folder holding `path` (nothing to do here).
#[cfg(not(unix))]
pub fn sync_parent(_path: &Path) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_existing_file_and_leaves_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.json");
        atomic_write(&path, b"old").unwrap();
        atomic_write(&path, b"new").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
        let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }

    #[test]
    fn a_link_planted_under_the_temporary_name_is_never_followed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sim.csv");
        let victim = dir.path().join("victim.txt");
        fs::write(&victim, b"precious").unwrap();
        std::os::unix::fs::symlink(&victim, temp_path_for(&path).unwrap()).unwrap();
        assert!(atomic_write(&path, b"result").is_err());
        assert_eq!(fs::read(&victim).unwrap(), b"precious");
        assert!(!path.exists());
        // A link at the target itself is replaced, not written through.
        fs::remove_file(temp_path_for(&path).unwrap()).unwrap();
        std::os::unix::fs::symlink(&victim, &path).unwrap();
        atomic_write(&path, b"result").unwrap();
        assert_eq!(fs::read(&victim).unwrap(), b"precious");
        assert!(!fs::symlink_metadata(&path).unwrap().is_symlink());
    }

    #[test]
    fn temporary_names_hold_a_token_and_are_recognised() {
        let t = temp_path_for(Path::new("/x/v2.csv")).unwrap();
        let name = t.file_name().unwrap().to_str().unwrap();
        let token = name.rsplit('-').next().unwrap();
        assert_eq!(token.len(), 16, "{name}");
        assert!(is_temp_name_of(name, "v2.csv"));
        assert!(is_temp_name_of(".v2.csv.tmp-17", "v2.csv"));
        assert!(!is_temp_name_of(".v2.csv.tmp-17", "v2"));
        assert!(!is_temp_name_of(".v2.csv.tmp-x", "v2.csv"));
        assert!(!is_temp_name_of(".v2.csv.tmp-17-mine", "v2.csv"));
        assert_eq!(temp_name_parts(".v2.csv.tmp-17"), Some(("v2.csv", "17")));
        assert_eq!(temp_name_parts("v2.csv.tmp-17"), None);
    }

    #[test]
    fn inputs_that_are_not_regular_files_or_too_large_are_refused_unread() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_input(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(e.to_string().contains("found a device"), "{e}");
        let e = read_input(dir.path(), 1 << 20).unwrap_err();
        assert!(e.to_string().contains("found a folder"), "{e}");
        let fifo = dir.path().join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let e = read_input(&fifo, 1 << 20).unwrap_err();
            assert!(e.to_string().contains("FIFO"), "{e}");
        }
        let big = dir.path().join("big.json");
        File::create(&big).unwrap().set_len(3 << 20).unwrap();
        let e = read_input(&big, 2 << 20).unwrap_err();
        assert!(
            e.to_string().contains("at most 2 MiB, found 3.0 MiB"),
            "{e}"
        );
        assert_eq!(read_input(&big, 3 << 20).unwrap().len(), 3 << 20);
    }

    #[test]
    fn a_description_loses_its_byte_order_mark() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rig.json");
        fs::write(&path, "\u{feff}{}".as_bytes()).unwrap();
        assert_eq!(read_description(&path).unwrap(), "{}");
    }

    #[test]
    fn temp_name_differs_from_target() {
        let p = Path::new("/x/y/checkpoint.json");
        let t = temp_path_for(p).unwrap();
        assert_ne!(t, p);
        assert_eq!(t.parent(), p.parent());
    }
}
