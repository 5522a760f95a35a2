//! `rigs/quarter_car_friction.json` (the vehicle suspension paper (data interrogation for vehicle suspensions, ASME, 2005)'s quarter car with the
//! strut seal's Coulomb friction, a `stick_slip` element in the strut): the
//! shipped campaign recovers the strut, the seal's slip
//! force and its tangential stiffness from a synthetic sprung-mass
//! acceleration record down to the noise floor, and no candidate of the search
//! chatters (the firing rule of `Transition::fires` holds a seal that sticks
//! at the slip limit at a turning point).

mod paper_rigs_common;

use paper_rigs_common::recover;

#[test]
fn the_shipped_campaign_recovers_the_strut_and_its_seal_without_chattering() {
    let r = recover(
        "quarter_car_friction_synthetic.json",
        "quarter_car_friction_reference_params.json",
        64,
        30,
        2,
    );
    for name in ["k2", "c2", "c2_high", "v_knee", "k_b", "play", "f_s", "k_s"] {
        assert!(r.determined(name), "{name} undetermined");
    }
    assert_eq!(r.summary.diverged_runs, 0, "runs flagged as chattering");
    r.assert_recovered(1.02, 0.05);
}
