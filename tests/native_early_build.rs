//! A native build started early (`start_builds`, which a job long enough to
//! want it calls as it opens the CPU evaluator) runs on a thread of its own:
//! runs keep interpreting while it builds (`NativeSlot::get` gives nothing
//! and does not wait), one build of a program at a time, and once it is done
//! every run gets it.

use rigfit::compile::back::native::{NativeSlot, start_builds};
use rigfit::compile::exec::lane_code::LaneCode;

#[test]
fn an_early_build_lets_runs_interpret_until_it_is_done() {
    let (id, _) = rigfit::rig::SHIPPED[0];
    let desc = rigfit::rig::shipped(id).expect("a shipped rig");
    let lowered = rigfit::compile::lower(&desc, id).expect("it lowers");
    let prog = &lowered.programs[0];
    let tape = rigfit::compile::Tape::new(prog);
    let code = LaneCode::new(prog, &tape);

    let slot = NativeSlot::default();
    let thread = start_builds(&[(&slot, &code)]).expect("the build's thread starts");
    // Claimed before the thread starts: whatever the compiler's speed, a
    // run asks while it builds (this process has built nothing before).
    assert!(
        slot.get(&code, u64::MAX / 2).is_none(),
        "a run waited for the build or built it again"
    );
    assert!(
        start_builds(&[(&slot, &code)]).is_none(),
        "a second build of the same program started"
    );
    thread.join().expect("the build's thread");
    assert!(slot.get(&code, 0).is_some(), "the build is not there");
    assert!(start_builds(&[(&slot, &code)]).is_none(), "built twice");
}
