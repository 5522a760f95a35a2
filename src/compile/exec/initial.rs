//! The state and the regimes a run starts in.
//!
//! Without initial-state parameters a run starts at rest with every mode
//! variable at its value 0 (gaps open, elastic, intact, stuck), as it always
//! has. A program whose states start from parameters ([`Program::has_initial`])
//! also starts in the regimes that state implies: every event function is
//! evaluated at `t = 0` and the initial state, and an armed transition whose
//! function is strictly past its switch (`g > 0` for [`Direction::Up`], `g < 0`
//! for [`Direction::Down`]) fires, one at a time, the functions evaluated again
//! after each, until none fires. Each regime variable switches at most once
//! (from its value 0), so an inconsistent start (a tangential spring past
//! `+f_c` while the element shortens, past both the slip and the stick
//! switch) takes the first switch in program order instead of alternating. A gap
//! already closed starts in contact, a friction element whose tangential
//! spring is already past `±f_c` starts slipping, an element already past its
//! yield limit or its `breaks_at` starts yielded or broken. A function exactly
//! at its switch does not fire, so a run at rest keeps every mode at 0 and two
//! opposite transitions at the same switch never alternate. The reference
//! computes this once per run on the host; the GPU kernels read the result as
//! the run's packed values ([`crate::compile::GpuRig::pack`]).

use crate::compile::exec::tape::{Frame, Point, Tape};
use crate::compile::program::{Direction, Program};

/// The held states' values before the first sample instant (the values of
/// [`crate::compile::program::Sampling::initial`], run constants of `frame`).
pub fn initial_held(prog: &Program, frame: &Frame<'_>) -> Vec<f64> {
    prog.sampling.as_ref().map_or_else(Vec::new, |s| {
        s.initial.iter().map(|&id| frame.get(id)).collect()
    })
}

/// The run's initial state (the values of [`Program::initial`], evaluated in
/// `frame`, whose run constants are filled) and initial regimes.
pub fn initial_state(prog: &Program, tape: &Tape, frame: &mut Frame<'_>) -> (Vec<f64>, Vec<u32>) {
    let n = prog.deriv.len();
    let y: Vec<f64> = (0..n)
        .map(|s| prog.initial.get(s).map_or(0.0, |&id| frame.get(id)))
        .collect();
    let mut regimes = vec![0; prog.mode_count()];
    if !prog.has_initial() {
        return (y, regimes);
    }
    let mut switched = vec![false; regimes.len()];
    let held = initial_held(prog, frame);
    loop {
        let pt = Point {
            t: 0.0,
            y: &y,
            regimes: &regimes,
            held: &held,
        };
        frame.eval(&tape.event_ops, pt);
        let fire = prog.transitions.iter().find(|tr| {
            let g = frame.get(tr.g);
            !switched[tr.var as usize]
                && tr.armed(&regimes)
                && match tr.dir {
                    Direction::Up => g > 0.0,
                    Direction::Down => g < 0.0,
                }
        });
        match fire {
            Some(tr) => {
                regimes[tr.var as usize] = tr.to;
                switched[tr.var as usize] = true;
            }
            None => break,
        }
    }
    (y, regimes)
}
