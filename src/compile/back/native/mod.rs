//! The lane ensemble in native code: a program's lane code written as C
//! ([`crate::compile::back::c`]), built by the system C compiler into a shared
//! library in a private directory of its own under the temporary folder
//! (mode 0700, a name no other process can guess; the library is checked to
//! be this process's own before it is loaded), loaded, and the directory
//! removed; directories left by killed processes go with the next build.
//! [`crate::compile::exec::lanes::LaneRunner`] then runs its RK4 steps and
//! its lists through the library's functions ([`Native`], whose calls are
//! the executor's: `exec/native_calls.rs`) instead of interpreting them; every lane stays bit-identical to the scalar reference
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
//! process, and kept for the next ([`crate::compile::back::native_cache`]).
//! Where no compiler works, or it takes too long, or the C is larger than a
//! build is started for ([`NATIVE_MAX_C_BYTES`]), the ensemble interprets,
//! and says why once.
//!
//! One job per file: the compiler's command, flags and time limit
//! (`compiler.rs`), the private build directory and its checks
//! (`scratch.rs`), loading a built library's functions (`load.rs`), when
//! a program is built at all (`slot.rs`: `RIGFIT_NATIVE`, the work done,
//! builds started early), and the size past which a build stops paying
//! (`size.rs`); this file builds one lane code.

pub(crate) mod compiler;
mod load;
mod scratch;
mod size;
mod slot;

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use compiler::{LIB, compile_and_load, kept_key};
use load::load_kept;
use scratch::scratch_dir;

use crate::compile::back::c;
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::lanes::Isa;

pub use crate::compile::exec::native_calls::{Arith, Native};
pub use compiler::CC_TIMEOUT_S;
pub use size::{NATIVE_AFTER_C_BYTES, NATIVE_MAX_C_BYTES, native_after};
pub use slot::{NATIVE_AFTER, NativeSlot, check_native_lanes, start_builds};

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
    /// The program's C is larger than a native build is started for
    /// ([`NATIVE_MAX_C_BYTES`]) and `RIGFIT_NATIVE=always` does not force it.
    #[error(
        "native lane code: its C is {bytes} bytes, over the {limit} (NATIVE_MAX_C_BYTES) up to \
         which it is built, as the C compiler's time and memory grow faster than the C \
         (RIGFIT_NATIVE=always builds it)"
    )]
    TooLarge {
        /// The C source's size (bytes).
        bytes: usize,
        /// [`NATIVE_MAX_C_BYTES`] (bytes).
        limit: usize,
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
            let kept = key
                .as_deref()
                .and_then(crate::compile::back::native_cache::find)
                .and_then(
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
                // A kept build is loaded whatever its size (one forced
                // before); a new one is not started past the size limit.
                None => size::check(src.len(), slot::forced())
                    .and_then(|()| compile_and_load(&scratch, &src, code, arith, isa))
                    .inspect(|_| {
                        if let Some(key) = &key {
                            crate::compile::back::native_cache::keep(key, &scratch.path.join(LIB));
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
}
