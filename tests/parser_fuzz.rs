//! The campaign parser and the CSV loader never panic, whatever they are fed:
//! random text, mutated campaigns, extreme numbers.

mod campaign_common;
use campaign_common as common;

use std::path::Path;

use common::{csv, example};
use proptest::prelude::*;
use rigfit::base::data::{Column, CsvSpec, parse_csv};
use rigfit::campaign::Campaign;
use serde_json::Value;

/// Every JSON pointer of `v`, containers included.
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                pointers(x, format!("{at}/{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                pointers(x, format!("{at}/{i}"), out);
            }
        }
        _ => {}
    }
    if !at.is_empty() {
        out.push(at);
    }
}

fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(-1.0),
        Just(1e300),
        Just(-1e300),
        Just(1e-300),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        -10.0..10.0f64,
    ]
}

fn json_value() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        number().prop_map(|x| serde_json::json!(x)),
        any::<u64>().prop_map(|x| serde_json::json!(x)),
        "[a-z_.0-9]{0,8}".prop_map(Value::String),
        Just(serde_json::json!("auto")),
        Just(serde_json::json!("log")),
    ];
    leaf.prop_recursive(2, 8, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            prop::collection::btree_map(
                "min|max|init|scale|t|value|start|end|force|x",
                inner,
                0..4
            )
            .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

fn setup() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("v2.csv"), csv(200, 1e-6, 0.0)).unwrap();
    dir
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn campaign_parser_survives_value_replacement(which in any::<prop::sample::Index>(), value in json_value()) {
        let dir = setup();
        let mut v = example();
        let mut ptrs = Vec::new();
        pointers(&v, String::new(), &mut ptrs);
        let p = which.get(&ptrs).clone();
        *v.pointer_mut(&p).unwrap() = value;
        let _ = Campaign::from_str(&v.to_string(), dir.path(), "fuzz.json");
    }

    #[test]
    fn campaign_parser_survives_text_mutation(pos in any::<prop::sample::Index>(), cut in 0usize..8, insert in "[\\[\\]{}:,\"0-9.eE+-]{0,4}") {
        let dir = setup();
        let text = example().to_string();
        let at = pos.index(text.len());
        let end = (at + cut).min(text.len());
        let mutated = format!("{}{insert}{}", &text[..at], &text[end..]);
        if let Err(e) = Campaign::from_str(&mutated, dir.path(), "fuzz.json") {
            prop_assert!(!e.to_string().contains('\n'));
        }
    }

    #[test]
    fn campaign_parser_survives_random_ranges(min in number(), max in number(), init in prop::option::of(number()), log in any::<bool>(), param in "m1|m2|k1|c1|slack_b|gap|e_fracture|a3|velocity") {
        let dir = setup();
        let mut v = example();
        let mut r = serde_json::json!({"min": min, "max": max, "scale": if log { "log" } else { "linear" }});
        if let Some(i) = init { r["init"] = serde_json::json!(i); }
        if param == "velocity" {
            v["experiments"][0]["params"]["velocity"] = r;
        } else {
            v["params"][param.as_str()] = r;
        }
        if let Ok(c) = Campaign::from_str(&v.to_string(), dir.path(), "fuzz.json") {
            prop_assert!(c.solver.substeps >= 1);
            let mid: Vec<f64> = c.genes.iter().map(|g| 0.5 * (g.lower + g.upper)).collect();
            let b = c.batch(&[mid]);
            prop_assert_eq!(b.params.len(), 1);
        }
    }

    #[test]
    fn csv_loader_survives_random_text(text in "[0-9a-z,;\t.eE+\\-#\" \n]{0,300}", by_name in any::<bool>()) {
        let spec = if by_name {
            CsvSpec { time: Column::Name("t".into()), force: Column::Name("f".into()), ..CsvSpec::default() }
        } else {
            CsvSpec::default()
        };
        if let Ok(s) = parse_csv(&text, Path::new("fuzz.csv"), &spec) {
            prop_assert!(s.t.len() >= 2 && s.t.len() == s.force.len());
            prop_assert!(s.dt > 0.0 && s.dt.is_finite());
            prop_assert!(s.force.iter().all(|f| f.is_finite()));
        }
    }

    #[test]
    fn csv_decoding_survives_random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..300), stated in 0..5usize, decimal in 0..3usize) {
        use rigfit::base::data::{Decimal, decode_record};
        use rigfit::base::encoding::Encoding;
        let encoding = [None, Some(Encoding::Utf8), Some(Encoding::Utf16Le), Some(Encoding::Utf16Be), Some(Encoding::Windows1252)][stated];
        let decimal = [None, Some(Decimal::Point), Some(Decimal::Comma)][decimal];
        let spec = CsvSpec { encoding, decimal, ..CsvSpec::default() };
        if let Ok(text) = decode_record(&bytes, Path::new("fuzz.csv"), &spec) {
            let _ = parse_csv(&text, Path::new("fuzz.csv"), &spec);
        }
    }

    #[test]
    fn csv_loader_survives_extreme_numbers(rows in prop::collection::vec((number(), number()), 0..40), sorted in any::<bool>(), scale in number()) {
        let mut rows = rows;
        if sorted {
            rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        let mut text = String::from("t,f\n");
        for (t, f) in &rows {
            text.push_str(&format!("{t:e},{f:e}\n"));
        }
        let spec = CsvSpec { time_scale: scale, ..CsvSpec::default() };
        if let Ok(s) = parse_csv(&text, Path::new("fuzz.csv"), &spec) {
            prop_assert!(s.t.len() >= 2 && s.t.len() == s.force.len());
            prop_assert!(s.dt > 0.0 && s.dt.is_finite());
            prop_assert!(s.t.iter().all(|t| t.is_finite()));
        }
    }
}

#[test]
fn a_huge_clock_offset_is_refused_without_an_overflow() {
    // Found by `campaign_parser_survives_value_replacement`: a clock offset
    // of 1e300 s asked for a prologue of usize::MAX steps, whose sum with
    // the record's overflowed while the step was chosen.
    let dir = setup();
    for offset in [
        serde_json::json!(1e300),
        serde_json::json!({"min": 0.0, "max": 1e300}),
        serde_json::json!({"min": 0.0, "max": 1e300, "init": 1e300}),
    ] {
        let mut v = example();
        v["experiments"][0]["offset"] = offset;
        let _ = Campaign::from_str(&v.to_string(), dir.path(), "fuzz.json");
    }
}
