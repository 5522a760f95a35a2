//! report.html: a job writes one self-contained page; `rigfit report`
//! rebuilds the same bytes from the folder's files, never over a file rigfit
//! did not write; a record of 2 million samples gives a page of a few MB.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;
use sha2::Digest as _;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A short CPU job on the shipped tensile campaign.
fn job(out: &Path) -> Output {
    let o = rigfit()
        .arg("run")
        .arg(repo().join("campaigns/aa2024_t3_synthetic.json"))
        .arg("--out")
        .arg(out)
        .args(["--population", "48", "--generations", "3", "--seed", "5"])
        .args(["--backend", "cpu"])
        .output()
        .unwrap();
    assert!(o.status.success(), "rigfit run failed: {}", stderr(&o));
    o
}

/// The page's embedded figure data.
fn embedded(html: &str) -> Value {
    let open = r#"<script type="application/json" id="rigfit-data">"#;
    let start = html.find(open).expect("embedded data") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).expect("embedded JSON parses")
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

#[test]
fn a_job_writes_a_self_contained_report_that_rigfit_report_reproduces() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("result");
    let o = job(&out);
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        said.contains("report.html"),
        "the summary names report.html: {said}"
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    for banned in ["http://", "https://", "src=", "<link", "@import"] {
        assert!(!page.contains(banned), "the page holds {banned:?}");
    }
    for id in [
        "verdict",
        "summary",
        "parameters",
        "profiles",
        "validation",
        "correlation",
        "convergence",
    ] {
        assert!(page.contains(&format!("id=\"{id}\"")), "no #{id}");
    }
    assert!(page.contains("class=\"experiment\""));
    assert!(page.contains("data-zoom=\"in\"") && page.contains("data-zoom=\"reset\""));
    assert!(page.contains("data-t0=\"") && page.contains("data-t1=\""));

    // The parameter table: one row per free parameter, at result.json's value.
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let table_start = page.find("<table id=\"parameters\"").unwrap();
    let table = &page[table_start..table_start + page[table_start..].find("</table>").unwrap()];
    let body = &table[table.find("<tbody>").unwrap()..];
    let free: Vec<&Value> = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["free"] == true)
        .collect();
    assert!(!free.is_empty());
    assert_eq!(body.matches("<tr>").count(), free.len());
    for p in &free {
        let name = p["name"].as_str().unwrap();
        let value = p["value"].as_f64().unwrap();
        let row = body
            .split("<tr>")
            .find(|row| row.contains(&format!(">{name}</th>")))
            .expect(name);
        let at = row.find("data-value=\"").unwrap() + 12;
        let shown: f64 = row[at..at + row[at..].find('"').unwrap()].parse().unwrap();
        assert_eq!(shown, value, "{name}");
    }

    // The figure data: every series of the fit within the drawing limit.
    let data = embedded(&page);
    let exp = &data["experiments"][0];
    assert!(exp["fit"].as_array().unwrap().len() >= 2);
    assert!(!exp["spectrum"]["x"].as_array().unwrap().is_empty());
    let generations = std::fs::read_to_string(out.join("history.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert!(generations >= 3);
    assert_eq!(
        data["convergence"]["best"].as_array().unwrap().len(),
        generations
    );

    // result.json's inputs and natural frequencies.
    let inputs = r["inputs"].as_array().unwrap();
    let record = inputs
        .iter()
        .find(|i| i["path"] == "aa2024_t3_v2_synthetic.csv")
        .expect("the record in inputs");
    let bytes = std::fs::read(repo().join("campaigns/aa2024_t3_v2_synthetic.csv")).unwrap();
    assert_eq!(
        record["sha256"].as_str().unwrap(),
        hex(&sha2::Sha256::digest(&bytes))
    );
    assert!(page.contains(record["sha256"].as_str().unwrap()));
    let hz = r["natural_frequencies_hz"][0]["hz"].as_array().unwrap();
    assert!(!hz.is_empty() && hz.iter().all(|f| f.as_f64().unwrap() >= 0.0));
    assert_eq!(exp["modes"].as_array().unwrap().len(), hz.len());

    // `rigfit report` gives the same bytes, to the folder and elsewhere.
    let elsewhere = dir.path().join("copy.html");
    let o = rigfit()
        .arg("report")
        .arg(&out)
        .arg("--out")
        .arg(&elsewhere)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&elsewhere).unwrap(), page);
    let o = rigfit().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(out.join("report.html")).unwrap(),
        page
    );
    // And replaces its own page when asked again.
    let o = rigfit()
        .arg("report")
        .arg(&out)
        .arg("--out")
        .arg(&elsewhere)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn rigfit_report_refuses_a_foreign_file_and_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("csvs");
    std::fs::create_dir(&folder).unwrap();
    write_record(&folder.join("e1.csv"), 2_000, 1e-3);
    let foreign = dir.path().join("notes.html");
    std::fs::write(&foreign, "my notes").unwrap();
    let o = rigfit()
        .arg("report")
        .arg(&folder)
        .arg("--out")
        .arg(&foreign)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("notes.html"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&foreign).unwrap(), "my notes");
    #[cfg(unix)]
    {
        let link = dir.path().join("link.html");
        std::os::unix::fs::symlink(&foreign, &link).unwrap();
        let o = rigfit()
            .arg("report")
            .arg(&folder)
            .arg("--out")
            .arg(&link)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert_eq!(std::fs::read_to_string(&foreign).unwrap(), "my notes");
    }
    // A folder without result.json: the CSV alone makes the page.
    let o = rigfit().arg("report").arg(&folder).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.contains("id=\"verdict\"") && page.contains("class=\"experiment\""));
    // An empty folder is refused, naming it.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = rigfit().arg("report").arg(&empty).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("empty"), "{}", stderr(&o));
}

/// A fit CSV of `n` samples: a decaying 40 Hz ring, the model a little off,
/// the first tenth outside the fit window.
fn write_record(path: &Path, n: usize, dt: f64) {
    let mut s = String::with_capacity(n * 64);
    s.push_str("t_record_s,t_model_s,measured_force_N,model_force_N,model_specimen_force_N,residual_N,in_fit_window\n");
    for k in 0..n {
        let t = k as f64 * dt;
        let model = 100.0 * (-t).exp() * (2.0 * std::f64::consts::PI * 40.0 * t).sin();
        let measured = model + 0.5 * (k as f64 * 1.618).sin();
        let _ = writeln!(
            s,
            "{t:.9e},{t:.9e},{measured:.6e},{model:.6e},{:.6e},{:.6e},{}",
            0.5 * model,
            model - measured,
            u8::from(k >= n / 10)
        );
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn a_two_million_sample_record_gives_a_page_under_5_mb() {
    let dir = tempfile::tempdir().unwrap();
    write_record(&dir.path().join("long.csv"), 2_000_000, 1e-6);
    std::fs::write(
        dir.path().join("result.json"),
        r#"{"campaign":"long","experiments":[{"name":"long","csv":"long.csv","unit":"N"}],
            "natural_frequencies_hz":[{"experiment":"long","hz":[40.0,9000.0]}]}"#,
    )
    .unwrap();
    let page = rigfit::report::html::build_report(dir.path()).unwrap();
    assert!(page.len() < 5 << 20, "{} bytes", page.len());
    let data = embedded(&page);
    let fit = data["experiments"][0]["fit"].as_array().unwrap();
    assert_eq!(
        fit.len(),
        3,
        "measured and model force, and the specimen force"
    );
    for s in fit {
        let n = s["x"].as_array().unwrap().len();
        assert!(n <= 4000 && n > 1000, "{n} points drawn");
    }
    // The table's samples count is the full record's.
    assert!(
        page.contains(">2000000<"),
        "the samples column counts every row"
    );
}

#[test]
fn simulate_writes_the_page_of_the_model_against_the_record() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = repo().join("campaigns/aa2024_t3_synthetic.json");
    let page = dir.path().join("sim.html");
    let o = rigfit()
        .arg("simulate")
        .arg(&campaign)
        .arg("--out")
        .arg(dir.path().join("sim.csv"))
        .arg("--report")
        .arg(&page)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let html = std::fs::read_to_string(&page).unwrap();
    for banned in ["http://", "https://", "src=", "<link", "@import"] {
        assert!(!html.contains(banned), "the page holds {banned:?}");
    }
    let data = embedded(&html);
    let exp = &data["experiments"][0];
    assert_eq!(exp["fit"][0]["role"], "measured");
    assert!(!exp["modes"].as_array().unwrap().is_empty());
    assert!(!exp["residual"]["y"].as_array().unwrap().is_empty());
    // Against a synthetic record of its own there is nothing measured.
    let o = rigfit()
        .arg("simulate")
        .arg(&campaign)
        .arg("--out")
        .arg(dir.path().join("noisy.csv"))
        .args(["--noise", "20"])
        .arg("--report")
        .arg(dir.path().join("noisy.html"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!dir.path().join("noisy.html").exists());
}
