//! Preparing a series: its folder, each test's campaign as a file of its
//! own, and the manifest.
//!
//! A test's campaign is the series' campaign with the test's record, seed
//! and parameter changes written in, its paths made absolute and its
//! `"output"` its job folder: `rigfit run` on that file runs the very job
//! the series runs, to the same bits.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde_json::{Map, Value, json};

use super::SeriesError;
use super::file::{SeriesFile, SeriesSource};
use super::manifest::{
    CAMPAIGNS_DIR, GENERATOR, MANIFEST_FILE, Manifest, STATUS_DIR, TESTS_DIR, TestEntry,
};
use super::table::{Overrides, TestRow};
use crate::campaign::Campaign;

/// How every test campaign's description begins: a file in `campaigns/`
/// without it is not rigfit's, and is never replaced.
const DESCRIPTION_MARK: &str = "rigfit series: test";

/// Prepares `series` in the folder `root`: created where missing; a folder
/// the same series was prepared in is prepared again in place (the tests
/// already done keep their results unless their campaign changed). Refuses
/// a folder that holds anything else. Returns the manifest, written.
pub fn prepare(series: &SeriesFile, root: &Path) -> Result<Manifest, SeriesError> {
    check_root(series, root)?;
    for sub in [CAMPAIGNS_DIR, TESTS_DIR, STATUS_DIR] {
        let dir = root.join(sub);
        std::fs::create_dir_all(&dir).map_err(|e| SeriesError::io(&dir, e))?;
    }
    let drafts = drafts(series)?;
    let tests: Vec<TestEntry> = drafts
        .into_par_iter()
        .map(|d| write_test(root, d))
        .collect::<Result<_, _>>()?;
    let covariates = match &series.source {
        SeriesSource::Table { covariates, .. } => covariates.clone(),
        SeriesSource::Campaigns(_) => Vec::new(),
    };
    let manifest = Manifest {
        generator: GENERATOR.into(),
        name: series.name.clone(),
        series_file: series.path.clone(),
        covariates,
        tasks: (0..tests.len()).map(|i| vec![i]).collect(),
        tests,
    };
    manifest.write(root)?;
    Ok(manifest)
}

/// The folder may be missing, empty, or a series prepared from the same
/// file.
fn check_root(series: &SeriesFile, root: &Path) -> Result<(), SeriesError> {
    let folder = |reason: String| SeriesError::Folder {
        path: root.to_path_buf(),
        reason,
    };
    if let Ok(meta) = std::fs::symlink_metadata(root) {
        if !meta.is_dir() {
            return Err(folder("it exists and is not a folder".into()));
        }
    } else {
        return std::fs::create_dir_all(root).map_err(|e| folder(format!("cannot create it: {e}")));
    }
    if root.join(MANIFEST_FILE).exists() {
        let manifest = Manifest::read(root)?;
        if manifest.series_file != series.path {
            return Err(folder(format!(
                "it holds the series \"{}\" prepared from `{}`; choose another folder (--out)",
                manifest.name,
                manifest.series_file.display()
            )));
        }
        return Ok(());
    }
    let mut entries = std::fs::read_dir(root).map_err(|e| SeriesError::io(root, e))?;
    if entries.next().is_some() {
        return Err(folder(
            "it holds files but no series.json: not a series' folder; rigfit writes a series \
             only into a new or empty folder, or one it prepared"
                .into(),
        ));
    }
    Ok(())
}

/// A test before its campaign is written.
struct Draft {
    id: String,
    source: String,
    covariates: Vec<String>,
    seed: u64,
    campaign: Value,
    error: Option<String>,
}

/// Each test's campaign, in memory.
fn drafts(series: &SeriesFile) -> Result<Vec<Draft>, SeriesError> {
    match &series.source {
        SeriesSource::Table {
            campaign,
            table,
            rows,
            ..
        } => {
            let base = read_campaign(campaign)?;
            let table_name = table
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            rows.iter()
                .enumerate()
                .map(|(i, row)| {
                    let mut c = base.clone();
                    merge_search(&mut c, &series.search);
                    let seed = row
                        .seed
                        .unwrap_or_else(|| campaign_seed(&c).wrapping_add(i as u64));
                    let place = |reason: String| {
                        SeriesError::input(table, format!("line {}", row.line), reason)
                    };
                    let error = set_records(&mut c, row).map_err(place)?;
                    apply_overrides(&mut c, &row.overrides).map_err(place)?;
                    Ok(Draft {
                        id: row.id.clone(),
                        source: format!("{table_name} line {}", row.line),
                        covariates: row.covariates.clone(),
                        seed,
                        campaign: c,
                        error,
                    })
                })
                .collect()
        }
        SeriesSource::Campaigns(files) => {
            let mut drafts: Vec<Draft> = Vec::new();
            for file in files {
                let id = file
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                super::file::check_name(&id).map_err(|r| {
                    SeriesError::input(
                        &series.path,
                        "campaigns",
                        format!("`{}`: its name makes the test's name: {r}", file.display()),
                    )
                })?;
                if let Some(other) = drafts.iter().find(|d| d.id == id) {
                    return Err(SeriesError::input(
                        &series.path,
                        "campaigns",
                        format!(
                            "`{}` and {} make the same test name \"{id}\"; rename one",
                            file.display(),
                            other.source
                        ),
                    ));
                }
                let mut c = read_campaign(file)?;
                merge_search(&mut c, &series.search);
                let seed = campaign_seed(&c);
                drafts.push(Draft {
                    id,
                    source: format!("`{}`", file.display()),
                    covariates: Vec::new(),
                    seed,
                    campaign: c,
                    error: None,
                });
            }
            Ok(drafts)
        }
    }
}

/// A campaign file as JSON, its relative paths made absolute.
fn read_campaign(path: &Path) -> Result<Value, SeriesError> {
    let text = crate::base::fsutil::read_description(path).map_err(|e| SeriesError::io(path, e))?;
    let mut v: Value = serde_json::from_str(&text)
        .map_err(|e| SeriesError::input(path, format!("line {}", e.line()), e.to_string()))?;
    if !v.is_object() {
        return Err(SeriesError::input(
            path,
            "(file)",
            "expected a campaign: a JSON object",
        ));
    }
    let dir = path.parent().unwrap_or(Path::new("/"));
    if let Some(rig) = v.get("rig").and_then(Value::as_str)
        && dir.join(rig).is_file()
    {
        v["rig"] = json!(dir.join(rig));
    }
    for list in ["experiments", "validation"] {
        if let Some(exps) = v.get_mut(list).and_then(Value::as_array_mut) {
            for e in exps {
                if let Some(file) = e.pointer_mut("/data/file")
                    && let Some(s) = file.as_str()
                {
                    *file = json!(dir.join(s));
                }
            }
        }
    }
    Ok(v)
}

fn campaign_seed(c: &Value) -> u64 {
    c.pointer("/search/seed")
        .and_then(Value::as_u64)
        .unwrap_or(0)
}

/// The series' `"search"` keys over the campaign's.
fn merge_search(c: &mut Value, search: &Map<String, Value>) {
    if search.is_empty() {
        return;
    }
    let obj = c.as_object_mut().expect("a campaign object");
    let s = obj.entry("search").or_insert_with(|| json!({}));
    if !s.is_object() {
        *s = json!({});
    }
    let s = s.as_object_mut().expect("an object");
    for (k, v) in search {
        s.insert(k.clone(), v.clone());
    }
}

fn experiment_names(c: &Value) -> Vec<String> {
    c.get("experiments")
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .filter_map(|e| e.get("name").and_then(Value::as_str).map(String::from))
                .collect()
        })
        .unwrap_or_default()
}

/// The row's records in the campaign's experiments; `Some` error (kept for
/// the test, which then fails) for a record that does not exist.
fn set_records(c: &mut Value, row: &TestRow) -> Result<Option<String>, String> {
    let names = experiment_names(c);
    let mut missing = None;
    for (exp, file) in &row.records {
        let index = match exp {
            None if names.len() == 1 => 0,
            None => {
                return Err(format!(
                    "column \"record\": the campaign has {} experiments ({}); name the one each record is for with a column \"record.<experiment>\"",
                    names.len(),
                    names.join(", ")
                ));
            }
            Some(name) => names.iter().position(|n| n == name).ok_or_else(|| {
                format!(
                    "column \"record.{name}\": the campaign has no experiment \"{name}\"; its experiments are: {}",
                    names.join(", ")
                )
            })?,
        };
        if !file.is_file() && missing.is_none() {
            missing = Some(format!("record `{}` is not a file", file.display()));
        }
        c["experiments"][index]["data"]["file"] = json!(file);
    }
    Ok(missing)
}

/// The row's fixed values and bounds in the campaign's parameters.
fn apply_overrides(c: &mut Value, o: &Overrides) -> Result<(), String> {
    for (name, value) in &o.values {
        if o.mins.iter().chain(&o.maxs).any(|(n, _)| n == name) {
            return Err(format!(
                "\"value.{name}\" and a bound of {name} are both given; a parameter is either fixed (value) or free (min, max)"
            ));
        }
        *param_slot(c, name)? = json!(value);
    }
    let mut names: Vec<&String> = o.mins.iter().chain(&o.maxs).map(|(n, _)| n).collect();
    names.dedup();
    for name in names {
        let min = o.mins.iter().find(|(n, _)| n == name).map(|x| x.1);
        let max = o.maxs.iter().find(|(n, _)| n == name).map(|x| x.1);
        let slot = param_slot(c, name)?;
        if let Some(range) = slot.as_object_mut() {
            if let Some(m) = min {
                range.insert("min".into(), json!(m));
            }
            if let Some(m) = max {
                range.insert("max".into(), json!(m));
            }
        } else {
            match (min, max) {
                (Some(min), Some(max)) => *slot = json!({"min": min, "max": max}),
                _ => {
                    return Err(format!(
                        "the campaign fixes {name}; give both \"min.{name}\" and \"max.{name}\" to free it"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The campaign's entry for parameter `name`: `k1` in the shared
/// `"params"`, `v2.k_lin` in experiment `v2`'s own; created (null) where
/// the campaign leaves it to the rig's default.
fn param_slot<'a>(c: &'a mut Value, name: &str) -> Result<&'a mut Value, String> {
    let params = match name.split_once('.') {
        Some((exp, _)) => {
            let names = experiment_names(c);
            let i = names.iter().position(|n| n == exp).ok_or_else(|| {
                format!(
                    "parameter \"{name}\": the campaign has no experiment \"{exp}\"; its experiments are: {}",
                    names.join(", ")
                )
            })?;
            &mut c["experiments"][i]
        }
        None => c,
    };
    let obj = params.as_object_mut().expect("an object");
    let p = obj.entry("params").or_insert_with(|| json!({}));
    let key = name.split_once('.').map_or(name, |(_, p)| p);
    Ok(p.as_object_mut()
        .ok_or_else(|| "the campaign's \"params\" is not an object".to_string())?
        .entry(key.to_string())
        .or_insert(Value::Null))
}

/// Writes a test's campaign (where it changed) and reads it back as a job
/// would, for its errors and the size of its search.
fn write_test(root: &Path, d: Draft) -> Result<TestEntry, SeriesError> {
    let Draft {
        id,
        source,
        covariates,
        seed,
        mut campaign,
        error,
    } = d;
    let original = campaign
        .get("description")
        .and_then(Value::as_str)
        .unwrap_or_default()
        .to_string();
    let name = campaign
        .get("name")
        .and_then(Value::as_str)
        .unwrap_or("test")
        .to_string();
    campaign["name"] = json!(format!("{name}-{id}"));
    campaign["description"] = json!(format!(
        "{DESCRIPTION_MARK} \"{id}\" ({source}), written by `rigfit series`. {original}"
    ));
    let obj = campaign.as_object_mut().expect("an object");
    let search = obj.entry("search").or_insert_with(|| json!({}));
    if let Some(s) = search.as_object_mut() {
        s.insert("seed".into(), json!(seed));
    }
    campaign["output"] = json!(format!("../{TESTS_DIR}/{id}"));
    let rel = PathBuf::from(CAMPAIGNS_DIR).join(format!("{id}.json"));
    let path = root.join(&rel);
    let mut text = serde_json::to_string_pretty(&campaign).expect("JSON serialises");
    text.push('\n');
    write_campaign(&path, &text)?;
    let (error, work) = match error {
        Some(e) => (Some(e), 0.0),
        None => match Campaign::load(&path) {
            Ok(c) => {
                let s = &c.search;
                (
                    None,
                    (s.population * s.generations) as f64 * c.run_length().steps_per_candidate,
                )
            }
            Err(e) => (
                Some(crate::base::text::shorten_quotes(&e.to_string(), 400)),
                0.0,
            ),
        },
    };
    Ok(TestEntry {
        id: id.clone(),
        campaign: rel,
        out: PathBuf::from(TESTS_DIR).join(&id),
        seed,
        covariates,
        source,
        error,
        work,
    })
}

/// Writes a test's campaign unless the same text is there; refuses to
/// replace a file rigfit did not write.
fn write_campaign(path: &Path, text: &str) -> Result<(), SeriesError> {
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        let ours = meta.is_file()
            && std::fs::read_to_string(path).ok().is_some_and(|old| {
                serde_json::from_str::<Value>(&old).ok().is_some_and(|v| {
                    v.get("description")
                        .and_then(Value::as_str)
                        .is_some_and(|d| d.starts_with(DESCRIPTION_MARK))
                })
            });
        if !ours {
            return Err(SeriesError::Folder {
                path: path.to_path_buf(),
                reason: "this file was not written by rigfit series; rigfit never replaces it: move it away".into(),
            });
        }
        if std::fs::read_to_string(path).is_ok_and(|old| old == text) {
            return Ok(());
        }
    }
    crate::base::fsutil::atomic_write(path, text.as_bytes()).map_err(|e| SeriesError::io(path, e))
}
