//! Where a native build stops paying for its size. The C compiler's time and
//! memory grow faster than the C it is given (each list is one function, and
//! the compiler's passes over a function grow faster than its statements),
//! while the native code's gain over the interpreter shrinks on a large rig;
//! so a larger C waits for more work before it is built ([`native_after`]),
//! and one over [`NATIVE_MAX_C_BYTES`] is not built at all unless
//! `RIGFIT_NATIVE=always`: its lanes interpret.
//!
//! Measured on chains of N masses (`tests/native_size_limit.rs` writes
//! them), GCC 12 at `-O2 -march=native` on an Intel Xeon (2 cores, shared
//! with other builds: the compiler's CPU-seconds and peak memory, then the
//! interpreter's and the native code's candidate-steps per CPU-second):
//! N = 10: 39 kB of C, 0.3 s, 46 MB, 1.4·10⁷ and 4.4·10⁷; N = 30: 91 kB,
//! 1.2 s, 68 MB, 3.5·10⁶ and 1.9·10⁷; N = 100: 299 kB, 7.9 s, 181 MB,
//! 9.1·10⁵ and 2.0·10⁶; N = 300: 888 kB, 39 s, 788 MB, 3.0·10⁵ and
//! 4.3·10⁵; N = 1000: 3.2 MB, 283 s, 3.6 GB, 5.1·10⁴ and 8.6·10⁴. The
//! compiler's time grows as the C's size to the power 1.5, its memory a
//! little faster than the size; the native code's gain falls from 3 to 5
//! times on small rigs to under 2 on large ones.

use super::NativeError;
use super::slot::NATIVE_AFTER;

/// The largest C (bytes) a native build is started for unless
/// `RIGFIT_NATIVE=always`: about a chain of 170 masses, whose build takes
/// some 17 s of one core and 0.4 GB, under a third of
/// [`super::CC_TIMEOUT_S`] (a loaded machine took 7 times the CPU time in
/// wall time). Beyond it, measured: 888 kB took 39 s of CPU (414 s of wall
/// time on the loaded machine, stopped by the time limit there) and paid
/// back after 3.7·10⁷ candidate-steps, the native code 1.45 times the
/// interpreter's speed; 3.2 MB took 283 s and 3.6 GB, more than the time
/// limit on any machine, so the build is only lost time and memory.
pub const NATIVE_MAX_C_BYTES: usize = 500_000;

/// The C size (bytes) up to which [`NATIVE_AFTER`] candidate-steps are run
/// before a build; a larger C waits in proportion ([`native_after`]).
pub const NATIVE_AFTER_C_BYTES: usize = 100_000;

/// The candidate-steps a program whose C is `c_bytes` long runs
/// interpreted before its native build is made: [`NATIVE_AFTER`], scaled
/// by `c_bytes` over [`NATIVE_AFTER_C_BYTES`] where it is larger. The build
/// pays back once the interpreter's time saved exceeds the compiler's:
/// measured, some 6·10⁶ and 5·10⁶ candidate-steps for chains of 10 and 30
/// masses (39 and 91 kB of C), 1.3·10⁷ for 100 masses (299 kB, here
/// 1.2·10⁷) and 3.7·10⁷ for 300 (888 kB, here 3.6·10⁷).
pub fn native_after(c_bytes: usize) -> u64 {
    let bytes = u64::try_from(c_bytes.max(NATIVE_AFTER_C_BYTES)).unwrap_or(u64::MAX);
    let per = NATIVE_AFTER_C_BYTES as u64;
    NATIVE_AFTER.saturating_mul(bytes) / per
}

/// Whether a C of `c_bytes` may be built: always where `forced`
/// (`RIGFIT_NATIVE=always`), else up to [`NATIVE_MAX_C_BYTES`].
pub(super) fn check(c_bytes: usize, forced: bool) -> Result<(), NativeError> {
    if forced || c_bytes <= NATIVE_MAX_C_BYTES {
        Ok(())
    } else {
        Err(NativeError::TooLarge {
            bytes: c_bytes,
            limit: NATIVE_MAX_C_BYTES,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::back::c;
    use crate::compile::exec::lane_code::LaneCode;
    use crate::compile::exec::native_calls::Arith;

    #[test]
    fn a_small_c_waits_the_plain_threshold_and_a_larger_one_longer() {
        assert_eq!(native_after(0), NATIVE_AFTER);
        assert_eq!(native_after(NATIVE_AFTER_C_BYTES), NATIVE_AFTER);
        assert_eq!(native_after(3 * NATIVE_AFTER_C_BYTES), 3 * NATIVE_AFTER);
        assert!(native_after(NATIVE_AFTER_C_BYTES + 1000) > NATIVE_AFTER);
        assert_eq!(
            native_after(usize::MAX),
            u64::MAX / NATIVE_AFTER_C_BYTES as u64
        );
    }

    #[test]
    fn a_c_over_the_limit_is_refused_unless_forced() {
        assert!(check(NATIVE_MAX_C_BYTES, false).is_ok());
        let err = check(NATIVE_MAX_C_BYTES + 1, false).unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains(&format!("{} bytes", NATIVE_MAX_C_BYTES + 1))
                && msg.contains("NATIVE_MAX_C_BYTES")
                && msg.contains("RIGFIT_NATIVE=always"),
            "{msg}"
        );
        assert!(check(NATIVE_MAX_C_BYTES + 1, true).is_ok());
    }

    #[test]
    fn every_shipped_rig_is_built() {
        for (id, _) in crate::rig::SHIPPED {
            let desc = crate::rig::shipped(id).unwrap();
            let lowered = crate::compile::front::lower(&desc, id).unwrap();
            for prog in &lowered.programs {
                let tape = crate::compile::exec::tape::Tape::new(prog);
                let code = LaneCode::new(prog, &tape);
                let bytes = c::source(&code, Arith::F64, 64).len();
                assert!(check(bytes, false).is_ok(), "{id}: {bytes} bytes of C");
            }
        }
    }
}
