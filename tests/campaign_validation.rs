//! Every kind of bad campaign or data file is refused with one line naming the
//! file, the JSON path (or CSV line) and what was expected.

mod campaign_common;
use campaign_common as common;

use common::{csv, example, remove, set, write};
use rigfit::campaign::Campaign;
use serde_json::{Value, json};

/// One bad campaign: how to spoil the example, the data files, and the message
/// fragments the error must contain.
struct Case {
    label: &'static str,
    spoil: fn(&mut Value),
    data: Option<String>,
    expect: &'static [&'static str],
}

fn good_csv() -> String {
    csv(300, 1e-6, 0.0)
}

/// A record whose force is 100 N throughout.
fn csv_constant() -> String {
    let mut s = String::from("t_s,force_N\n");
    for k in 0..300 {
        s += &format!("{:e},100\n", k as f64 * 1e-6);
    }
    s
}

/// The example CSV with line `line` (1-based) replaced.
fn csv_with_line(line: usize, text: &str) -> String {
    let mut lines: Vec<String> = good_csv().lines().map(String::from).collect();
    lines[line - 1] = text.to_string();
    lines.join("\n")
}

fn run_case(case: &Case) {
    let dir = tempfile::tempdir().unwrap();
    let mut v = example();
    (case.spoil)(&mut v);
    let data = case.data.clone().unwrap_or_else(good_csv);
    let path = write(dir.path(), &v.to_string(), &[("v2.csv", &data)]);
    let err = match Campaign::load(&path) {
        Ok(_) => panic!("{}: accepted", case.label),
        Err(e) => e.to_string(),
    };
    assert!(
        !err.contains('\n'),
        "{}: message spans lines: {err}",
        case.label
    );
    assert!(
        err.contains("campaign.json"),
        "{}: no file in {err}",
        case.label
    );
    for f in case.expect {
        assert!(
            err.contains(f),
            "{}: expected {f:?} in\n  {err}",
            case.label
        );
    }
}

macro_rules! case {
    ($label:expr, $spoil:expr, [$($e:expr),*]) => {
        Case { label: $label, spoil: $spoil, data: None, expect: &[$($e),*] }
    };
    ($label:expr, $spoil:expr, data = $data:expr, [$($e:expr),*]) => {
        Case { label: $label, spoil: $spoil, data: Some($data), expect: &[$($e),*] }
    };
}

#[test]
fn bad_campaign_values_name_path_and_expectation() {
    let cases = [
        case!(
            "unknown top-level key",
            |v| set(v, "/outptu", json!("x")),
            ["unknown field `outptu`"]
        ),
        case!(
            "unknown nested key",
            |v| set(v, "/experiments/0/fit_window/stop", json!(1.0)),
            ["experiments[0].fit_window.stop", "unknown field `stop`"]
        ),
        case!(
            "wrong type",
            |v| set(v, "/search/population", json!("many")),
            ["search.population", "invalid type"]
        ),
        case!(
            "missing data",
            |v| remove(v, "/experiments/0/data"),
            ["experiments[0]", "missing field `data`"]
        ),
        case!(
            "unknown range key",
            |v| set(v, "/params/c1/mx", json!(1.0)),
            ["params.c1.mx", "unknown field `mx`"]
        ),
        case!(
            "misspelt parameter",
            |v| set(v, "/params/k_1", json!(1e9)),
            ["params.k_1", "unknown parameter 'k_1'", "did you mean 'k1'"]
        ),
        case!(
            "parameter in the wrong case",
            |v| set(v, "/params/K1", json!(1e9)),
            [
                "params.K1",
                "unknown parameter 'K1'",
                "did you mean 'k1'? (names are case-sensitive)"
            ]
        ),
        case!(
            "polynomial degree 6",
            |v| set(v, "/experiments/0/params/a6", json!(1.0)),
            ["experiments[0].params.a6", "polynomial degree is at most 5"]
        ),
        case!(
            "rig parameter in experiment",
            |v| set(v, "/experiments/0/params/k1", json!(1e9)),
            [
                "experiments[0].params.k1",
                "rig parameter 'k1' must be set in the campaign's top-level params"
            ]
        ),
        case!(
            "missing rig parameter",
            |v| remove(v, "/params/m2"),
            ["params: missing parameter(s) without a model default: m2"]
        ),
        case!(
            "missing experiment parameter",
            |v| remove(v, "/experiments/0/params/velocity"),
            ["experiments[0].params: missing parameter(s) without a model default: velocity"]
        ),
        case!(
            "min >= max",
            |v| set(v, "/params/c1", json!({"min": 3e6, "max": 1e4})),
            ["params.c1.max: expected max > min (3000000), found 10000"]
        ),
        case!(
            "log over zero",
            |v| set(v, "/params/c1", json!({"min": 0.0, "max": 1e6})),
            [
                "params.c1.min",
                "min > 0 for log scale",
                "default scale for 'c1'",
                "found 0"
            ]
        ),
        case!(
            "init outside",
            |v| set(v, "/params/k1/init", json!(1e11)),
            ["params.k1.init: expected a value in [2000000000, 30000000000], found 100000000000"]
        ),
        case!(
            "negative mass",
            |v| set(v, "/params/m1", json!(-1.0)),
            ["params.m1: expected m1: a mass > 0, found -1"]
        ),
        case!(
            "zero mass bound",
            |v| set(
                v,
                "/params/m2",
                json!({"min": 0.0, "max": 1.0, "scale": "linear"})
            ),
            ["params.m2.min: expected m2: a mass > 0, found 0"]
        ),
        case!(
            "the retired model key",
            |v| set(v, "/model", json!("tensile5")),
            [
                "model: expected \"rig\": the \"model\" key is gone, write \"rig\": \"tensile4\"",
                "\"model\": \"tensile5\""
            ]
        ),
        case!(
            "missing data file",
            |v| set(v, "/experiments/0/data/file", json!("nope.csv")),
            ["experiments[0].data.file", "nope.csv: cannot read"]
        ),
        case!(
            "no such column",
            |v| set(v, "/experiments/0/data/force_column", json!("F")),
            [
                "experiments[0].data",
                "v2.csv:3: no column 'F'",
                "t_s, force_N"
            ]
        ),
        case!(
            "non-numeric cell",
            |_| {},
            data = csv_with_line(10, "6e-6,abc"),
            ["v2.csv:10: column 2 ('force_N'): expected a number, found 'abc'"]
        ),
        case!(
            "NaN cell",
            |_| {},
            data = csv_with_line(12, "8e-6,NaN"),
            ["v2.csv:12: column 2 ('force_N'): expected a finite number, found 'NaN'"]
        ),
        case!(
            "infinite time",
            |_| {},
            data = csv_with_line(12, "inf,1.0"),
            ["v2.csv:12: column 1 ('t_s'): expected a finite number"]
        ),
        case!(
            "duplicate time",
            |_| {},
            data = csv_with_line(12, "7e-6,1.0"),
            [
                "v2.csv:12: time column 1 ('t_s'): expected a strictly increasing time, found 0.000007 s after 0.000007 s"
            ]
        ),
        case!(
            "decreasing time",
            |_| {},
            data = csv_with_line(12, "1e-6,1.0"),
            ["v2.csv:12: time column 1 ('t_s'): expected a strictly increasing time"]
        ),
        case!(
            "short row",
            |_| {},
            data = csv_with_line(12, "8e-6"),
            ["v2.csv:12: row: expected at least 2 fields, found 1 field(s)"]
        ),
        case!(
            "single sample",
            |_| {},
            data = "t_s,force_N\n0.0,1.0\n".into(),
            ["v2.csv: expected at least 2 samples, found 1"]
        ),
        case!(
            "window outside data",
            |v| set(
                v,
                "/experiments/0/fit_window",
                json!({"start": 1.0, "end": 2.0})
            ),
            [
                "experiments[0].fit_window: expected a window holding at least 2 samples",
                "holding 0 sample(s)"
            ]
        ),
        case!(
            "window reversed",
            |v| set(
                v,
                "/experiments/0/fit_window",
                json!({"start": 2e-4, "end": 1e-4})
            ),
            ["experiments[0].fit_window.end: expected end > start"]
        ),
        case!(
            "population 3",
            |v| set(v, "/search/population", json!(3)),
            ["search.population: expected at least 4, found 3"]
        ),
        case!(
            "zero generations",
            |v| set(v, "/search/generations", json!(0)),
            ["search.generations: expected at least 1, found 0"]
        ),
        case!(
            "elitism >= population",
            |v| set(v, "/search/elitism", json!(64)),
            ["search.elitism: expected less than the population (64)"]
        ),
        case!(
            "crossover probability",
            |v| set(v, "/search/crossover", json!({"probability": 1.5})),
            ["search.crossover.probability: expected a value in [0, 1], found 1.5"]
        ),
        case!(
            "no experiments",
            |v| set(v, "/experiments", json!([])),
            ["experiments: expected at least one experiment"]
        ),
        case!(
            "zero weight",
            |v| set(v, "/experiments/0/weight", json!(0.0)),
            ["experiments[0].weight: expected a weight > 0, found 0"]
        ),
        case!(
            "negative weight",
            |v| set(v, "/experiments/0/weight", json!(-2)),
            ["experiments[0].weight: expected a weight > 0, found -2"]
        ),
        case!(
            "zero substeps",
            |v| set(v, "/solver/substeps", json!(0)),
            ["solver.substeps", "an integer ≥ 1 or \"auto\""]
        ),
        case!(
            "word substeps",
            |v| set(v, "/solver/substeps", json!("fast")),
            ["solver.substeps", "an integer ≥ 1 or \"auto\""]
        ),
        case!(
            "unknown backend",
            |v| set(v, "/solver/backend", json!("tpu")),
            ["solver.backend", "unknown variant `tpu`"]
        ),
        case!(
            "unknown drive",
            |v| set(v, "/experiments/0/drive", json!("displacement")),
            ["experiments[0].drive", "unknown variant `displacement`"]
        ),
        case!(
            "force table decreasing",
            |v| set(
                v,
                "/experiments/0/drive",
                json!({"force": {"t": [0.0, 1e-3, 1e-3], "value": [0, 1, 2]}})
            ),
            ["experiments[0].drive.force.t[2]: expected strictly increasing times"]
        ),
        case!(
            "force table one point",
            |v| set(
                v,
                "/experiments/0/drive",
                json!({"force": {"t": [0.0], "value": [0]}})
            ),
            ["experiments[0].drive.force: expected at least 2 points"]
        ),
        case!(
            "log offset",
            |v| set(
                v,
                "/experiments/0/offset",
                json!({"min": 1e-6, "max": 1e-5, "scale": "log"})
            ),
            ["experiments[0].offset.scale: expected \"linear\""]
        ),
        case!(
            "zero time scale",
            |v| set(v, "/experiments/0/data/time_scale", json!(0.0)),
            ["experiments[0].data.time_scale: expected a multiplier > 0"]
        ),
        case!(
            "experiment name with dot",
            |v| set(v, "/experiments/0/name", json!("v.2")),
            ["experiments[0].name: expected a non-empty name without '.'"]
        ),
        case!(
            "duplicate experiment",
            |v| {
                let x = v["experiments"][0].clone();
                v["experiments"].as_array_mut().unwrap().push(x);
            },
            ["experiments[1].name: expected a unique experiment name"]
        ),
        case!(
            "empty name",
            |v| set(v, "/name", json!("")),
            ["name: expected a non-empty name"]
        ),
        case!(
            "the time column again as the measured column",
            |v| set(v, "/experiments/0/data/force_column", json!("t_s")),
            [
                "experiments[0].data.force_column: expected a measured column other than the time column",
                "v2.csv",
                "the time values again"
            ]
        ),
        case!(
            "a measured sample whose square overflows",
            |_| {},
            data = csv_with_line(100, "9.6e-5,1e300"),
            [
                "experiments[0].data: expected measured values whose squared deviations add up to a finite number in",
                "v2.csv (R² divides by that sum), found",
                "1e300 at t = 9.6e-5 s"
            ]
        ),
        case!(
            "constant force in the fit window",
            |_| {},
            data = csv_constant(),
            [
                "experiments[0].fit_window: expected a force that varies",
                "v2.csv",
                "100 N at every sample"
            ]
        ),
        case!(
            "campaign named ..",
            |v| set(v, "/name", json!("..")),
            ["name: expected a non-empty name", "not '.' or '..'"]
        ),
        case!(
            "experiment name too long for a file name",
            |v| set(v, "/experiments/0/name", json!("v".repeat(300))),
            [
                "experiments[0].name: expected",
                "at most 100 characters",
                "300 characters"
            ]
        ),
        case!(
            "experiment name with a newline",
            |v| set(v, "/experiments/0/name", json!("v2\nINFO fake log line")),
            [
                "experiments[0].name: expected",
                "\"v2\\nINFO fake log line\""
            ]
        ),
        case!(
            "experiment called history",
            |v| set(v, "/experiments/0/name", json!("History")),
            [
                "experiments[0].name: expected",
                "\"History\"",
                "history.csv"
            ]
        ),
        case!(
            "names that differ only in case",
            |v| {
                let mut x = v["experiments"][0].clone();
                x["name"] = json!("V2");
                v["experiments"].as_array_mut().unwrap().push(x);
            },
            [
                "experiments[1].name: expected a unique experiment name",
                "\"V2\"",
                "\"v2\""
            ]
        ),
        case!(
            "non-ASCII names that map to one file",
            |v| {
                set(v, "/experiments/0/name", json!("versuch_µ_😀"));
                let mut x = v["experiments"][0].clone();
                x["name"] = json!("versuch_ä_ö");
                v["experiments"].as_array_mut().unwrap().push(x);
            },
            ["experiments[1].name", "versuch____.csv", "\"versuch_µ_😀\""]
        ),
        case!(
            "a weight a billionth of another",
            |v| {
                let mut x = v["experiments"][0].clone();
                x["name"] = json!("v3");
                x["weight"] = json!(1e-10);
                v["experiments"].as_array_mut().unwrap().push(x);
            },
            ["experiments[1].weight: expected a weight at least 1/1e9 of the largest"]
        ),
    ];
    for case in &cases {
        run_case(case);
    }
}

#[test]
fn malformed_json_gives_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "{\n  \"name\": \"x\",\n  \"rig\": ,\n}", &[]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.contains("campaign.json:3:"), "{err}");
    assert!(err.contains("malformed JSON"), "{err}");
}

#[test]
fn type_errors_give_line_and_column_too() {
    let dir = tempfile::tempdir().unwrap();
    let text = serde_json::to_string_pretty(&{
        let mut v = example();
        set(&mut v, "/experiments/0/weight", json!("heavy"));
        v
    })
    .unwrap();
    let line = text.lines().position(|l| l.contains("heavy")).unwrap() + 1;
    let path = write(dir.path(), &text, &[("v2.csv", &good_csv())]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.contains(&format!("campaign.json:{line}:")), "{err}");
    assert!(
        err.contains("experiments[0].weight: invalid type: string \"heavy\""),
        "{err}"
    );
}

#[test]
fn missing_campaign_file_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let err = Campaign::load(&dir.path().join("absent.json"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("absent.json: cannot read"), "{err}");
}

#[test]
fn a_campaign_without_free_parameters_loads_but_cannot_run() {
    let dir = tempfile::tempdir().unwrap();
    let mut v = example();
    set(&mut v, "/params/k1", json!(8.4e9));
    set(&mut v, "/params/c1", json!(5.51e5));
    set(&mut v, "/experiments/0/params/k_lin", json!(8.63e7));
    let path = write(dir.path(), &v.to_string(), &[("v2.csv", &good_csv())]);
    let c = Campaign::load(&path).unwrap();
    assert!(c.genes.is_empty());
    let err = c.require_genes().unwrap_err().to_string();
    assert!(
        err.contains("campaign.json: params: expected at least one free parameter"),
        "{err}"
    );
}

#[test]
fn a_parameter_given_twice_is_refused_not_last_one_wins() {
    let dir = tempfile::tempdir().unwrap();
    let text = example().to_string();
    for (from, to, at) in [
        ("\"m1\":7.9", "\"m1\":7.9,\"m1\":1000", "params"),
        (
            "\"velocity\":2.0",
            "\"velocity\":2.0,\"velocity\":20.0",
            "experiments[0].params",
        ),
    ] {
        assert!(text.contains(from), "{text}");
        let path = write(
            dir.path(),
            &text.replacen(from, to, 1),
            &[("v2.csv", &good_csv())],
        );
        let err = Campaign::load(&path).unwrap_err().to_string();
        assert!(err.contains(&format!("{at}: ")), "{err}");
        assert!(err.contains("given twice"), "{err}");
    }
    // The same in a --params file.
    let path = write(dir.path(), &text, &[("v2.csv", &good_csv())]);
    let mut c = Campaign::load(&path).unwrap();
    let params = dir.path().join("p.json");
    std::fs::write(&params, r#"{"params": {"m1": 7.9, "m1": 1000}}"#).unwrap();
    let err = c.apply_param_file(&params).unwrap_err().to_string();
    assert!(
        err.contains("p.json") && err.contains("given twice"),
        "{err}"
    );
    assert_eq!(c.base[0][0], 7.9);
}

#[test]
fn text_after_the_campaign_object_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = serde_json::to_string_pretty(&example()).unwrap();
    let lines = text.lines().count();
    let path = write(
        dir.path(),
        &format!("{text}\n{{}}garbage"),
        &[("v2.csv", &good_csv())],
    );
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(
        err.contains(&format!("campaign.json:{}:", lines + 1)),
        "{err}"
    );
    assert!(err.contains("end of the file"), "{err}");
    // Trailing blanks are fine, and so is a byte-order mark in front.
    let path = write(
        dir.path(),
        &format!("\u{feff}{text}\n\n  "),
        &[("v2.csv", &good_csv())],
    );
    Campaign::load(&path).unwrap();
}

#[test]
fn a_top_level_array_names_what_was_expected_not_an_internal_type() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), " []", &[]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.contains("campaign.json:1:2:"), "{err}");
    assert!(err.contains("expected a JSON object"), "{err}");
    assert!(!err.contains("Raw"), "{err}");
}

#[test]
fn weights_near_the_largest_float_still_give_the_weighted_mean() {
    let dir = tempfile::tempdir().unwrap();
    for (w0, w1, expected) in [
        (1e308, 1e308, 0.5 * (0.78 + 0.58)),
        (1e308, 5e307, (0.78 + 0.5 * 0.58) / 1.5),
        (1.0, 1.0, 0.5 * (0.78 + 0.58)),
    ] {
        let mut v = example();
        set(&mut v, "/experiments/0/weight", json!(w0));
        let mut x = v["experiments"][0].clone();
        x["name"] = json!("v3");
        x["weight"] = json!(w1);
        v["experiments"].as_array_mut().unwrap().push(x);
        let path = write(dir.path(), &v.to_string(), &[("v2.csv", &good_csv())]);
        let c = Campaign::load(&path).unwrap();
        let scores = rigfit::eval::Scores {
            experiments: 2,
            values: vec![0.78, 0.58],
            diverged: 0,
        };
        let joint = c.combine(&scores)[0];
        assert!((joint - expected).abs() < 1e-12, "{w0} {w1}: {joint}");
    }
}

#[test]
fn an_unknown_parameter_name_is_quoted_short_and_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let long = format!("k\n{}", "x".repeat(100_000));
    let mut v = example();
    set(&mut v, &format!("/params/{long}"), json!(1.0));
    let path = write(dir.path(), &v.to_string(), &[("v2.csv", &good_csv())]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.len() < 600, "{} bytes", err.len());
    assert!(
        err.contains("unknown parameter 'k\\nxxx") && err.contains("100002 bytes"),
        "{err}"
    );
    assert!(!err.contains('\n'), "{err}");
}
