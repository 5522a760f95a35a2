//! Raw campaign → validated [`Campaign`]: names, experiments, data, genes, step.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::{invalid, parse_json};
use super::initial;
use super::names::{check_campaign_name, check_experiment_names};
use super::raw::{RawCampaign, RawData, RawDrive, RawExperiment, RawParam};
use super::record_file::{self, Recorded};
use super::resolve::{check_map, check_physics, check_value, resolve};
use super::simulation::{self, Reading};
use super::stability::choose;
use super::{Campaign, CampaignError, FNV_BASIS, Gene, GeneTarget, Source, acts_in, fnv1a};
use crate::base::data::{Column, CsvSpec};
use crate::base::{Drive, PiecewiseLinear};
use crate::eval::{ExperimentData, Problem};
use crate::model::compiled::CompiledRig;
use crate::record::lent::{Lent, Loan};
use crate::rig;
use crate::search::SearchSettings;

/// Validates campaign text from `file`, resolving paths against `dir`, its
/// records read as `reading` says.
pub(crate) fn build(
    text: &str,
    dir: &Path,
    file: &Path,
    reading: Reading<'_>,
    lent: &Lent,
) -> Result<Campaign, CampaignError> {
    let raw: RawCampaign = parse_json(text, file)?;
    check_campaign_name(file, &raw.name)?;
    let mut rig_file = None;
    let rig = model_of(&raw, dir, file, &mut rig_file)?;
    let model: &CompiledRig = &rig;
    if let Some(search) = &raw.search {
        search
            .validate()
            .map_err(|e| invalid(file, format!("search.{}", e.field), e.expected, e.found))?;
    }
    if raw.experiments.is_empty() {
        return Err(invalid(
            file,
            "experiments",
            "at least one experiment",
            "an empty list",
        ));
    }
    let names: Vec<&str> = raw.experiments.iter().map(|x| x.name.as_str()).collect();
    check_experiment_names(file, &names)?;

    let shared = check_map(file, "params", model, &raw.params, false)?;
    let own = raw
        .experiments
        .iter()
        .enumerate()
        .map(|(e, x)| {
            check_map(
                file,
                &format!("experiments[{e}].params"),
                model,
                &initial::as_params(file, (dir, lent), e, x)?,
                true,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<String> = raw.experiments.iter().map(|x| x.name.clone()).collect();
    let mut r = resolve(file, model, &shared, &own, &names)?;

    // Offsets: genes after each experiment's own parameter genes.
    let mut base_offsets = Vec::new();
    let mut genes: Vec<Gene> = r
        .genes
        .iter()
        .filter(|g| g.experiment.is_none())
        .cloned()
        .collect();
    for (e, x) in raw.experiments.iter().enumerate() {
        genes.extend(r.genes.iter().filter(|g| g.experiment == Some(e)).cloned());
        let raw_off = x.offset.clone().unwrap_or(RawParam::Fixed(0.0));
        let spec = check_value(file, &format!("experiments[{e}].offset"), &raw_off, None)?;
        let name = format!("{}.offset", x.name);
        genes.extend(spec.gene(name, Some(e), GeneTarget::Offset, "s"));
        base_offsets.push(spec.base());
    }

    let mut digest = fnv1a(FNV_BASIS, text.as_bytes());
    let mut experiments = Vec::new();
    let mut inputs: Vec<PathBuf> = std::iter::once(file.to_path_buf())
        .chain(rig_file)
        .collect();
    let mut owners = Vec::new();
    let mut records = Vec::new();
    for (e, x) in raw.experiments.iter().enumerate() {
        let free = |i: usize| {
            genes
                .iter()
                .any(|g| acts_in(g, e, &r.sources[e]) && g.target == GeneTarget::Param(i))
        };
        let (lo, hi) = corners(&r.base[e], &genes, e, &r.sources[e]);
        check_physics(file, model, &r.base[e], &lo, &hi, &r.paths[e], &free)?;
        // The record is read once for all of an experiment's channels.
        let mut record = record_file::Shared::default();
        for (c, (view, output, name)) in super::channels::views(file, model, e, x)?
            .into_iter()
            .enumerate()
        {
            let (mut exp, bytes_hash, read, recorded) = experiment(
                file,
                (dir, lent),
                e,
                &view,
                (digest, &mut record),
                reading,
                &mut r.warnings,
            )?;
            if !model.supports(&exp.drive) {
                return Err(invalid(
                    file,
                    format!("experiments[{e}].drive"),
                    format!("a drive mode that rig '{}' declares", model.id()),
                    "a force table (the rig has no \"force\"-mode drive)",
                ));
            }
            if output != 0 {
                rig.scoring(output).map_err(rig_error)?;
            }
            if let (Some(recorded), Some(data_file)) = (recorded, &read) {
                let used = (e, c, x);
                let r =
                    record_file::check_units(file, model, used, name.clone(), recorded, data_file)?;
                records.push(r);
            }
            exp.output = output;
            exp.name = name;
            initial::check_prescribed(file, model, e, x, &exp.drive)?;
            digest = bytes_hash;
            experiments.push(exp);
            owners.push(e);
            inputs.extend(read.filter(|p| !inputs.contains(p)));
        }
    }

    check_weights(file, &experiments)?;
    let requested = raw.solver.substeps;
    let step = choose(
        model,
        &experiments,
        &genes,
        |e| corners(&r.base[owners[e]], &genes, owners[e], &r.sources[owners[e]]),
        |e| latest_offset(base_offsets[owners[e]], &genes, owners[e]),
        |e| (r.base[owners[e]].clone(), base_offsets[owners[e]]),
        requested,
        raw.solver.tolerance,
    )
    .map_err(|message| CampaignError::Unstable {
        file: file.to_path_buf(),
        path: "solver.substeps".into(),
        message,
    })?;
    r.warnings.extend(step.warning.clone());
    // A record sampled far slower than the rig moves: a time column in
    // milliseconds read as seconds, most often.
    let slowest =
        (0..experiments.len()).max_by(|&a, &b| experiments[a].dt.total_cmp(&experiments[b].dt));
    if let Some(e) = slowest.filter(|_| step.auto) {
        let x = &experiments[e];
        let scale = raw.experiments[owners[e]].data.time_scale;
        if let Some(h) = crate::base::data::slow_sampling_hint(x.dt, step.substeps, scale) {
            r.warnings.push(format!(
                "{}: experiments[{}] ('{}'): {h}",
                file.display(),
                owners[e],
                crate::base::text::echo_bare(&x.name)
            ));
        }
    }
    let substeps = step.substeps;
    let output = lexical_clean(&match &raw.output {
        Some(o) => dir.join(o),
        None => dir.join("results").join(&raw.name),
    });
    Ok(Campaign {
        path: file.to_path_buf(),
        name: raw.name,
        description: raw.description,
        model: rig.clone(),
        problem: Problem {
            model: rig,
            experiments,
            substeps,
        },
        genes,
        base: owners.iter().map(|&o| r.base[o].clone()).collect(),
        base_offsets: owners.iter().map(|&o| base_offsets[o]).collect(),
        solver: step.settings(raw.solver.backend, raw.solver.precision),
        search_given: raw.search.is_some(),
        search: raw.search.unwrap_or_else(SearchSettings::unset),
        output,
        inputs,
        records,
        raw_json: text.to_string(),
        digest,
        warnings: r.warnings,
        validation: None,
        sources: owners.iter().map(|&o| r.sources[o].clone()).collect(),
        owners,
    })
}

/// Largest ratio of two experiments' weights: beyond it the lighter experiment
/// would count for nothing in the joint fitness.
pub const MAX_WEIGHT_RATIO: f64 = 1e9;

/// Weights are used relative to the largest, so their size cannot overflow the
/// joint fitness; one far below another would be ignored in effect.
fn check_weights(file: &Path, experiments: &[ExperimentData]) -> Result<(), CampaignError> {
    let (max_e, max) = experiments
        .iter()
        .enumerate()
        .fold((0, 0.0_f64), |(i, m), (e, x)| {
            if x.weight > m { (e, x.weight) } else { (i, m) }
        });
    for (e, x) in experiments.iter().enumerate() {
        if x.weight * MAX_WEIGHT_RATIO < max {
            return Err(invalid(
                file,
                format!("experiments[{e}].weight"),
                format!(
                    "a weight at least 1/{MAX_WEIGHT_RATIO:e} of the largest \
                     (experiments[{max_e}].weight = {max:e})"
                ),
                format!("{:e}", x.weight),
            ));
        }
    }
    Ok(())
}

/// Lower and upper parameter vectors of experiment `e`.
/// Experiment `e`'s latest clock offset (s): its own, or the upper bound of
/// its offset gene.
pub(crate) fn latest_offset(base: f64, genes: &[Gene], e: usize) -> f64 {
    genes
        .iter()
        .filter(|g| g.experiment == Some(e) && g.target == GeneTarget::Offset)
        .fold(base, |m, g| m.max(g.upper))
}

pub(crate) fn corners(
    base: &[f64],
    genes: &[Gene],
    owner: usize,
    sources: &[Source],
) -> (Vec<f64>, Vec<f64>) {
    let (mut lo, mut hi) = (base.to_vec(), base.to_vec());
    for g in genes.iter().filter(|g| acts_in(g, owner, sources)) {
        if let GeneTarget::Param(i) = g.target {
            lo[i] = g.lower;
            hi[i] = g.upper;
        }
    }
    (lo, hi)
}

/// The campaign's rig, `"rig"` compiled. A `"model"` (the retired
/// hand-written tensile model's key) is refused with its replacement named,
/// not migrated: the compiled rig locates events the hand-written model took
/// where a step landed, so a silent migration would change a user's figures
/// without a word.
fn model_of(
    raw: &RawCampaign,
    dir: &Path,
    file: &Path,
    rig_file: &mut Option<PathBuf>,
) -> Result<Arc<CompiledRig>, CampaignError> {
    if let Some(m) = &raw.model {
        // The key only ever named the tensile rig; a shipped id is kept.
        let id = m
            .as_str()
            .filter(|id| rig::SHIPPED.iter().any(|(s, _)| s == id))
            .unwrap_or("tensile4");
        return Err(invalid(
            file,
            "model",
            format!(
                "\"rig\": the \"model\" key is gone, write \"rig\": \"{id}\" (shipped rigs: {})",
                rig::SHIPPED.map(|(i, _)| i).join(", ")
            ),
            format!(
                "\"model\": {}",
                m.as_str().map_or_else(
                    || crate::base::text::echo_bare(&m.to_string()),
                    crate::base::text::echo
                )
            ),
        ));
    }
    match &raw.rig {
        Some(v) => {
            let (desc, src) = rig::resolve(v, dir, file).map_err(rig_error)?;
            if let rig::RigSource::File(path) = &src {
                // An input like the data: a job never writes over it.
                *rig_file = Some(path.clone());
            }
            let at_campaign = |mut e: rig::RigError| {
                if matches!(src, rig::RigSource::Inline(..)) {
                    e.path = format!("rig.{}", e.path);
                    e.file = file.display().to_string();
                }
                rig_error(e)
            };
            let mut desc = desc;
            if raw.experiments.iter().any(|x| !x.initial.is_empty()) {
                let states =
                    crate::compile::front::state_names(&desc, &src.label()).map_err(at_campaign)?;
                initial::declare(file, &raw.experiments, &mut desc, &states)?;
            }
            CompiledRig::shared(desc, &src.label()).map_err(at_campaign)
        }
        None => Err(invalid(
            file,
            "rig",
            "a \"rig\": a shipped rig's id, a rig file or the rig itself, inline",
            "none",
        )),
    }
}

fn rig_error(e: rig::RigError) -> CampaignError {
    CampaignError::Invalid {
        file: e.file.into(),
        path: e.path,
        expected: e.expected,
        found: e.found,
    }
}

/// An experiment's data, the digest extended with its record's bytes, the
/// record file read and what was read of it (none on a simulation's grid).
type Experiment = (ExperimentData, u64, Option<PathBuf>, Option<Recorded>);

/// Loads and checks one experiment's data, drive, window and weight. Returns the
/// experiment, the digest extended with the data file's bytes and the file read
/// (none on a simulation's grid without a record and without a drive column).
/// One channel of experiment `e` (`x` the channel's view of it). `record`
/// holds the record's bytes once a first channel has read them (and added
/// them to `digest`), and its channels once parsed, for the experiment's
/// other channels.
fn experiment(
    file: &Path,
    (dir, lent): (&Path, &Lent),
    e: usize,
    x: &RawExperiment,
    (digest, record): (u64, &mut record_file::Shared),
    reading: Reading<'_>,
    warnings: &mut Vec<String>,
) -> Result<Experiment, CampaignError> {
    let at = format!("experiments[{e}]");
    let d = &x.data;
    let data_at = format!("{at}.data");
    let checks: [(String, f64, bool, &str); 3] = [
        (
            format!("{at}.weight"),
            x.weight,
            x.weight > 0.0,
            "a weight > 0",
        ),
        (
            format!("{data_at}.time_scale"),
            d.time_scale,
            d.time_scale > 0.0,
            "a multiplier > 0",
        ),
        (
            format!("{data_at}.force_scale"),
            d.force_scale,
            d.force_scale != 0.0,
            "a non-zero multiplier",
        ),
    ];
    for (path, value, ok, expected) in checks {
        if !(ok && value.is_finite()) {
            let found = crate::base::text::number(value);
            return Err(invalid(file, path, expected, found));
        }
    }
    let spec = CsvSpec {
        time: d.time_column.clone().unwrap_or(Column::Index(0)),
        force: d.force_column.clone().unwrap_or(Column::Index(1)),
        time_scale: d.time_scale,
        force_scale: d.force_scale,
        encoding: d.encoding,
        decimal: d.decimal,
    };
    // Without a record, the only file read is the one a drive column comes from.
    let column_drive = matches!(&x.drive, RawDrive::Force(t) if t.column.is_some());
    let bystander = column_drive && reading.bystander(e, &x.name);
    let (data_file, read) = match reading.uniform() {
        None => (dir.join(&d.file), true),
        Some(_) if bystander => (PathBuf::new(), false),
        Some((_, _, Some(f))) => (f.to_path_buf(), column_drive),
        Some((_, _, None)) if column_drive => {
            return Err(simulation::no_drive_file(
                file,
                &format!("{at}.drive.force"),
            ));
        }
        Some(_) => (PathBuf::new(), false),
    };
    let data_err = |path: String, source| CampaignError::Data {
        file: file.to_path_buf(),
        path,
        source: Box::new(source),
    };
    let digest = match record.loan {
        Some(_) => digest,
        None => {
            let loan = if read {
                lent.read(&data_file).map_err(|err| {
                    let source = crate::base::data::DataError::Io {
                        file: data_file.clone(),
                        message: err.to_string(),
                    };
                    data_err(format!("{data_at}.file"), source)
                })?
            } else {
                Loan::Bytes(Arc::from(&[][..]))
            };
            record.lend(loan, digest)
        }
    };
    let mut read_as = |spec: &CsvSpec| record_file::read(record, &data_file, d, spec);
    let (series, recorded) = match reading.uniform() {
        Some((dt, samples, _)) => (simulation::uniform_series(dt, samples), None),
        None => {
            let (series, r) = read_as(&spec).map_err(|s| data_err(data_at.clone(), s))?;
            (series, Some(r))
        }
    };
    warnings.extend(series.warning.clone());
    if let crate::base::data::Column::Name(column) = &spec.time {
        let hint = crate::base::data::millisecond_column_hint(column, d.time_scale, series.dt);
        warnings.extend(hint.map(|h| format!("{}: {data_at}.time_column: {h}", file.display())));
    }
    let drive = match &x.drive {
        RawDrive::Velocity => Drive::Velocity,
        RawDrive::Force(table) => {
            let path = format!("{at}.drive.force");
            let (t, value) = match (&table.t, &table.value, &table.column) {
                (Some(t), Some(v), None) => (t.clone(), v.clone()),
                (None, None, Some(_)) if bystander => (vec![0.0, 1.0], vec![0.0, 0.0]),
                (None, None, Some(column)) => {
                    let spec = CsvSpec {
                        force: column.clone(),
                        ..spec.clone()
                    };
                    let (s, _) =
                        read_as(&spec).map_err(|s| data_err(format!("{path}.column"), s))?;
                    (s.t, s.force)
                }
                _ => {
                    return Err(invalid(
                        file,
                        path,
                        "\"t\" and \"value\", or \"column\" (a column of the data file)",
                        "another combination",
                    ));
                }
            };
            if t.len() < 2 || t.len() != value.len() {
                let found = format!("{} times and {} values", t.len(), value.len());
                return Err(invalid(
                    file,
                    path,
                    "at least 2 points, as many times as values",
                    found,
                ));
            }
            if let Some(k) = t.windows(2).position(|w| w[1] <= w[0]) {
                let found = format!("{} s after {} s", t[k + 1], t[k]);
                return Err(invalid(
                    file,
                    format!("{path}.t[{}]", k + 1),
                    "strictly increasing times",
                    found,
                ));
            }
            let table = PiecewiseLinear { t, value };
            if reading.uniform().is_some() && column_drive && !bystander {
                let at = format!("{path}.column");
                Drive::Force(simulation::resample(
                    &table, &series.t, &data_file, &at, warnings,
                ))
            } else {
                Drive::Force(table)
            }
        }
    };
    let window = match reading.uniform() {
        Some(_) => 0..series.t.len(),
        None => super::window::window(file, &at, x, &series, warnings)?,
    };
    let scored = &series.force[window.clone()];
    if reading.scores() && scored.iter().all(|&f| f == scored[0]) {
        // R² compares the model with the record's variation: there is none.
        let (t0, t1) = (series.t[window.start], series.t[window.end - 1]);
        return Err(invalid(
            file,
            format!("{at}.fit_window"),
            format!(
                "a force that varies inside the fit window ({} samples from {t0} s to {t1} s of \
                 {}); R² is undefined for a constant record",
                window.len(),
                data_file.display()
            ),
            format!("{} N at every sample", scored[0]),
        ));
    }
    let mut measured = series.force;
    measured.truncate(window.end);
    let mut exp = ExperimentData {
        output: 0,
        name: x.name.clone(),
        drive,
        t_first: series.t[0],
        dt: series.dt,
        measured,
        window,
        weight: x.weight,
    };
    if reading.scores() {
        check_scored_record(file, &at, &data_file, &series.t, &exp, d)?;
    }
    if let Some(samples) = reading.record_samples() {
        // Continued past the record or cut short; the placeholder is never scored.
        exp.measured.resize(samples, 0.0);
        exp.window = 0..samples;
    }
    Ok((exp, digest, read.then_some(data_file), recorded))
}

/// `a/b/../c` → `a/c` without touching the file system, so messages show the
/// folder a user would type.
fn lexical_clean(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

/// A scored record must be one R² means something for: its measured column is
/// not the time column again, and the squares of its deviations stay finite.
fn check_scored_record(
    file: &Path,
    at: &str,
    data_file: &Path,
    t: &[f64],
    exp: &ExperimentData,
    d: &RawData,
) -> Result<(), CampaignError> {
    let (t, f) = (&t[exp.window.clone()], &exp.measured[exp.window.clone()]);
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
    if t.iter()
        .zip(f)
        .all(|(&t, &f)| same(t / d.time_scale, f / d.force_scale))
    {
        return Err(invalid(
            file,
            format!("{at}.data.force_column"),
            format!(
                "a measured column other than the time column of {}",
                data_file.display()
            ),
            "the time values again at every sample of the fit window",
        ));
    }
    if !exp.ss_tot().is_finite() {
        let (k, big) = f
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map_or((0, 0.0), |(k, &x)| (k, x));
        return Err(invalid(
            file,
            format!("{at}.data"),
            format!(
                "measured values whose squared deviations add up to a finite number in {} \
                 (R² divides by that sum)",
                data_file.display()
            ),
            format!(
                "{} at t = {} s",
                crate::base::text::number(big),
                crate::base::text::number(t[k])
            ),
        ));
    }
    Ok(())
}
