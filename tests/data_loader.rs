//! The measured-data loader: headers, comments, separators, index columns,
//! unit scales, resampling with a warning, and line numbers in errors.

use std::path::Path;

use rigfit::base::data::{Column, CsvSpec, DataError, parse_csv};

fn parse(text: &str, spec: &CsvSpec) -> Result<rigfit::base::data::Series, DataError> {
    parse_csv(text, Path::new("rec.csv"), spec)
}

fn by_name(t: &str, f: &str) -> CsvSpec {
    CsvSpec {
        time: Column::Name(t.into()),
        force: Column::Name(f.into()),
        ..CsvSpec::default()
    }
}

#[test]
fn header_names_pick_columns_and_comments_are_skipped() {
    let text = "# synthetic AA2024\n# noise 20 N\nforce_N, t_s ,strain\n\n1.0,0.0,9\n# gap\n2.0,1e-6,9\n3.0,2e-6,9\n";
    let s = parse(text, &by_name("t_s", "force_N")).unwrap();
    assert_eq!(s.force, [1.0, 2.0, 3.0]);
    assert_eq!(s.t.len(), 3);
    assert!((s.dt - 1e-6).abs() < 1e-18);
    assert_eq!(s.warning, None);
}

#[test]
fn index_columns_work_with_and_without_header() {
    let spec = CsvSpec::default();
    let bare = parse("0.0,5\n0.001,6\n0.002,7\n", &spec).unwrap();
    assert_eq!(bare.force, [5.0, 6.0, 7.0]);
    let headed = parse("time,force\n0.0,5\n0.001,6\n", &spec).unwrap();
    assert_eq!(headed.force, [5.0, 6.0]);
    let swapped = CsvSpec {
        time: Column::Index(2),
        force: Column::Index(0),
        ..spec
    };
    // A first row with any non-numeric field is a header, even when the
    // selected columns are numeric.
    let e = parse("7,x,0\n8,x,1\n", &swapped).unwrap_err().to_string();
    assert_eq!(e, "rec.csv: expected at least 2 samples, found 1");
    let s = parse("a;b;c\n7;x;0\n8;x;1\n", &swapped).unwrap();
    assert_eq!(s.force, [7.0, 8.0]);
}

#[test]
fn semicolons_tabs_decimal_commas_and_scales() {
    let semi = parse("t;f\n0,0;1,5\n0,5;2,5\n", &CsvSpec::default()).unwrap();
    assert_eq!(semi.force, [1.5, 2.5]);
    assert_eq!(semi.dt, 0.5);
    let spec = CsvSpec {
        time_scale: 1e-3,
        force_scale: 1e3,
        ..CsvSpec::default()
    };
    let tab = parse("t_ms\tF_kN\n0\t1\n1\t2\n2\t3\n", &spec).unwrap();
    assert_eq!(tab.force, [1e3, 2e3, 3e3]);
    assert!((tab.dt - 1e-3).abs() < 1e-18);
    let quoted = parse(
        "\"t\",\"F\"\n\"0\",\"4\"\n\"1\",\"5\"\n",
        &by_name("t", "F"),
    )
    .unwrap();
    assert_eq!(quoted.force, [4.0, 5.0]);
}

#[test]
fn jittered_sampling_is_resampled_with_a_warning() {
    // Intervals alternate 1.05 and 0.95: median 1.0, jitter 5 %.
    let mut text = String::from("t,f\n");
    for k in 0..11 {
        let t = k as f64 + if k % 2 == 1 { 0.05 } else { 0.0 };
        text.push_str(&format!("{t},{}\n", 10.0 * t));
    }
    let s = parse(&text, &CsvSpec::default()).unwrap();
    let w = s.warning.expect("a warning");
    assert!(w.contains("rec.csv: sampling is not uniform"), "{w}");
    assert!(w.contains("jitter up to 5.000%"), "{w}");
    assert!(
        (s.dt - 1.0).abs() < 1e-12,
        "median interval, found {}",
        s.dt
    );
    assert_eq!(s.t.len(), 11);
    for (t, f) in s.t.iter().zip(&s.force) {
        assert!((f - 10.0 * t).abs() < 1e-9, "linear data stays linear");
    }
}

#[test]
fn tiny_jitter_is_accepted_and_the_mean_interval_used() {
    let text = "0.0,1\n1.0e-6,2\n2.0000001e-6,3\n3.0e-6,4\n";
    let s = parse(text, &CsvSpec::default()).unwrap();
    assert_eq!(s.warning, None);
    assert!((s.dt - 1e-6).abs() < 1e-15);
}

#[test]
fn errors_carry_line_numbers_counting_comments() {
    let spec = by_name("t", "f");
    let text = "# c\nt,f\n0,1\n# c\n1,x\n";
    let e = parse(text, &spec).unwrap_err().to_string();
    assert_eq!(e, "rec.csv:5: column 2 ('f'): expected a number, found 'x'");
    let e = parse("t,f\n0,1\n1,nan\n", &spec).unwrap_err().to_string();
    assert_eq!(
        e,
        "rec.csv:3: column 2 ('f'): expected a finite number, found 'nan'"
    );
    let e = parse("t,f\n0,1\n1,1\n1,2\n", &spec)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("rec.csv:4: time column 1 ('t'): expected a strictly increasing time"),
        "{e}"
    );
    let e = parse("# only\nt,f\n0,1\n", &spec).unwrap_err().to_string();
    assert_eq!(e, "rec.csv: expected at least 2 samples, found 1");
    let e = parse("", &spec).unwrap_err().to_string();
    assert_eq!(e, "rec.csv: expected at least 2 samples, found 0");
    let e = parse("# x\ntime,f\n0,1\n", &spec).unwrap_err().to_string();
    assert_eq!(
        e,
        "rec.csv:2: no column 't'; the header has 2 column(s): time, f"
    );
    let e = parse(
        "0,1\n1,2\n",
        &CsvSpec {
            force: Column::Index(4),
            ..CsvSpec::default()
        },
    );
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("rec.csv:1: no column #4")
    );
}

#[test]
fn load_csv_names_a_missing_file() {
    let e = rigfit::base::data::load_csv(Path::new("/nonexistent/rec.csv"), &CsvSpec::default());
    let e = e.unwrap_err().to_string();
    assert!(e.starts_with("/nonexistent/rec.csv: cannot read"), "{e}");
}

#[test]
fn a_byte_order_mark_is_not_part_of_the_first_column_name() {
    let text = "\u{feff}t_s,force_N\n0.0,5\n1e-6,6\n2e-6,7\n";
    let s = parse(text, &by_name("t_s", "force_N")).unwrap();
    assert_eq!(s.force, [5.0, 6.0, 7.0]);
}

#[test]
fn cr_only_line_endings_are_lines() {
    let s = parse("t,f\r0.0,5\r1e-6,6\r2e-6,7\r", &by_name("t", "f")).unwrap();
    assert_eq!(s.force, [5.0, 6.0, 7.0]);
}

#[test]
fn a_quoted_header_keeps_its_comma() {
    let text = "\"time, s\",\"force, N\"\n0.0,5\n1e-6,6\n";
    let s = parse(text, &by_name("time, s", "force, N")).unwrap();
    assert_eq!(s.force, [5.0, 6.0]);
}

#[test]
fn errors_quote_huge_or_binary_input_short_and_escaped() {
    // A gigabyte of NULs on one line stands for any unbounded input: the
    // message quotes a short, escaped prefix and the length.
    let nul_line = "\0".repeat(1 << 20);
    let text = format!("t,f\n0.0,5\n1e-6,{nul_line}\n");
    let e = parse(&text, &by_name("t", "f")).unwrap_err().to_string();
    assert!(e.len() < 400, "{} bytes", e.len());
    assert!(
        e.contains("rec.csv:3:") && e.contains("\\0") && e.contains("1048576 bytes"),
        "{e}"
    );
    // A file of one huge "column", like /proc/self/environ.
    let env: String = (0..5000).map(|i| format!("VAR{i}=secret\0")).collect();
    let e = parse(&env, &by_name("t", "f")).unwrap_err().to_string();
    assert!(e.len() < 400, "{} bytes", e.len());
    assert!(!e.contains("VAR4999"), "{e}");
    // Many columns: a dozen are listed, then how many more.
    let header: Vec<String> = (0..100).map(|i| format!("c{i}")).collect();
    let e = parse(&format!("{}\n", header.join(",")), &by_name("t", "f"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("100 column(s)") && e.contains("88 more"), "{e}");
}
