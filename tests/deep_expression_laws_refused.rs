//! Expression laws too deep or too long for the parser's limits are refused
//! with the rig file, the JSON path and the limit, rather than overflowing the
//! stack; the largest laws inside the limits compile, evaluate and drop on an
//! ordinary test thread.

use rigfit::compile::front::expr::{MAX_CHARS, MAX_DEPTH};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::{RigSource, parse};
use serde_json::{Value, json};

fn duffing_with_spring(force: &str) -> Value {
    let text = rigfit::rig::SHIPPED
        .iter()
        .find(|(i, _)| *i == "duffing_base")
        .unwrap()
        .1;
    let mut v: Value = serde_json::from_str(text).unwrap();
    v["elements"][0]["spring"] = json!({"law": "expression", "force": force});
    v
}

fn compile(force: &str) -> Result<CompiledRig, String> {
    let src = RigSource::File("deep_rig.json".into());
    let desc = parse(&duffing_with_spring(force).to_string(), &src).map_err(|e| e.to_string())?;
    CompiledRig::new(desc, &src.label()).map_err(|e| e.to_string())
}

#[test]
fn hostile_laws_are_refused_with_file_path_and_limit() {
    let cases: Vec<(&str, String, String)> = vec![
        (
            "10 000 nested parentheses",
            format!("{}x{}", "(".repeat(10_000), ")".repeat(10_000)),
            format!("at most {MAX_CHARS} characters"),
        ),
        (
            "40 000 unary minuses",
            format!("{}x", "-".repeat(40_000)),
            format!("at most {MAX_CHARS} characters"),
        ),
        (
            "a 20 000-long power chain",
            format!("x{}", "^x".repeat(20_000)),
            format!("at most {MAX_CHARS} characters"),
        ),
        (
            "a flat sum of 100 000 terms",
            format!("k*x{}", "+x".repeat(100_000)),
            format!("at most {MAX_CHARS} characters"),
        ),
        (
            "parentheses one level too deep, inside the length limit",
            format!("{}x{}", "(".repeat(MAX_DEPTH), ")".repeat(MAX_DEPTH)),
            format!("nested deeper than {MAX_DEPTH} levels"),
        ),
        (
            "unary minuses one level too deep",
            format!("{}x", "-".repeat(MAX_DEPTH + 1)),
            format!("nested deeper than {MAX_DEPTH} levels"),
        ),
        (
            "a power chain one level too deep",
            format!("x{}", "^x".repeat(MAX_DEPTH + 1)),
            format!("nested deeper than {MAX_DEPTH} levels"),
        ),
        (
            "calls nested one level too deep",
            format!("{}x{}", "abs(".repeat(MAX_DEPTH), ")".repeat(MAX_DEPTH)),
            format!("nested deeper than {MAX_DEPTH} levels"),
        ),
    ];
    for (what, force, limit) in cases {
        let Err(e) = compile(&force) else {
            panic!("{what}: accepted");
        };
        println!("{what}: {e}");
        assert!(
            e.starts_with("deep_rig.json: elements[0].spring.force: expected a formula"),
            "{what}: {e}"
        );
        assert!(e.contains(&limit), "{what}: {e}");
        assert!(
            e.len() < 600,
            "{what}: the message quotes the law briefly: {e}"
        );
    }
}

#[test]
fn the_largest_laws_inside_the_limits_compile_on_a_test_thread() {
    // A flat sum as long as allowed: a tree as deep as the law is long.
    let mut sum = String::from("k*x");
    while sum.len() + 2 <= MAX_CHARS {
        sum += "+x";
    }
    // Nesting as deep as allowed, around a product chain.
    let mut nested = "x*".repeat(200) + "x";
    for _ in 0..MAX_DEPTH - 1 {
        nested = format!("({nested})");
    }
    let power = format!("x{}", "^x".repeat(MAX_DEPTH - 1));
    for force in [sum, nested, power] {
        assert!(force.chars().count() <= MAX_CHARS);
        let rig = compile(&force).unwrap_or_else(|e| panic!("{e}"));
        drop(rig);
        let e = rigfit::compile::front::expr::parse(&force).unwrap();
        assert!(e.eval(&|_| 0.5).is_finite());
    }
}

#[test]
fn check_refuses_a_deep_law_with_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let force = format!("k*x + {}x{}", "(".repeat(10_000), ")".repeat(10_000));
    std::fs::write(
        dir.join("deep_rig.json"),
        duffing_with_spring(&force).to_string(),
    )
    .unwrap();
    let c = json!({
        "name": "deep", "rig": "deep_rig.json",
        "params": {"m": 1.0, "k": 1e3, "k3": 0.0, "c": 1.0},
        "experiments": [{"name": "e", "data": {"file": "d.csv", "time_column": "t_s", "force_column": "f_N"}}]
    });
    std::fs::write(dir.join("c.json"), c.to_string()).unwrap();
    std::fs::write(dir.join("d.csv"), "t_s,f_N\n0,0\n0.01,1\n0.02,2\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["check", "c.json"])
        .current_dir(dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    println!("{err}");
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("deep_rig.json"), "{err}");
    assert!(err.contains("elements[0].spring.force"), "{err}");
    assert!(err.contains("at most 2000 characters"), "{err}");
}
