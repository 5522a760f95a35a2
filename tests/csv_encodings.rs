//! Records as spreadsheets on other systems save them: Windows-1252 (Latin-1)
//! headers, UTF-16 with a byte-order mark, decimal commas with tabs, a
//! decimal comma in a comma-separated file (refused with a hint), and an
//! encoding stated in the campaign that the bytes contradict.

use std::path::{Path, PathBuf};
use std::process::Command;

use rigfit::base::data::{Column, CsvSpec, DataError, Decimal, load_csv, parse_csv};
use rigfit::base::encoding::Encoding;
use rigfit::campaign::Campaign;
use serde_json::{Value, json};

/// The hint a decimal comma in a comma-separated file is refused with.
const HINT: &str = "the decimal mark and the separator are both ',' (a decimal comma in a \
                    comma-separated file): export with ';' as the separator, or with '.' as \
                    the decimal mark";

fn by_name(t: &str, f: &str) -> CsvSpec {
    CsvSpec {
        time: Column::Name(t.into()),
        force: Column::Name(f.into()),
        ..CsvSpec::default()
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `text` in Latin-1: every character below U+0100 as its one byte.
fn latin1(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| u8::try_from(u32::from(c)).expect("a Latin-1 character"))
        .collect()
}

fn utf16le_with_bom(text: &str) -> Vec<u8> {
    let mut bytes = vec![0xFF, 0xFE];
    bytes.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
    bytes
}

#[test]
fn a_latin_1_header_is_matched_by_the_column_key() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = latin1("Zeit [s];Weg [µm]\n0;1,5\n0,001;2,5\n0,002;3,5\n");
    assert!(std::str::from_utf8(&bytes).is_err(), "not UTF-8");
    let path = write(dir.path(), "weg.csv", &bytes);
    let s = load_csv(&path, &by_name("Zeit [s]", "Weg [µm]")).unwrap();
    assert_eq!(s.force, [1.5, 2.5, 3.5]);
    assert!((s.dt - 1e-3).abs() < 1e-15);
    // Stated as Latin-1 it reads the same.
    let stated = CsvSpec {
        encoding: Some("latin-1".parse().unwrap()),
        ..by_name("Zeit [s]", "Weg [µm]")
    };
    assert_eq!(load_csv(&path, &stated).unwrap(), s);
}

#[test]
fn utf16_with_a_byte_order_mark_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = "t [s],a [m/s²]\n0,1.25\n0.5,2.5\n1,-3\n";
    let path = write(dir.path(), "a.csv", &utf16le_with_bom(text));
    let s = load_csv(&path, &by_name("t [s]", "a [m/s²]")).unwrap();
    assert_eq!(s.force, [1.25, 2.5, -3.0]);
    assert_eq!(s.dt, 0.5);
    // Big-endian too.
    let mut be = vec![0xFE, 0xFF];
    be.extend(text.encode_utf16().flat_map(u16::to_be_bytes));
    let path = write(dir.path(), "be.csv", &be);
    assert_eq!(load_csv(&path, &by_name("t [s]", "a [m/s²]")).unwrap(), s);
}

#[test]
fn a_decimal_comma_is_read_with_tabs_and_refused_where_a_point_is_stated() {
    let file = Path::new("rec.csv");
    let headed = parse_csv(
        "Zeit\tKraft\n0,0\t1,5\n0,5\t2,5\n",
        file,
        &CsvSpec::default(),
    );
    assert_eq!(headed.unwrap().force, [1.5, 2.5]);
    // Without a header: the tab, not the comma, separates.
    let bare = parse_csv("0,0\t1,5\n0,5\t2,5\n1,0\t3,5\n", file, &CsvSpec::default()).unwrap();
    assert_eq!(bare.force, [1.5, 2.5, 3.5]);
    assert_eq!(bare.dt, 0.5);
    let point = CsvSpec {
        decimal: Some(Decimal::Point),
        ..CsvSpec::default()
    };
    let e = parse_csv("t;F\n0;1,5\n1;2,5\n", file, &point).unwrap_err();
    assert!(matches!(e, DataError::Cell { line: 2, .. }), "{e}");
    // A stated decimal comma refuses a point (it may group thousands).
    let comma = CsvSpec {
        decimal: Some(Decimal::Comma),
        ..CsvSpec::default()
    };
    let e = parse_csv("t;F\n0;1.500\n1;2,5\n", file, &comma)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rec.csv:2:") && e.contains("decimal comma"),
        "{e}"
    );
}

#[test]
fn a_decimal_comma_in_a_comma_separated_file_is_refused_with_a_hint() {
    let file = Path::new("rec.csv");
    let text = "# Excel, German\nZeit,Kraft\n0,000,12,5\n0,001,13,5\n";
    let e = parse_csv(text, file, &CsvSpec::default()).unwrap_err();
    assert!(matches!(e, DataError::DecimalComma { line: 3, .. }), "{e}");
    let e = e.to_string();
    assert!(e.starts_with("rec.csv:3: ") && e.contains(HINT), "{e}");
    assert!(e.contains("'0,000,12,5'"), "{e}");
    // Stated, the comma-separated file is refused at its first row.
    let comma = CsvSpec {
        decimal: Some(Decimal::Comma),
        ..CsvSpec::default()
    };
    let e = parse_csv("Zeit,Kraft\n0,1\n1,2\n", file, &comma).unwrap_err();
    assert!(
        e.to_string().starts_with("rec.csv:1: ") && e.to_string().contains(HINT),
        "{e}"
    );
    // Other files keep their messages.
    let e = parse_csv("t,F\n0,1\n0,2\n", file, &CsvSpec::default()).unwrap_err();
    assert!(e.to_string().contains("strictly increasing"), "{e}");
}

#[test]
fn a_stated_encoding_the_bytes_contradict_names_the_byte() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "r.csv", &latin1("t,F [µN]\n0,1\n1,2\n"));
    let spec = CsvSpec {
        encoding: Some(Encoding::Utf8),
        ..CsvSpec::default()
    };
    let e = load_csv(&path, &spec).unwrap_err();
    assert!(matches!(e, DataError::Encoding { offset: 5, .. }), "{e}");
    assert!(e.to_string().contains("byte 5: expected UTF-8"), "{e}");
    let odd = write(
        dir.path(),
        "odd.csv",
        &utf16le_with_bom("t,F\n0,1\n1,2\n")[..9],
    );
    let e = load_csv(&odd, &CsvSpec::default()).unwrap_err();
    assert!(matches!(e, DataError::Encoding { offset: 8, .. }), "{e}");
}

/// The shipped campaign with its record rewritten as a German Excel on
/// Windows saves it: Latin-1 (a header `Kraft (Meßdose) [N]`), `;`, decimal
/// commas; `data` is merged into the experiment's data.
fn german_campaign(dir: &Path, data: Value) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let csv = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_v2_synthetic.csv")).unwrap();
    let mut out = String::from("Zeit [s];Kraft (Meßdose) [N]\n");
    for line in csv.lines().filter(|l| !l.starts_with('#')).skip(1) {
        out += &line.replace(',', ";").replace('.', ",");
        out.push('\n');
    }
    write(dir, "v2.csv", &latin1(&out));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let mut d = json!({"file": "v2.csv", "time_column": "Zeit [s]",
                       "column": "Kraft (Meßdose) [N]"});
    for (k, v) in data.as_object().unwrap() {
        d[k] = v.clone();
    }
    c["experiments"][0]["data"] = d;
    let path = dir.join("c.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

/// `rigfit check --no-measure CAMPAIGN`, its cache under `dir`.
fn check(campaign: &Path, dir: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["check", "--no-measure"])
        .arg(campaign)
        .env("RIGFIT_CACHE_DIR", dir.join("cache"))
        .output()
        .unwrap()
}

#[test]
fn a_campaign_reads_a_latin_1_record_with_decimal_commas_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let path = german_campaign(
        dir.path(),
        json!({"decimal": ",", "encoding": "Windows-1252"}),
    );
    let out = check(&path, dir.path());
    let said = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    // The same samples as the shipped UTF-8 record.
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let shipped = Campaign::load(&repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let german = Campaign::load(&german_campaign(dir.path(), json!({}))).unwrap();
    let (a, b) = (
        &shipped.problem.experiments[0],
        &german.problem.experiments[0],
    );
    assert!(!a.measured.is_empty());
    assert_eq!(a.measured, b.measured);
}

#[test]
fn a_campaign_refuses_an_unknown_or_contradicted_encoding_by_its_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = german_campaign(dir.path(), json!({"encoding": "ebcdic"}));
    let out = check(&path, dir.path());
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("experiments[0].data.encoding"), "{e}");
    assert!(e.contains("latin-1") && e.contains("'ebcdic'"), "{e}");
    let path = german_campaign(dir.path(), json!({"encoding": "utf-8"}));
    let e = Campaign::load(&path).unwrap_err().to_string();
    assert!(
        e.contains("experiments[0].data") && e.contains("byte 18"),
        "{e}"
    );
    let path = german_campaign(dir.path(), json!({"decimal": ";"}));
    let e = Campaign::load(&path).unwrap_err().to_string();
    assert!(e.contains("experiments[0].data.decimal"), "{e}");
}

#[test]
fn the_identify_tools_read_latin_1_and_utf16_records() {
    use rigfit::identify::columns::Table;
    let dir = tempfile::tempdir().unwrap();
    let text = "t [s],Weg [µm],a [m/s²]\n0,1,2\n1,3,4\n";
    for (name, bytes) in [
        ("latin1.csv", latin1(text)),
        ("utf16.csv", utf16le_with_bom(text)),
    ] {
        let table = Table::read(&write(dir.path(), name, &bytes)).unwrap();
        assert_eq!(table.header, ["t [s]", "Weg [µm]", "a [m/s²]"], "{name}");
        assert_eq!(table.column("Weg [µm]").unwrap(), [1.0, 3.0], "{name}");
    }
}
