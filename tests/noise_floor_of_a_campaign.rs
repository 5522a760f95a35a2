//! The joint cost the records' noise alone would give (the convergence
//! plot's noise floor): on the shipped example, made with 20 N of noise, it
//! is that noise's share of the record's variance, and the polished fit the
//! README shows sits at it.

use std::path::Path;

use rigfit::campaign::Campaign;

#[test]
fn the_noise_floor_is_the_records_noise_over_its_variance() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let c = Campaign::load(&path).unwrap();
    let floor = c.problem.noise_floor().unwrap();
    let x = &c.problem.experiments[0];
    let made_with = x.window.len() as f64 * 20.0 * 20.0 / x.ss_tot();
    println!("floor {floor:e}, from the noise the record was made with {made_with:e}");
    assert!(
        (floor / made_with - 1.0).abs() < 0.2,
        "floor {floor:e} against {made_with:e} from the 20 N the record was made with"
    );
}
