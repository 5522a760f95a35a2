//! The specimen-law fit recovers known laws from noisy generated data and
//! refuses data that cannot support the degree asked.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::identify::IdentifyError;
use rigfit::identify::csv_input::{parse_two_columns, read_two_columns};
use rigfit::identify::specimen::{SpecimenFitOptions, YieldChoice, fit};

const K_LIN: f64 = 8.63e7;
const E_YIELD: f64 = 5.4e-5;
const CUBIC: [f64; 4] = [4.56e3, 1.97e6, -9.26e8, 1.36e11];

fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

fn law(e: f64, k: f64, ey: f64, a: &[f64]) -> f64 {
    if e <= ey {
        k * e
    } else {
        a.iter().rev().fold(0.0, |acc, c| acc * e + c)
    }
}

fn generate(
    n: usize,
    e_max: f64,
    k: f64,
    ey: f64,
    a: &[f64],
    sigma: f64,
    seed: u64,
) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let e: Vec<f64> = (0..n).map(|i| e_max * i as f64 / (n - 1) as f64).collect();
    let f = e
        .iter()
        .map(|&e| law(e, k, ey, a) + sigma * gauss(&mut rng))
        .collect();
    (e, f)
}

fn options(degree: usize) -> SpecimenFitOptions {
    SpecimenFitOptions {
        degree,
        e_yield: None,
    }
}

#[test]
fn cubic_reference_law_is_recovered_from_noisy_data() {
    let (e, f) = generate(1001, 1e-3, K_LIN, E_YIELD, &CUBIC, 3.0, 7);
    let fit = fit(&e, &f, &options(3)).unwrap();
    assert_eq!(fit.yield_choice, YieldChoice::BestTotalFit);
    assert!(
        (fit.k_lin / K_LIN - 1.0).abs() < 0.01,
        "k_lin {}",
        fit.k_lin
    );
    assert!(
        (fit.e_yield - E_YIELD).abs() <= 3e-6,
        "e_yield {}",
        fit.e_yield
    );
    for i in 0..=100 {
        let x = 1e-5 * i as f64;
        let err = fit.force(x) - law(x, K_LIN, E_YIELD, &CUBIC);
        assert!(
            err.abs() < 5.0 || (x - E_YIELD).abs() < 4e-6,
            "S({x}) off by {err} N"
        );
    }
    // The cubic is well conditioned on [e_yield, 1e-3]: low-order coefficients close.
    assert!(
        (fit.coefficients[0] / CUBIC[0] - 1.0).abs() < 0.005,
        "{:?}",
        fit.coefficients
    );
    assert!(
        (fit.coefficients[1] / CUBIC[1] - 1.0).abs() < 0.05,
        "{:?}",
        fit.coefficients
    );
    assert!(
        fit.r2_total >= 0.999 && fit.r2_plastic >= 0.999 && fit.r2_elastic >= 0.999,
        "{fit:?}"
    );
    assert!((fit.rmse - 3.0).abs() < 0.5, "rmse {}", fit.rmse);
    assert!(fit.jump_at_yield.abs() < 20.0, "jump {}", fit.jump_at_yield);
}

#[test]
fn noise_free_cubic_gives_exact_coefficients() {
    let (e, f) = generate(401, 1e-3, K_LIN, E_YIELD, &CUBIC, 0.0, 1);
    let fit = fit(&e, &f, &options(3)).unwrap();
    for (got, want) in fit.coefficients.iter().zip(CUBIC) {
        assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
    }
    assert!((fit.k_lin / K_LIN - 1.0).abs() < 1e-9);
    assert!(fit.r2_total > 1.0 - 1e-12);
    // The reference branches meet just below e_yield.
    let meet = fit.e_meet.expect("branches cross near e_yield");
    assert!((meet - E_YIELD).abs() < 2e-6, "e_meet {meet}");
}

#[test]
fn quintic_carbon_epoxy_like_law_is_recovered() {
    // A softening quintic that meets the elastic line near e_yield = 2e-4 m.
    let (k, ey) = (3.0e7, 2.0e-4);
    let a = [1.5e3, 2.4e7, -3.0e10, 2.0e13, -6.0e15, 6.5e17];
    let (e, f) = generate(1201, 1.2e-3, k, ey, &a, 2.0, 11);
    let fit = fit(&e, &f, &options(5)).unwrap();
    assert_eq!(fit.coefficients.len(), 6);
    assert!((fit.k_lin / k - 1.0).abs() < 0.01);
    for i in 25..=120 {
        let x = 1e-5 * i as f64;
        let err = fit.force(x) - law(x, k, ey, &a);
        assert!(err.abs() < 4.0, "S({x}) off by {err} N");
    }
    assert!(fit.r2_total >= 0.999 && fit.r2_plastic >= 0.999, "{fit:?}");
}

#[test]
fn fixed_e_yield_is_used_and_fragment_lists_all_parameters() {
    let (e, f) = generate(501, 1e-3, K_LIN, E_YIELD, &CUBIC, 3.0, 3);
    let opts = SpecimenFitOptions {
        degree: 3,
        e_yield: Some(6.0e-5),
    };
    let fit = fit(&e, &f, &opts).unwrap();
    assert_eq!(fit.yield_choice, YieldChoice::Fixed);
    assert_eq!(fit.e_yield, 6.0e-5);
    let fragment = fit.to_campaign_fragment();
    let params = fragment["params"].as_object().unwrap();
    for name in ["k_lin", "e_yield", "a0", "a1", "a2", "a3", "a4", "a5"] {
        assert!(params[name].is_f64(), "{name} missing");
    }
    assert_eq!(params["a4"].as_f64(), Some(0.0));
    assert_eq!(params["k_lin"].as_f64(), Some(fit.k_lin));
}

#[test]
fn shipped_example_file_fits_the_reference_law() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/campaigns/specimen_quasistatic_synthetic.csv"
    );
    let data = read_two_columns(path.as_ref()).unwrap();
    let fit = fit(&data.x, &data.y, &options(3)).unwrap();
    assert!((fit.k_lin / K_LIN - 1.0).abs() < 0.01, "{fit:?}");
    assert!((fit.e_yield - E_YIELD).abs() <= 3e-6, "{fit:?}");
    assert!(fit.r2_total >= 0.999, "{fit:?}");
}

#[test]
fn degree_outside_one_to_five_is_refused() {
    let (e, f) = generate(101, 1e-3, K_LIN, E_YIELD, &CUBIC, 3.0, 1);
    for degree in [0, 6] {
        let err = fit(&e, &f, &options(degree)).unwrap_err();
        assert!(
            matches!(err, IdentifyError::DegreeOutOfRange { max: 5, .. }),
            "{err}"
        );
    }
}

#[test]
fn too_few_points_are_refused() {
    let (e, f) = generate(8, 1e-3, K_LIN, E_YIELD, &CUBIC, 0.0, 1);
    let err = fit(&e, &f, &options(5)).unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::TooFewPoints {
                needed: 9,
                found: 8,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("at least 9"));
}

#[test]
fn purely_elastic_data_has_no_plastic_range() {
    // Elastic up to the end of the data: nothing for a polynomial to fit.
    let (e, f) = generate(300, 5.0e-5, K_LIN, 1.0, &CUBIC, 3.0, 5);
    let err = fit(&e, &f, &options(3)).unwrap_err();
    assert!(matches!(err, IdentifyError::NoPlasticRange { .. }), "{err}");
    let exact: Vec<f64> = e.iter().map(|x| K_LIN * x).collect();
    let err = fit(&e, &exact, &options(3)).unwrap_err();
    assert!(matches!(err, IdentifyError::NoPlasticRange { .. }), "{err}");
}

#[test]
fn fixed_e_yield_leaving_too_few_plastic_points_is_refused() {
    let (e, f) = generate(101, 1e-3, K_LIN, E_YIELD, &CUBIC, 3.0, 1);
    let opts = SpecimenFitOptions {
        degree: 3,
        e_yield: Some(0.99e-3),
    };
    let err = fit(&e, &f, &opts).unwrap_err();
    assert!(
        matches!(err, IdentifyError::BadYield { plastic: 1, .. }),
        "{err}"
    );
}

#[test]
fn non_finite_and_mismatched_inputs_are_refused() {
    let (e, mut f) = generate(101, 1e-3, K_LIN, E_YIELD, &CUBIC, 3.0, 1);
    let err = fit(&e[..100], &f, &options(3)).unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::LengthMismatch {
                x_len: 100,
                y_len: 101,
                ..
            }
        ),
        "{err}"
    );
    f[17] = f64::NAN;
    let err = fit(&e, &f, &options(3)).unwrap_err();
    assert!(
        matches!(err, IdentifyError::NonFiniteSample { index: 17, .. }),
        "{err}"
    );
}

#[test]
fn non_numeric_and_nan_csv_lines_are_reported_with_line_numbers() {
    let err = parse_two_columns("# synthetic\nelongation,force\n0,0\n1e-6,eighty\n").unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::NotNumeric {
                line: 4,
                column: 2,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().starts_with("line 4, column 2"));
    let err = parse_two_columns("0,0\n1e-6,NaN\n").unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::NotFinite {
                line: 2,
                column: 2,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn elongations_without_spread_past_yield_are_refused() {
    // An elastic ramp, then an extensometer that stalls: the force rises
    // while the elongation stays (nearly) put. A cubic through that is
    // noise amplified (a3 of order 1e15), not a law.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for spread in [0.0, 1e-8, 1e-6] {
        let n = 200;
        let mut e: Vec<f64> = (0..n).map(|i| 5e-4 * i as f64 / n as f64).collect();
        let mut f: Vec<f64> = e.iter().map(|&e| 7e7 * e + gauss(&mut rng)).collect();
        for i in 0..n {
            e.push(6e-4 + spread * (i as f64 / n as f64));
            f.push(35e3 + 5e3 * (i as f64 / n as f64) + gauss(&mut rng));
        }
        let err = fit(&e, &f, &options(3)).unwrap_err();
        let text = err.to_string();
        println!("{spread}: {text}");
        assert!(
            matches!(
                err,
                IdentifyError::Numerical {
                    stage: "specimen plastic fit",
                    ..
                }
            ),
            "{text}"
        );
        assert!(text.contains("too little spread"), "{text}");
    }
}
