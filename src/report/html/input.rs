//! Reading a result folder for the report: result.json into structs of the
//! report's own (every key optional, so that older and newer files read), the
//! experiments' CSVs and history.csv. Errors name the file, the line or JSON
//! path, and what was expected.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::ReportError;

/// result.json as the report reads it.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct ResultFile {
    /// rigfit version that wrote the file.
    pub rigfit_version: String,
    /// The one-line verdict and its flags.
    pub verdict: Option<Verdict>,
    /// Campaign name.
    pub campaign: String,
    /// Campaign file.
    pub campaign_file: String,
    /// Rig id.
    pub rig: String,
    /// Search seed.
    pub seed: Option<u64>,
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Device description.
    pub device: String,
    /// `"f32"` or `"f64"`.
    pub precision: String,
    /// Generations run.
    pub generations: Option<u64>,
    /// Candidate evaluations.
    pub evaluations: Option<u64>,
    /// The search's wall time (s).
    pub wall_time_s: Option<f64>,
    /// The search's and the polish's wall time (s).
    pub job_wall_time_s: Option<f64>,
    /// Why the search stopped.
    pub stop_reason: String,
    /// The search method (absent: the genetic algorithm).
    pub search_method: Option<String>,
    /// Best joint fitness.
    pub fitness: Option<f64>,
    /// The polish.
    pub polish: Option<Polish>,
    /// Per experiment.
    pub experiments: Vec<Experiment>,
    /// Every parameter.
    pub parameters: Vec<Parameter>,
    /// Warnings in words.
    pub warnings: Vec<String>,
    /// The data files read, with their SHA-256.
    pub inputs: Vec<InputFile>,
    /// The rig's natural frequencies at the fitted values.
    pub natural_frequencies_hz: Vec<NaturalFrequencies>,
    /// Profile likelihoods, where computed.
    pub profiles: Option<Profiles>,
    /// Validation records, where given.
    pub validation: Option<Validation>,
}

/// The verdict.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Verdict {
    /// The line.
    pub line: String,
    /// Cost over the noise floor.
    pub cost_over_noise_floor: Option<f64>,
    /// What is flagged, in words.
    pub flags: Vec<String>,
}

/// One polish start: cost before and after.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Start {
    /// Before.
    pub initial: Option<f64>,
    /// After.
    pub polished: Option<f64>,
}

/// The polish.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Polish {
    /// Why it stopped.
    pub stop: Option<String>,
    /// Iterations.
    pub iterations: Option<u64>,
    /// Evaluations.
    pub evaluations: Option<u64>,
    /// Wall time (s).
    pub wall_time_s: Option<f64>,
    /// The search's best cost before the polish.
    pub ga_fitness: Option<f64>,
    /// The start that won.
    pub best_start: Option<usize>,
    /// The starts.
    pub starts: Vec<Start>,
    /// Free parameters in the correlation's order.
    pub genes: Vec<String>,
    /// Correlation matrix (`null` where undetermined).
    pub correlation: Vec<Vec<Option<f64>>>,
}

/// One experiment's fit.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Experiment {
    /// Name.
    pub name: String,
    /// R².
    pub r2: Option<f64>,
    /// 1 − R².
    pub one_minus_r2: Option<f64>,
    /// Residual RMS.
    pub residual_rms: Option<f64>,
    /// Measured output's unit.
    pub unit: String,
    /// Noise estimate.
    pub noise_estimate: Option<f64>,
    /// Cost over the noise floor.
    pub cost_over_noise_floor: Option<f64>,
    /// The CSV's file name.
    pub csv: String,
}

/// One parameter.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Parameter {
    /// Name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Value.
    pub value: Option<f64>,
    /// Whether fitted.
    pub free: bool,
    /// `"log"` for a log-scale gene.
    pub scale: Option<String>,
    /// Bounds.
    pub bounds: Option<[Option<f64>; 2]>,
    /// Elite width relative to the value.
    pub elite_relative_width: Option<f64>,
    /// Standard error.
    pub std_error: Option<f64>,
    /// 95 % interval from the covariance (`null` on an open side).
    pub interval_95: Option<[Option<f64>; 2]>,
    /// Whether determined.
    pub determined: Option<bool>,
    /// `"lower"` or `"upper"`.
    pub at_bound: Option<String>,
    /// Why not determined.
    pub uncertainty_note: Option<String>,
}

/// One data file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct InputFile {
    /// As the campaign names it.
    pub path: String,
    /// SHA-256, hex.
    pub sha256: String,
}

/// Natural frequencies of one experiment's linearised rig.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct NaturalFrequencies {
    /// Experiment name.
    pub experiment: String,
    /// Frequencies (Hz), lowest first.
    pub hz: Vec<f64>,
}

/// Profile likelihoods.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Profiles {
    /// One per profiled parameter.
    pub parameters: Vec<Profile>,
}

/// One parameter's profile.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Profile {
    /// Parameter name.
    pub name: String,
    /// Values the profile was computed at.
    pub grid: Vec<Option<f64>>,
    /// Cost at each (`null` where it failed).
    pub cost: Vec<Option<f64>>,
    /// `Δχ²` at each (`null` where it failed); what `threshold` bounds
    /// where given.
    pub delta_chi2: Vec<Option<f64>>,
    /// The parameter's unit.
    pub unit: String,
    /// The fitted value.
    pub value: Option<f64>,
    /// The cost threshold of the 95 % interval.
    pub threshold: Option<f64>,
    /// The best cost.
    pub best_cost: Option<f64>,
    /// The interval.
    pub interval: Option<[Option<f64>; 2]>,
    /// A flag in words.
    pub flag: Option<String>,
}

/// Validation records.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct Validation {
    /// One per validation record.
    pub experiments: Vec<ValidationRecord>,
}

/// One validation record's numbers.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default)]
pub struct ValidationRecord {
    /// Name.
    pub name: String,
    /// R².
    pub r2: Option<f64>,
    /// 1 − R².
    pub one_minus_r2: Option<f64>,
    /// Residual RMS.
    pub residual_rms: Option<f64>,
    /// Noise estimate.
    pub noise_estimate: Option<f64>,
    /// Cost over the noise floor.
    pub cost_over_noise_floor: Option<f64>,
    /// Its CSV.
    pub csv: String,
}

/// One column of an experiment CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// `measured`, `model` or `residual`.
    pub kind: &'static str,
    /// Output name (`load_cell_force`).
    pub name: String,
    /// Unit (`N`).
    pub unit: String,
    /// Values.
    pub values: Vec<f64>,
}

/// An experiment CSV as the job writes it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FitCsv {
    /// Record time (s).
    pub t: Vec<f64>,
    /// Measured, model and residual columns, in the file's order.
    pub columns: Vec<Column>,
    /// Whether each sample is scored.
    pub in_fit_window: Vec<bool>,
}

impl FitCsv {
    /// The measured column and each one's name.
    pub fn of_kind(&self, kind: &str) -> impl Iterator<Item = &Column> {
        self.columns.iter().filter(move |c| c.kind == kind)
    }
}

/// history.csv: cost by generation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    /// Generation.
    pub generation: Vec<f64>,
    /// Best cost.
    pub best: Vec<f64>,
    /// Median cost.
    pub median: Vec<f64>,
}

/// Reads `dir/result.json`; `None` when there is none (a folder of CSVs).
pub fn read_result(dir: &Path) -> Result<Option<ResultFile>, ReportError> {
    let file = dir.join("result.json");
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(ReportError::Io { file, source: e }),
    };
    let de = &mut serde_json::Deserializer::from_str(&text);
    serde_path_to_error::deserialize(de)
        .map(Some)
        .map_err(|e| ReportError::Json {
            file,
            path: e.path().to_string(),
            message: e.inner().to_string(),
        })
}

/// Reads one experiment CSV (`t_record_s,t_model_s,measured_*,model_*…,
/// residual_*,in_fit_window`).
pub fn read_fit_csv(file: &Path) -> Result<FitCsv, ReportError> {
    let text = std::fs::read_to_string(file).map_err(|source| ReportError::Io {
        file: file.to_path_buf(),
        source,
    })?;
    parse_fit_csv(&text, file)
}

fn bad(file: &Path, line: usize, expected: impl Into<String>) -> ReportError {
    ReportError::Csv {
        file: file.to_path_buf(),
        line,
        expected: expected.into(),
    }
}

/// `measured_load_cell_force_N` → (`load_cell_force`, `N`): the unit is
/// after the last `_` (units hold none).
fn name_unit(rest: &str) -> (String, String) {
    match rest.rsplit_once('_') {
        Some((n, u)) => (n.to_string(), u.to_string()),
        None => (String::new(), rest.to_string()),
    }
}

/// [`read_fit_csv`] of text already read.
pub fn parse_fit_csv(text: &str, file: &Path) -> Result<FitCsv, ReportError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(bad(file, 1, "a header line"));
    };
    let heads: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut time = None;
    let mut window = None;
    let mut columns = Vec::new();
    let mut at = Vec::new();
    for (i, h) in heads.iter().enumerate() {
        let column = |kind, rest: &str| {
            let (name, unit) = name_unit(rest);
            Column {
                kind,
                name,
                unit,
                values: Vec::new(),
            }
        };
        if *h == "t_record_s" || (time.is_none() && (*h == "t_s" || *h == "t_model_s")) {
            time = Some(i);
        } else if *h == "in_fit_window" {
            window = Some(i);
        } else if let Some(r) = h.strip_prefix("measured_") {
            columns.push(column("measured", r));
            at.push(i);
        } else if let Some(r) = h.strip_prefix("model_") {
            columns.push(column("model", r));
            at.push(i);
        } else if let Some(u) = h.strip_prefix("residual_") {
            let mut c = column("residual", "");
            c.unit = u.to_string();
            columns.push(c);
            at.push(i);
        }
    }
    let Some(time) = time else {
        return Err(bad(file, 1, "a time column t_record_s in the header"));
    };
    if !columns.iter().any(|c| c.kind == "measured") {
        return Err(bad(
            file,
            1,
            "a measured_<output>_<unit> column in the header",
        ));
    }
    let mut csv = FitCsv::default();
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != heads.len() {
            return Err(bad(
                file,
                n + 1,
                format!(
                    "{} cells as in the header, found {}",
                    heads.len(),
                    cells.len()
                ),
            ));
        }
        let number = |i: usize| -> Result<f64, ReportError> {
            let s = cells[i].trim();
            s.parse::<f64>().map_err(|_| {
                bad(
                    file,
                    n + 1,
                    format!("a number in column {:?}, found {s:?}", heads[i]),
                )
            })
        };
        csv.t.push(number(time)?);
        for (c, &i) in columns.iter_mut().zip(&at) {
            c.values.push(number(i)?);
        }
        csv.in_fit_window
            .push(window.is_none_or(|w| cells[w].trim() != "0"));
    }
    csv.columns = columns;
    Ok(csv)
}

/// Reads history.csv (`generation,best_cost,…,median_cost,…`); `None`
/// when absent.
pub fn read_history(dir: &Path) -> Result<Option<History>, ReportError> {
    let file = dir.join("history.csv");
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(ReportError::Io { file, source }),
    };
    let mut lines = text.lines().enumerate();
    let Some((_, header)) = lines.next() else {
        return Ok(Some(History::default()));
    };
    let heads: Vec<&str> = header.split(',').collect();
    let find = |name: &str| {
        heads
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| bad(&file, 1, format!("a {name} column in the header")))
    };
    let (g, b, m) = (
        find("generation")?,
        find("best_cost")?,
        find("median_cost")?,
    );
    let mut h = History::default();
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        let number = |i: usize| -> Result<f64, ReportError> {
            let s = cells.get(i).map_or("", |s| s.trim());
            s.parse::<f64>().map_err(|_| {
                bad(
                    &file,
                    n + 1,
                    format!("a number in column {:?}, found {s:?}", heads[i]),
                )
            })
        };
        h.generation.push(number(g)?);
        h.best.push(number(b)?);
        h.median.push(number(m)?);
    }
    Ok(Some(h))
}

/// The CSVs of a folder without result.json, by name: every `*.csv` but
/// history.csv whose header has a measured column.
pub fn csv_files(dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    let entries = std::fs::read_dir(dir).map_err(|source| ReportError::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().is_some_and(|x| x == "csv")
                && p.file_name().is_some_and(|n| n != "history.csv")
        })
        .collect();
    files.sort();
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fit_csv_reads_by_its_header_and_a_bad_cell_names_its_line() {
        let text = "t_record_s,t_model_s,measured_f_N,model_f_N,model_g_N,residual_N,in_fit_window\n\
                    0,0,1,2,3,1,0\n1e-3,1e-3,2,2,4,0,1\n";
        let csv = parse_fit_csv(text, Path::new("a.csv")).unwrap();
        assert_eq!(csv.t, [0.0, 1e-3]);
        assert_eq!(csv.in_fit_window, [false, true]);
        let model: Vec<&str> = csv.of_kind("model").map(|c| c.name.as_str()).collect();
        assert_eq!(model, ["f", "g"]);
        assert_eq!(csv.columns[0].unit, "N");
        let bad = parse_fit_csv(&text.replace("1e-3,2,2", "1e-3,x,2"), Path::new("a.csv"));
        let message = bad.unwrap_err().to_string();
        assert!(
            message.contains("a.csv") && message.contains("line 3"),
            "{message}"
        );
    }

    #[test]
    fn result_json_tolerates_missing_keys_and_names_a_wrong_one() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("result.json"), r#"{"rig":"x"}"#).unwrap();
        let r = read_result(dir.path()).unwrap().unwrap();
        assert_eq!(r.rig, "x");
        assert!(r.profiles.is_none());
        std::fs::write(
            dir.path().join("result.json"),
            r#"{"parameters":[{"name":"k","value":"no"}]}"#,
        )
        .unwrap();
        let message = read_result(dir.path()).unwrap_err().to_string();
        assert!(message.contains("parameters[0].value"), "{message}");
    }
}
