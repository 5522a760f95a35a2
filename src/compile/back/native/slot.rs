//! When a program's native build is made: the policy (`RIGFIT_NATIVE`), the
//! work a program has done, and builds started early on a thread of their
//! own.

use std::process::Command;
use std::sync::Arc;

use super::NativeError;
use super::compiler::compiler;
use super::size::{NATIVE_MAX_C_BYTES, native_after};
use crate::compile::back::c;
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::lanes::Isa;
use crate::compile::exec::native_calls::{Arith, Native};

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

/// Whether `RIGFIT_NATIVE=always` forces every build, whatever the size of
/// its C ([`NATIVE_MAX_C_BYTES`]).
pub(super) fn forced() -> bool {
    policy() == Some(0)
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
    let lowered = crate::compile::front::lower(&desc, id).map_err(|e| e.to_string())?;
    let prog = &lowered.programs[0];
    let tape = crate::compile::exec::tape::Tape::new(prog);
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
/// [`NATIVE_AFTER`] candidate-steps in this process (building a small rig's
/// C takes about a quarter of a second, as long as the interpreter takes
/// for some 4·10⁶), more for a larger C ([`native_after`]), never for a C
/// over [`NATIVE_MAX_C_BYTES`], or once a build started early
/// ([`start_builds`], by a job that will run that long) is done.
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
    /// The f64 C's size (bytes), measured on the first [`NativeSlot::get`].
    c_bytes: std::sync::OnceLock<usize>,
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
                    // A rig too large to build is said once, for its first
                    // program (its others differ in size alone).
                    let key = match e {
                        NativeError::TooLarge { .. } => format!("too large {arith:?}"),
                        _ => what.clone(),
                    };
                    let mut said = SAID.lock().unwrap_or_else(|p| p.into_inner());
                    if !said.contains(&key) {
                        log::warn!("{what}");
                        said.push(key);
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
    /// threshold (for its size: [`native_after`]); `None` while a thread of
    /// [`start_builds`] is building it. A C over [`NATIVE_MAX_C_BYTES`] is
    /// refused (and the refusal said) on the first call, unless
    /// `RIGFIT_NATIVE=always`.
    pub fn get(&self, code: &LaneCode, work: u64) -> Option<Arc<Native>> {
        let after = policy()?;
        if let Some(b) = self.inner.built.get() {
            return b.clone();
        }
        let after = if after == 0 {
            0
        } else {
            let bytes = *self
                .inner
                .c_bytes
                .get_or_init(|| c::source(code, Arith::F64, Isa::detect().vector_bytes()).len());
            if bytes > NATIVE_MAX_C_BYTES {
                // Refused now, once: said in the log, and `None` kept.
                return self.now(code, Arith::F64);
            }
            native_after(bytes).max(after)
        };
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
