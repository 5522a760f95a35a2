//! A native build of a program's lane code as the lane runner calls it: the
//! functions of the library the back end built and loaded
//! ([`crate::compile::back::native`]), with the types the C declares them with
//! ([`crate::compile::back::c`]), and the safe calls [`super::lanes::LaneRunner`]
//! and [`super::events::EventStepper`] make instead of interpreting. The back
//! end makes a [`Native`]; the executors only call it, so their imports stay
//! below the back ends'.

use std::ffi::c_long;

use crate::compile::exec::events::MAX_EVENTS_PER_STEP;
use crate::compile::exec::lanes::{BLOCKS, Reg};

/// The arithmetic the C code computes in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arith {
    /// f64, eight lanes to a vector: bit for bit the scalar reference.
    F64,
    /// f32, sixteen lanes to a vector (the states and per-run constants
    /// packed as f32 in their rows, the other rows two blocks of the f64
    /// register file rounded on load): `eˣ` and `eˣ − 1` by the same reduction with an f32
    /// polynomial, `ln` (the f64 vector form), `sin`, `cos` computed in f64
    /// and rounded once.
    F32,
}

/// `rig_rk4` in the C ([`crate::compile::back::c`]).
pub(crate) type Rk4Fn = unsafe extern "C" fn(
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
/// `rig_report`, `rig_measured` and `rig_update`.
pub(crate) type ListFn = unsafe extern "C" fn(*mut Reg, c_long, f64, *const f64);
/// `rig_deriv1` and `rig_events1`.
pub(crate) type Deriv1Fn = unsafe extern "C" fn(*const f64, f64, *const f64, *mut f64);
/// `rig_redo`.
pub(crate) type RedoFn = unsafe extern "C" fn(
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
pub(crate) const REDO_FIRED: usize = MAX_EVENTS_PER_STEP + 1;

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
    pub(crate) rk4: Rk4Fn,
    pub(crate) lists: [ListFn; 3],
    /// `rig_deriv1` and `rig_events1`, where no `rig_redo` is built.
    pub(crate) one_run: Option<[Deriv1Fn; 2]>,
    /// `rig_redo`, where the lane code has switches and no tables
    /// ([`crate::compile::back::c::redoes`]).
    pub(crate) redo: Option<RedoFn>,
    /// The lanes [`Self::redo`] takes at once: an f64 vector's.
    pub(crate) redo_lanes: usize,
    /// The lane code's register count, state count and event-function
    /// count, which [`Self::deriv1`]'s and [`Self::events1`]'s slices hold.
    pub(crate) registers: usize,
    pub(crate) states: usize,
    pub(crate) events: usize,
    /// Table values per derivative in [`Self::rk4`]'s `tab`.
    pub(crate) table_stride: usize,
    /// The per-run constants whose values, shared by every lane, let
    /// [`Self::rk4`] compute the derivative's time-only part once per call
    /// ([`crate::compile::back::c::hoistable`]).
    pub(crate) hoist_reads: Vec<u16>,
    /// The arithmetic it computes in.
    pub arith: Arith,
    /// Kept loaded for the functions above.
    pub(crate) _lib: libloading::Library,
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
