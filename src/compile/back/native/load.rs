//! A built library loaded: its functions looked up by the names and types
//! the C declares them with.

use std::path::Path;

use super::NativeError;
use super::scratch::{Scratch, check_before_loading, io, write_new};
use crate::compile::back::c;
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::lanes::Isa;
use crate::compile::exec::native_calls::{Arith, Deriv1Fn, ListFn, Native, RedoFn, Rk4Fn};

/// Loads a kept build's `bytes` as a library just built: written into
/// `scratch` (a new private file, under a name of its own, so that a build
/// that follows where it fails to load is not taken for it by the loader)
/// and checked there before it is loaded.
pub(super) fn load_kept(
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

/// Loads the functions of `lib`, the build of `code` in `arith` (checked by
/// [`check_before_loading`]).
#[expect(unsafe_code, reason = "loads the library built and its functions")]
pub(super) fn load(
    lib: &Path,
    code: &LaneCode,
    arith: Arith,
    isa: Isa,
) -> Result<Native, NativeError> {
    let load_err = |source| NativeError::Load {
        path: lib.to_path_buf(),
        source,
    };
    // SAFETY: the library is the C `code` was written as (built here, or
    // kept from a build of the same source by the same compiler), which has
    // no initialisers; each symbol is declared with the signature `back::c`
    // writes for it (the types in `exec::native_calls`).
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
