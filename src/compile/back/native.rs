//! The lane ensemble in native code: a program's lane code written as C
//! ([`crate::compile::back::c`]), built by the system C compiler into a shared
//! library in a private directory of its own under the temporary folder
//! (mode 0700, a name no other process can guess; the library is checked to
//! be this process's own before it is loaded), loaded, and the directory
//! removed; directories left by killed processes go with the next build. [`crate::compile::exec::lanes::LaneRunner`] then runs its RK4 steps
//! and its lists through the library's functions instead of interpreting
//! them; every lane stays bit-identical to the scalar reference
//! (`tests/rig_cpu_ensemble.rs`).
//!
//! The compiler is `RIGFIT_CC` or `cc`, run with `-O2 -march=native
//! -ffp-contract=off` (the code is built for the processor that runs it, and
//! no multiply and add is fused; the f32 code, held to a tolerance and not to
//! the reference's bits, with `-ffp-contract=fast`, fusing where the
//! processor can), its vectors as wide as
//! [`Isa::detect`]'s (with `-mno-avx512f` or `-mno-avx` where
//! `RIGFIT_LANES_ISA` asks for a narrower one than the processor has), for at
//! most `RIGFIT_CC_TIMEOUT` seconds
//! ([`CC_TIMEOUT_S`] by default). One library per distinct source is built per
//! process, and kept for the next ([`super::native_cache`]). Where no
//! compiler works, or it takes too long, the ensemble interprets, and says
//! why once.

use std::collections::HashMap;
use std::ffi::c_long;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};

use crate::compile::back::c::{self, Arith};
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::lanes::Isa;
use crate::compile::exec::lanes::{BLOCKS, Reg};

/// Why no native code could be had.
#[derive(Debug, thiserror::Error)]
pub enum NativeError {
    /// Writing or reading the build directory failed.
    #[error("native lane code: {what} {path}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The C compiler could not be run or refused the source.
    #[error("native lane code: the C compiler `{cc}` {why}")]
    Compiler {
        /// The compiler's command.
        cc: String,
        /// What happened (its message, shortened).
        why: String,
    },
    /// The built library would not load or lacks a function.
    #[error("native lane code: loading {path}: {source}")]
    Load {
        /// The library.
        path: PathBuf,
        /// The loader's error.
        source: libloading::Error,
    },
}

type Rk4Fn = unsafe extern "C" fn(
    *mut Reg,
    *mut Reg,
    c_long,
    *const f64,
    *const f64,
    f64,
    f64,
    f64,
    c_long,
    *mut u8,
);
type ListFn = unsafe extern "C" fn(*mut Reg, c_long, f64, *const f64);
type Deriv1Fn = unsafe extern "C" fn(*const f64, f64, *const f64, *mut f64);
type RedoFn = unsafe extern "C" fn(
    *mut f64,
    *mut f64,
    *const f64,
    f64,
    f64,
    c_long,
    *mut f64,
    *mut c_long,
    *mut c_long,
    *mut c_long,
);

/// Most switches one redone step fires before its run is flagged as
/// chattering, and one more.
pub(crate) const REDO_FIRED: usize = crate::compile::exec::events::MAX_EVENTS_PER_STEP + 1;

/// The buffers [`Native::redo`] reads and writes: the lanes' register file,
/// states and step ends (a row of [`Native::redo_lanes`] lanes per register
/// or state), and per lane the switches fired (time, transition; up to
/// [`REDO_FIRED`]), how many, and whether it chattered.
#[derive(Debug, Clone, Default)]
pub(crate) struct RedoLanes {
    /// `registers` rows.
    pub r: Vec<f64>,
    /// `states` rows: the steps' starts in, their ends out.
    pub y: Vec<f64>,
    /// `states` rows: where the lanes' plain steps ended.
    pub y_end: Vec<f64>,
    /// [`REDO_FIRED`] per lane.
    pub times: Vec<f64>,
    /// [`REDO_FIRED`] per lane.
    pub transitions: Vec<c_long>,
    /// One per lane.
    pub fired: Vec<c_long>,
    /// One per lane.
    pub chattered: Vec<c_long>,
}

/// A loaded build of one program's lane code.
pub struct Native {
    rk4: Rk4Fn,
    lists: [ListFn; 3],
    /// `rig_deriv1` and `rig_events1`, where no `rig_redo` is built.
    one_run: Option<[Deriv1Fn; 2]>,
    /// `rig_redo`, where the lane code has switches and no tables
    /// ([`c::redoes`]).
    redo: Option<RedoFn>,
    /// The lanes [`Self::redo`] takes at once: an f64 vector's.
    pub(crate) redo_lanes: usize,
    /// The lane code's register count, state count and event-function
    /// count, which [`Self::deriv1`]'s and [`Self::events1`]'s slices hold.
    registers: usize,
    states: usize,
    events: usize,
    /// Table values per derivative in [`Self::rk4`]'s `tab`.
    pub(crate) table_stride: usize,
    /// The per-run constants whose values, shared by every lane, let
    /// [`Self::rk4`] compute the derivative's time-only part once per call
    /// ([`c::hoistable`]).
    pub(crate) hoist_reads: Vec<u16>,
    /// The arithmetic it computes in.
    pub arith: Arith,
    /// Kept loaded for the functions above.
    _lib: libloading::Library,
}

impl std::fmt::Debug for Native {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Native")
            .field("table_stride", &self.table_stride)
            .finish_non_exhaustive()
    }
}

/// Which list [`Native::list`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NativeList {
    Report = 0,
    Measured = 1,
    Update = 2,
}

impl Native {
    /// The build of `code` in `arith`, compiled on first request in this
    /// process.
    pub fn build(code: &LaneCode, arith: Arith) -> Result<Arc<Self>, NativeError> {
        static BUILT: Mutex<Option<HashMap<String, Arc<Native>>>> = Mutex::new(None);
        let isa = Isa::detect();
        let src = c::source(code, arith, isa.vector_bytes());
        let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
        let built = built.get_or_insert_with(HashMap::new);
        if let Some(n) = built.get(&src) {
            return Ok(n.clone());
        }
        let started = std::time::Instant::now();
        let scratch = scratch_dir()?;
        // A build kept by an earlier process (`native_cache`), else one
        // compiled here and kept for the next; none where the compiler hung
        // when asked for the key (the build would hang as long).
        let mut how = "built";
        let result = kept_key(&scratch, &src, arith, isa).and_then(|key| {
            let kept =
                key.as_deref().and_then(super::native_cache::find).and_then(
                    |bytes| match load_kept(&scratch, &bytes, code, arith, isa) {
                        Ok(n) => Some(n),
                        Err(e) => {
                            log::info!("{e}; building again");
                            None
                        }
                    },
                );
            match kept {
                Some(n) => {
                    how = "loaded as kept";
                    Ok(n)
                }
                None => compile_and_load(&scratch, &src, code, arith, isa).inspect(|_| {
                    if let Some(key) = &key {
                        super::native_cache::keep(key, &scratch.path.join(LIB));
                    }
                }),
            }
        });
        // Only the files written above are in it; the library stays mapped.
        let _ = std::fs::remove_dir_all(&scratch.path);
        let n = Arc::new(result?);
        log::info!(
            "native lane code {how} ({arith:?}, {} registers, {}-byte vectors) in {:.2} s",
            code.registers,
            isa.vector_bytes(),
            started.elapsed().as_secs_f64()
        );
        built.insert(src, n.clone());
        Ok(n)
    }

    /// One RK4 step of blocks `0..nb` of `r` (states in its first rows), the
    /// start stored in `y`: derivatives at times `tt`, with table values `tab`
    /// (`table_stride` per derivative), stage factors `ch = 0.5·h`, `h`, `h/6`;
    /// `hoist` where every lane holds the same value in each of
    /// `hoist_reads`. Then the event list at `tt[3]` (the step's end), which
    /// sets, per block, the bit of each lane past an armed switch in `hit`
    /// (as `LaneRunner`'s test does).
    #[expect(clippy::too_many_arguments, reason = "the C function's operands")]
    #[expect(unsafe_code, reason = "calls the compiled C")]
    pub(crate) fn rk4(
        &self,
        r: &mut [Reg],
        y: &mut [Reg],
        nb: usize,
        tt: &[f64; 4],
        tab: &[f64],
        ch: f64,
        h: f64,
        h6: f64,
        hoist: bool,
        hit: &mut [u8; BLOCKS],
    ) {
        assert!(r.len() == self.registers && y.len() == self.states && nb <= BLOCKS);
        assert!(tab.len() >= 4 * self.table_stride);
        // SAFETY: the C reads and writes rows below the lane code's register
        // count (`r`'s length) and `y`'s state rows, blocks below `nb` ≤
        // BLOCKS (the f32 code of 64-byte vectors also the block after an
        // odd last one, still below BLOCKS); `tab` holds what it reads;
        // `hit` has a byte for every block.
        unsafe {
            (self.rk4)(
                r.as_mut_ptr(),
                y.as_mut_ptr(),
                nb as c_long,
                tt.as_ptr(),
                tab.as_ptr(),
                ch,
                h,
                h6,
                c_long::from(hoist),
                hit.as_mut_ptr(),
            );
        }
    }

    /// Runs `which` list at time `t` (table values `tab`) over blocks `0..nb`.
    #[expect(unsafe_code, reason = "calls the compiled C")]
    pub(crate) fn list(&self, which: NativeList, r: &mut [Reg], nb: usize, t: f64, tab: &[f64]) {
        assert!(r.len() == self.registers && nb <= BLOCKS);
        assert!(tab.len() >= self.table_stride);
        // SAFETY: as in `rk4`.
        unsafe {
            (self.lists[which as usize])(r.as_mut_ptr(), nb as c_long, t, tab.as_ptr());
        }
    }

    /// One run's derivative in f64 (whatever [`Self::arith`]), bit for bit
    /// the scalar reference's: `r` the run's scalar register file (states,
    /// regimes, held states and per-run constants at their registers), time
    /// `t`, table values `tab`; the slopes into `out`.
    pub(crate) fn deriv1(&self, r: &[f64], t: f64, tab: &[f64], out: &mut [f64]) {
        let f = self.one_run.expect("a build without rig_redo")[0];
        self.one_run(f, self.states, r, t, tab, out);
    }

    /// One run's event functions in f64, bit for bit the scalar
    /// reference's, as [`Self::deriv1`]: their values into `out`, one per
    /// transition.
    pub(crate) fn events1(&self, r: &[f64], t: f64, tab: &[f64], out: &mut [f64]) {
        let f = self.one_run.expect("a build without rig_redo")[1];
        self.one_run(f, self.events, r, t, tab, out);
    }

    /// Whether [`Self::redo`] is built.
    pub(crate) fn redoes(&self) -> bool {
        self.redo.is_some()
    }

    /// Buffers for [`Self::redo`] of this build.
    pub(crate) fn redo_buffers(&self) -> RedoLanes {
        let l = self.redo_lanes;
        RedoLanes {
            r: vec![0.0; self.registers * l],
            y: vec![0.0; self.states * l],
            y_end: vec![0.0; self.states * l],
            times: vec![0.0; REDO_FIRED * l],
            transitions: vec![0; REDO_FIRED * l],
            fired: vec![0; l],
            chattered: vec![0; l],
        }
    }

    /// The steps from `b.y` over `[t, t + h]` of the lanes whose bit is set
    /// in `act` redone with their switches located, each bit for bit as the
    /// scalar reference's stepper redoes it (`EventStepper::step_known`),
    /// where [`Self::redoes`]: `b.r` their register files with their
    /// regimes and held states set (the regimes they switch set there),
    /// `b.y_end` where the lanes' plain steps ended, `b.y` the starts in and
    /// the ends out; the switches each fires, how many, and whether it
    /// chattered, into the rest of `b`.
    #[expect(unsafe_code, reason = "calls the compiled C")]
    pub(crate) fn redo(&self, b: &mut RedoLanes, t: f64, h: f64, act: u64) {
        let f = self.redo.expect("a build that redoes");
        let l = self.redo_lanes;
        assert!(
            b.r.len() == self.registers * l
                && b.y.len() == self.states * l
                && b.y_end.len() == self.states * l
                && b.times.len() == REDO_FIRED * l
                && b.transitions.len() == REDO_FIRED * l
                && b.fired.len() == l
                && b.chattered.len() == l
                && act >> l == 0
        );
        // SAFETY: `rig_redo` of this library reads and writes `registers`
        // rows of `redo_lanes` values of `r`, `states` rows of `y` and
        // `y_end`, and at most REDO_FIRED switches per lane and one count
        // and flag per lane, as the buffers above hold.
        unsafe {
            f(
                b.r.as_mut_ptr(),
                b.y.as_mut_ptr(),
                b.y_end.as_ptr(),
                t,
                h,
                act as c_long,
                b.times.as_mut_ptr(),
                b.transitions.as_mut_ptr(),
                b.fired.as_mut_ptr(),
                b.chattered.as_mut_ptr(),
            );
        }
    }

    /// Calls `f`, one of the one-run functions, which writes `n` values.
    #[expect(unsafe_code, reason = "calls the compiled C")]
    fn one_run(&self, f: Deriv1Fn, n: usize, r: &[f64], t: f64, tab: &[f64], out: &mut [f64]) {
        assert!(r.len() == self.registers && out.len() == n);
        assert!(tab.len() >= self.table_stride);
        // SAFETY: `f` is `rig_deriv1` or `rig_events1` of this library; each
        // reads registers below `registers` and tables below `table_stride`,
        // and writes its `n` values (`states` slopes, `events` values).
        unsafe { f(r.as_ptr(), t, tab.as_ptr(), out.as_mut_ptr()) }
    }
}

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
fn scratch_dir() -> Result<Scratch, NativeError> {
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
struct Scratch {
    path: PathBuf,
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
fn check_before_loading(scratch: &Scratch, lib: &Path) -> std::io::Result<()> {
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
    mut cmd: Command,
    log: &Path,
    out: Option<&Path>,
    limit: std::time::Duration,
) -> Result<std::process::ExitStatus, String> {
    let create = |p: &Path| std::fs::File::create(p).map_err(|e| format!("could not be run: {e}"));
    let err = create(log)?;
    let stdout = match out {
        Some(p) => std::process::Stdio::from(create(p)?),
        None => std::process::Stdio::null(),
    };
    cmd.stdin(std::process::Stdio::null())
        .stdout(stdout)
        .stderr(err);
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
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
                #[cfg(unix)]
                {
                    let group = rustix::process::Pid::from_child(&child);
                    let _ =
                        rustix::process::kill_process_group(group, rustix::process::Signal::KILL);
                }
                let _ = child.kill();
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
const LIB: &str = "lanes.so";

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

/// The text a kept build of `src` is found by ([`super::native_cache`]): the
/// compiler, its flags, what it predefines for this processor with them (its
/// version and the instruction-set extensions `-march=native` enables), and
/// the source. The compiler is asked once per process and flags; `None`
/// where it will not say (a compiler that fails), and nothing is kept or
/// taken. A compiler that takes longer than a build may is an error: the
/// build would wait as long again, and so would every later one in the
/// process.
fn kept_key(
    scratch: &Scratch,
    src: &str,
    arith: Arith,
    isa: Isa,
) -> Result<Option<String>, NativeError> {
    type Asked = HashMap<(String, Vec<&'static str>), Result<Option<String>, String>>;
    static SAID: Mutex<Option<Asked>> = Mutex::new(None);
    if super::native_cache::folder().is_none() {
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

/// Loads a kept build's `bytes` as a library just built: written into
/// `scratch` (a new private file, under a name of its own, so that a build
/// that follows where it fails to load is not taken for it by the loader)
/// and checked there before it is loaded.
fn load_kept(
    scratch: &Scratch,
    bytes: &[u8],
    code: &LaneCode,
    arith: Arith,
    isa: Isa,
) -> Result<Native, NativeError> {
    let lib = scratch.path.join("kept.so");
    write_new(&lib, bytes).map_err(io("writing", &lib))?;
    check_before_loading(scratch, &lib).map_err(io("checking", &lib))?;
    load(&lib, code, arith, isa)
}

/// [`NativeError::Io`] of `what` was done to `path`, from its cause.
fn io(what: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> NativeError {
    let path = path.to_path_buf();
    move |source| NativeError::Io { what, path, source }
}

/// Writes `bytes` into a new file at `path` (failing where anything is
/// there already).
fn write_new(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .and_then(|mut f| std::io::Write::write_all(&mut f, bytes))
}

/// Builds `src` (the C of `code` in `arith`) in `scratch` and loads its
/// functions.
fn compile_and_load(
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

/// Loads the functions of `lib`, the build of `code` in `arith` (checked by
/// [`check_before_loading`]).
#[expect(unsafe_code, reason = "loads the library built and its functions")]
fn load(lib: &Path, code: &LaneCode, arith: Arith, isa: Isa) -> Result<Native, NativeError> {
    let load_err = |source| NativeError::Load {
        path: lib.to_path_buf(),
        source,
    };
    // SAFETY: the library is the C `code` was written as (built here, or
    // kept from a build of the same source by the same compiler), which has
    // no initialisers; each symbol is declared with the signature `native_c`
    // writes for it.
    unsafe {
        let l = libloading::Library::new(lib).map_err(load_err)?;
        let rk4: Rk4Fn = *l.get::<Rk4Fn>(b"rig_rk4\0").map_err(load_err)?;
        let list = |name: &[u8]| l.get::<ListFn>(name).map(|f| *f).map_err(load_err);
        let lists = [
            list(b"rig_report\0")?,
            list(b"rig_measured\0")?,
            list(b"rig_update\0")?,
        ];
        let one = |name: &[u8]| l.get::<Deriv1Fn>(name).map(|f| *f).map_err(load_err);
        let (redo, one_run) = if c::redoes(code) {
            (
                Some(*l.get::<RedoFn>(b"rig_redo\0").map_err(load_err)?),
                None,
            )
        } else {
            (None, Some([one(b"rig_deriv1\0")?, one(b"rig_events1\0")?]))
        };
        Ok(Native {
            rk4,
            lists,
            one_run,
            redo,
            redo_lanes: isa.vector_bytes() / 8,
            registers: code.registers,
            states: code.slopes.len(),
            events: code.events.roots.len(),
            table_stride: c::table_stride(code),
            hoist_reads: c::hoistable(code).reads,
            arith,
            _lib: l,
        })
    }
}

/// The C compiler: `RIGFIT_CC`, or `cc`.
pub(crate) fn compiler() -> String {
    std::env::var("RIGFIT_CC").unwrap_or_else(|_| "cc".into())
}

/// `RIGFIT_NATIVE`, read once per process: `None` never to build native
/// code (`off`), else the candidate-steps a program runs before it is built
/// for [`NativeSlot::get`] (0 for `always`, [`NATIVE_AFTER`] by default).
fn policy() -> Option<u64> {
    static POLICY: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    *POLICY.get_or_init(|| match std::env::var("RIGFIT_NATIVE").as_deref() {
        Ok("off") => None,
        Ok("always") => Some(0),
        _ => Some(NATIVE_AFTER),
    })
}

/// Whether this machine builds native lane code, for `rigfit devices`: the
/// C compiler and the first line of its `--version` where it builds the
/// first shipped rig's lanes, else why not (`RIGFIT_NATIVE=off`
/// included).
pub fn check_native_lanes() -> Result<(String, String), String> {
    if policy().is_none() {
        return Err("RIGFIT_NATIVE=off".into());
    }
    let (id, _) = crate::rig::SHIPPED[0];
    let desc = crate::rig::shipped(id).ok_or("the shipped rigs are missing")?;
    let lowered = crate::compile::lower(&desc, id).map_err(|e| e.to_string())?;
    let prog = &lowered.programs[0];
    let tape = crate::compile::Tape::new(prog);
    let code = LaneCode::new(prog, &tape);
    Native::build(&code, Arith::F64).map_err(|e| e.to_string())?;
    let cc = compiler();
    let version = Command::new(&cc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|v| v.lines().next().map(str::to_string))
        .unwrap_or_default();
    Ok((cc, version))
}

/// When the lane ensemble runs native code: `RIGFIT_NATIVE=off` never,
/// `always` from the first batch, otherwise once a program has run
/// [`NATIVE_AFTER`] candidate-steps in this process (building takes about a
/// quarter of a second, as long as the interpreter takes for some 4·10⁶),
/// or once a build started early ([`start_builds`], by a job that will run
/// that long) is done.
pub const NATIVE_AFTER: u64 = 4_000_000;

/// One program's native build, made when [`NATIVE_AFTER`] says so, or
/// started early on a thread of its own ([`start_builds`]).
#[derive(Debug, Default)]
pub struct NativeSlot {
    inner: Arc<SlotInner>,
}

#[derive(Debug, Default)]
struct SlotInner {
    work: std::sync::atomic::AtomicU64,
    /// Set while a thread of [`start_builds`] builds it.
    building: std::sync::atomic::AtomicBool,
    built: std::sync::OnceLock<Option<Arc<Native>>>,
}

impl SlotInner {
    fn build(&self, code: &LaneCode, arith: Arith) -> Option<Arc<Native>> {
        self.built
            .get_or_init(|| match Native::build(code, arith) {
                Ok(n) => Some(n),
                Err(e) => {
                    // Once per process and failure: a drive program's fitness
                    // variant and its full code are two builds that fail alike.
                    static SAID: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
                    let what = match arith {
                        Arith::F64 => format!("{e}; the lane ensemble interprets instead"),
                        Arith::F32 => format!("{e}; no f32 lanes"),
                    };
                    let mut said = SAID.lock().unwrap_or_else(|p| p.into_inner());
                    if !said.contains(&what) {
                        log::warn!("{what}");
                        said.push(what);
                    }
                    None
                }
            })
            .clone()
    }
}

impl NativeSlot {
    /// The build of `code` in `arith` now, whatever the work so far (`None`
    /// where it cannot be had, or `RIGFIT_NATIVE=off`); where a thread of
    /// [`start_builds`] is building it, once that thread is done.
    pub fn now(&self, code: &LaneCode, arith: Arith) -> Option<Arc<Native>> {
        policy()?;
        self.inner.build(code, arith)
    }

    /// The f64 build to run `work` more candidate-steps of `code` with, once
    /// the program's work in this process has reached the policy's
    /// threshold; `None` while a thread of [`start_builds`] is building it.
    pub fn get(&self, code: &LaneCode, work: u64) -> Option<Arc<Native>> {
        let after = policy()?;
        if let Some(b) = self.inner.built.get() {
            return b.clone();
        }
        if self
            .inner
            .building
            .load(std::sync::atomic::Ordering::Acquire)
            || self
                .inner
                .work
                .fetch_add(work, std::sync::atomic::Ordering::Relaxed)
                < after
        {
            return None;
        }
        self.now(code, Arith::F64)
    }
}

/// Starts building each program of `builds` in f64, in order, on one thread
/// of its own (one compiler at a time), skipping those built or being built
/// (nothing with `RIGFIT_NATIVE=off`): for a job that will run long enough
/// to want them, so that the C compiler works while the interpreter does
/// rather than in its place. Runs keep interpreting ([`NativeSlot::get`])
/// until their build is there; [`NativeSlot::now`] waits for it. Returns the
/// thread, to join before the process may end (its compiler's files are
/// removed when it is done).
pub fn start_builds(builds: &[(&NativeSlot, &LaneCode)]) -> Option<std::thread::JoinHandle<()>> {
    use std::sync::atomic::Ordering;
    policy()?;
    let claimed: Vec<(Arc<SlotInner>, LaneCode)> = builds
        .iter()
        .filter(|(slot, _)| {
            slot.inner.built.get().is_none() && !slot.inner.building.swap(true, Ordering::AcqRel)
        })
        .map(|(slot, code)| (slot.inner.clone(), (*code).clone()))
        .collect();
    if claimed.is_empty() {
        return None;
    }
    let inners: Vec<Arc<SlotInner>> = claimed.iter().map(|(i, _)| i.clone()).collect();
    let spawned = std::thread::Builder::new()
        .name("rigfit-native".into())
        .spawn(move || {
            for (inner, code) in claimed {
                inner.build(&code, Arith::F64);
                inner.building.store(false, Ordering::Release);
            }
        });
    // A thread that will not start leaves the builds to `get`.
    spawned
        .map_err(|e| {
            log::info!("native lane code not built early: {e}");
            for inner in inners {
                inner.building.store(false, Ordering::Release);
            }
        })
        .ok()
}
