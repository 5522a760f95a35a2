//! Ctrl-C and SIGTERM (and, for a series' Slurm tasks, SIGUSR1) as a flag the
//! work checks: the first two raise it, a third ends the process at once.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::exit::EXIT_INTERRUPTED;

/// Sends Ctrl-C and SIGTERM to `flag`: the first two raise it (the work
/// stops what runs and winds down; for a job, a second stops the interim
/// outputs an interrupted search writes), a third ends the process at once
/// (a folder's lock is released with it; the lock file is left, unlocked).
/// Each raise prints `\nrigfit: interrupted; {what}` on stderr, and
/// "; once more ends at once" from the second on; never failing on a
/// closed stderr.
pub fn install(flag: &Arc<AtomicBool>, what: &'static str) {
    use std::io::Write as _;
    let flag = flag.clone();
    let count = AtomicUsize::new(0);
    let _ = ctrlc::set_handler(move || {
        let n = count.fetch_add(1, Ordering::SeqCst) + 1;
        if n >= 3 {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        flag.store(true, Ordering::SeqCst);
        let _ = writeln!(
            std::io::stderr(),
            "\nrigfit: interrupted; {what}{}",
            if n == 1 {
                ""
            } else {
                "; once more ends at once"
            }
        );
    });
}

/// SIGUSR1 (Slurm's warning before a task's time limit) raises `flag` too,
/// silently; without this its default action would end the process.
#[cfg(unix)]
pub fn install_usr1(flag: &Arc<AtomicBool>) -> std::io::Result<()> {
    signal_hook::flag::register(signal_hook::consts::SIGUSR1, flag.clone()).map(|_| ())
}
