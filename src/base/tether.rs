//! A child process tethered to this process: killed with it, however it
//! ends. A child may be a tree of processes (the C compiler: `cc` runs
//! `cc1`, `as`, `ld`), in a process group of its own; a signal to `cc` alone
//! leaves `cc1` running, and nothing is told when this process is killed
//! (SIGKILL, a time limit). On Linux the child runs under a small shell, the
//! group's leader, that `setpriv` (util-linux) gives a parent-death signal:
//! when this process dies the shell is sent SIGTERM and kills its whole
//! group. Without `setpriv` the child runs as given.
//!
//! The shell hands the child its own standard input (a shell gives a
//! background command `/dev/null` otherwise) and passes its exit status on;
//! a child killed by signal N is, as shells say it, an exit status of
//! 128 + N. The C compiler's build (`compile::back::native`) and the HDF5
//! reader's child (`record::hdf5_child`) run tethered.

use std::path::PathBuf;
use std::process::{Child, Command};
use std::sync::OnceLock;

/// The shell between `setpriv` and the child: the child in the background
/// with the shell's standard input (through descriptor 3), its status passed
/// on, the group killed on SIGTERM.
const TETHER: &str = r#"trap 'kill -KILL 0' TERM; exec 3<&0; "$@" <&3 3<&- & exec 3<&-; wait $!"#;

/// `cmd`, tethered where this system allows it (see the module's text), in
/// a process group of its own ([`stop`] ends the group). The caller sets its
/// standard input and output on the returned command (those of `cmd` are
/// not kept).
pub(crate) fn tethered(cmd: Command) -> Command {
    let mut t = tether(cmd);
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut t, 0);
    t
}

/// Stops a child started from [`tethered`] and everything it started (its
/// process group). The caller still waits for it.
pub(crate) fn stop(child: &mut Child) {
    #[cfg(unix)]
    {
        let group = rustix::process::Pid::from_child(child);
        let _ = rustix::process::kill_process_group(group, rustix::process::Signal::KILL);
    }
    let _ = child.kill();
}

fn tether(cmd: Command) -> Command {
    let Some(setpriv) = setpriv() else {
        return cmd;
    };
    if !runnable(cmd.get_program()) {
        // Started as it is, so that its absence is said as itself ("could
        // not be run"), not as the shell's "not found".
        return cmd;
    }
    let mut t = Command::new(setpriv);
    t.args(["--pdeathsig", "TERM", "--", "sh", "-c", TETHER, "sh"])
        .arg(cmd.get_program())
        .args(cmd.get_args());
    for (key, value) in cmd.get_envs() {
        match value {
            Some(v) => t.env(key, v),
            None => t.env_remove(key),
        };
    }
    if let Some(dir) = cmd.get_current_dir() {
        t.current_dir(dir);
    }
    t
}

/// Whether `program` names a file that could be run: a path, or a name
/// found on the `PATH`.
fn runnable(program: &std::ffi::OsStr) -> bool {
    let path = std::path::Path::new(program);
    if path.components().count() > 1 {
        return path.is_file();
    }
    std::env::var_os("PATH")
        .is_some_and(|dirs| std::env::split_paths(&dirs).any(|d| d.join(program).is_file()))
}

/// `setpriv` where this is Linux and it is on the `PATH` and takes
/// `--pdeathsig`; looked up once.
fn setpriv() -> Option<&'static PathBuf> {
    static FOUND: OnceLock<Option<PathBuf>> = OnceLock::new();
    FOUND
        .get_or_init(|| {
            if !cfg!(target_os = "linux") {
                return None;
            }
            let path = std::env::var_os("PATH")?;
            let found = std::env::split_paths(&path)
                .map(|d| d.join("setpriv"))
                .find(|p| p.is_file())?;
            let works = Command::new(&found)
                .args(["--pdeathsig", "TERM", "--", "true"])
                .stdin(std::process::Stdio::null())
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .status()
                .is_ok_and(|s| s.success());
            works.then_some(found)
        })
        .as_ref()
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn passes_the_arguments_and_the_exit_status_on() {
        let mut cmd = Command::new("sh");
        cmd.args(["-c", "test \"$1\" = 'a b' && exit 7", "sh", "a b"]);
        let status = tethered(cmd).status().unwrap();
        assert_eq!(status.code(), Some(7));
    }

    #[test]
    fn hands_the_child_its_standard_input() {
        use std::io::Write;
        use std::process::Stdio;
        let mut cmd = Command::new("sh");
        cmd.args(["-c", "tr a-z A-Z"]);
        let mut child = tethered(cmd)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        child.stdin.take().unwrap().write_all(b"abc").unwrap();
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success());
        assert_eq!(out.stdout, b"ABC");
    }

    #[test]
    fn a_child_killed_by_a_signal_is_128_and_its_number() {
        let mut cmd = Command::new("sh");
        cmd.args(["-c", "kill -SEGV $$"]);
        let status = tethered(cmd).status().unwrap();
        use std::os::unix::process::ExitStatusExt;
        if setpriv().is_some() {
            assert_eq!(status.code(), Some(128 + 11));
        } else {
            assert_eq!(status.signal(), Some(11));
        }
    }
}
