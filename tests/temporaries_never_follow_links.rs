//! The atomic writer behind every file rigfit writes creates its temporary
//! file exclusively under a name another process cannot guess: a symbolic
//! link planted under that name is never followed, its target never written,
//! and the file asked for is never left a link.

use std::path::Path;

use rigfit::base::fsutil::{atomic_write, temp_path_for};

#[test]
fn a_link_under_the_temporary_name_fails_the_write_and_its_target_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sim.csv");
    let elsewhere = dir.path().join("named_nowhere.txt");
    std::fs::write(&elsewhere, b"a file of the user's").unwrap();
    std::os::unix::fs::symlink(&elsewhere, temp_path_for(&path).unwrap()).unwrap();
    assert!(atomic_write(&path, b"t_s,force_N\n").is_err());
    assert_eq!(std::fs::read(&elsewhere).unwrap(), b"a file of the user's");
    assert!(
        std::fs::symlink_metadata(&path).is_err(),
        "sim.csv was made"
    );
    // A dangling link is not followed either (O_EXCL): nothing is created at
    // its target.
    let dangling = dir.path().join("would_be_created.txt");
    let other = dir.path().join("other.csv");
    std::os::unix::fs::symlink(&dangling, temp_path_for(&other).unwrap()).unwrap();
    assert!(atomic_write(&other, b"x").is_err());
    assert!(!dangling.exists());
}

#[test]
fn temporary_names_are_not_the_old_predictable_ones() {
    let path = Path::new("/any/where/result.json");
    let tmp = temp_path_for(path).unwrap();
    let predictable = format!(".result.json.tmp-{}", std::process::id());
    let name = tmp.file_name().unwrap().to_str().unwrap();
    assert!(
        name.starts_with(&predictable) && name.len() > predictable.len() + 8,
        "{name}"
    );
}

#[test]
fn a_link_at_the_target_is_replaced_not_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sim.csv");
    let elsewhere = dir.path().join("named_nowhere.txt");
    std::fs::write(&elsewhere, b"keep").unwrap();
    std::os::unix::fs::symlink(&elsewhere, &path).unwrap();
    atomic_write(&path, b"new").unwrap();
    assert_eq!(std::fs::read(&elsewhere).unwrap(), b"keep");
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
    assert!(!std::fs::symlink_metadata(&path).unwrap().is_symlink());
}
