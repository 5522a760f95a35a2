//! The C compiler's command: which compiler, its flags, its time limit, the
//! key a kept build is found by, and the build itself.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;
use std::sync::Mutex;

use super::NativeError;
use super::load::load;
use super::scratch::{Scratch, check_before_loading, io, write_new};
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::lanes::Isa;
use crate::compile::exec::native_calls::{Arith, Native};

/// How long the C compiler may take: `RIGFIT_CC_TIMEOUT` seconds, else
/// [`CC_TIMEOUT_S`].
fn compiler_timeout() -> std::time::Duration {
    let s = std::env::var("RIGFIT_CC_TIMEOUT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(CC_TIMEOUT_S);
    std::time::Duration::from_secs_f64(s.min(86_400.0))
}

/// The default time limit of one native build (s); a compiler that takes
/// longer is stopped and the lanes interpret.
pub const CC_TIMEOUT_S: f64 = 60.0;

/// Runs `cmd` (its stderr into `log`, its stdout into `out` or nowhere)
/// until it ends or `limit` passes; then stops it and everything it started.
/// Its exit status, or why there is none.
fn run_limited(
    cmd: Command,
    log: &Path,
    out: Option<&Path>,
    limit: std::time::Duration,
) -> Result<std::process::ExitStatus, String> {
    // Killed with this process, however it ends (base/tether.rs).
    let mut cmd = crate::base::tether::tethered(cmd);
    let create = |p: &Path| std::fs::File::create(p).map_err(|e| format!("could not be run: {e}"));
    let err = create(log)?;
    let stdout = match out {
        Some(p) => std::process::Stdio::from(create(p)?),
        None => std::process::Stdio::null(),
    };
    cmd.stdin(std::process::Stdio::null())
        .stdout(stdout)
        .stderr(err);
    let mut child = cmd.spawn().map_err(|e| format!("could not be run: {e}"))?;
    let started = std::time::Instant::now();
    let mut pause = std::time::Duration::from_millis(1);
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return Ok(status),
            Ok(None) if started.elapsed() < limit => {
                std::thread::sleep(pause);
                pause = (pause * 2).min(std::time::Duration::from_millis(50));
            }
            other => {
                // The compiler's own processes (cc1, as, ld) go with it.
                crate::base::tether::stop(&mut child);
                let _ = child.wait();
                return Err(match other {
                    Err(e) => format!("could not be waited for: {e}"),
                    _ => format!(
                        "did not finish within {:.0} s (RIGFIT_CC_TIMEOUT) and was stopped",
                        limit.as_secs_f64()
                    ),
                });
            }
        }
    }
}

/// The library's file name in a build directory.
pub(super) const LIB: &str = "lanes.so";

/// The compiler's flags for `arith` on `isa`, before the output and source.
fn flags(arith: Arith, isa: Isa) -> Vec<&'static str> {
    let mut f = vec!["-O2", "-march=native"];
    f.extend_from_slice(isa.narrowing_flags());
    f.push(match arith {
        Arith::F64 => "-ffp-contract=off",
        Arith::F32 => "-ffp-contract=fast",
    });
    f.extend_from_slice(&["-fPIC", "-shared", "-w"]);
    f
}

/// The text a kept build of `src` is found by ([`crate::compile::back::native_cache`]): the
/// compiler, its flags, what it predefines for this processor with them (its
/// version and the instruction-set extensions `-march=native` enables), and
/// the source. The compiler is asked once per process and flags; `None`
/// where it will not say (a compiler that fails), and nothing is kept or
/// taken. A compiler that takes longer than a build may is an error: the
/// build would wait as long again, and so would every later one in the
/// process.
pub(super) fn kept_key(
    scratch: &Scratch,
    src: &str,
    arith: Arith,
    isa: Isa,
) -> Result<Option<String>, NativeError> {
    type Asked = HashMap<(String, Vec<&'static str>), Result<Option<String>, String>>;
    static SAID: Mutex<Option<Asked>> = Mutex::new(None);
    if crate::compile::back::native_cache::folder().is_none() {
        return Ok(None);
    }
    let cc = compiler();
    let flags = flags(arith, isa);
    let mut probe = flags.clone();
    probe.retain(|f| *f != "-shared");
    let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
    let said = said.get_or_insert_with(HashMap::new);
    let target = said
        .entry((cc.clone(), probe.clone()))
        .or_insert_with(|| {
            let out = scratch.path.join("target.txt");
            let mut cmd = Command::new(&cc);
            cmd.args(&probe).args(["-dM", "-E", "-x", "c", "/dev/null"]);
            let status = run_limited(
                cmd,
                &scratch.path.join("probe.log"),
                Some(&out),
                compiler_timeout(),
            );
            match status {
                Ok(s) if s.success() => Ok(std::fs::read_to_string(&out).ok()),
                Ok(_) => Ok(None),
                Err(why) => Err(why),
            }
        })
        .clone();
    match target {
        Ok(Some(target)) => Ok(Some(format!("{cc}\n{flags:?}\n{target}\n{src}"))),
        Ok(None) => Ok(None),
        Err(why) => Err(NativeError::Compiler { cc, why }),
    }
}

/// Builds `src` (the C of `code` in `arith`) in `scratch` and loads its
/// functions.
pub(super) fn compile_and_load(
    scratch: &Scratch,
    src: &str,
    code: &LaneCode,
    arith: Arith,
    isa: Isa,
) -> Result<Native, NativeError> {
    let dir = &scratch.path;
    let c = dir.join("lanes.c");
    let lib = dir.join(LIB);
    write_new(&c, src.as_bytes()).map_err(io("writing", &c))?;
    let cc = compiler();
    let mut cmd = Command::new(&cc);
    cmd.args(flags(arith, isa))
        .arg("-o")
        .arg(&lib)
        .arg(&c)
        .arg("-lm");
    let log = dir.join("cc.log");
    let status =
        run_limited(cmd, &log, None, compiler_timeout()).map_err(|why| NativeError::Compiler {
            cc: cc.clone(),
            why,
        })?;
    if !status.success() {
        let msg = std::fs::read_to_string(&log).unwrap_or_default();
        let first: Vec<&str> = msg.lines().take(3).collect();
        return Err(NativeError::Compiler {
            cc,
            why: format!("failed ({status}): {}", first.join(" / ")),
        });
    }
    check_before_loading(scratch, &lib).map_err(io("checking", &lib))?;
    load(&lib, code, arith, isa)
}

/// The C compiler: `RIGFIT_CC`, or `cc`.
pub(crate) fn compiler() -> String {
    std::env::var("RIGFIT_CC").unwrap_or_else(|_| "cc".into())
}
