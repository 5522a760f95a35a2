//! Resolving parameters: which value or gene each experiment's parameter gets,
//! and the checks on names, ranges and physical sense.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::invalid;
use super::raw::RawParam;
use super::{CampaignError, Gene, GeneTarget, Source};
use crate::base::{ParamInfo, ParamScope, Scale};
use crate::model::{CompiledRig, param_index};

/// A checked parameter value.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Spec {
    Fixed(f64),
    Free {
        lower: f64,
        upper: f64,
        scale: Scale,
        init: Option<f64>,
    },
}

impl Spec {
    /// The value used in the base vector: fixed value, init or mid-range.
    pub(crate) fn base(&self) -> f64 {
        match *self {
            Spec::Fixed(v) => v,
            Spec::Free { init: Some(v), .. } => v,
            Spec::Free {
                lower,
                upper,
                scale: Scale::Log,
                ..
            } => lower.sqrt() * upper.sqrt(),
            Spec::Free { lower, upper, .. } => 0.5 * (lower + upper),
        }
    }

    /// The gene that searches this value, or `None` when it is fixed.
    pub(crate) fn gene(
        &self,
        name: String,
        experiment: Option<usize>,
        target: GeneTarget,
        unit: &str,
    ) -> Option<Gene> {
        match *self {
            Spec::Fixed(_) => None,
            Spec::Free {
                lower,
                upper,
                scale,
                init,
            } => Some(Gene {
                name,
                experiment,
                target,
                lower,
                upper,
                scale,
                init,
                unit: unit.to_string(),
            }),
        }
    }
}

/// Checks one raw value at `path`. `info` is `None` for an offset (linear only).
pub(crate) fn check_value(
    file: &Path,
    path: &str,
    raw: &RawParam,
    info: Option<&ParamInfo>,
) -> Result<Spec, CampaignError> {
    let r = match raw {
        RawParam::Fixed(v) => return Ok(Spec::Fixed(*v)),
        RawParam::Free(r) => r,
    };
    if r.min >= r.max {
        let expected = format!("max > min ({})", r.min);
        return Err(invalid(
            file,
            format!("{path}.max"),
            expected,
            r.max.to_string(),
        ));
    }
    let scale = match (r.scale, info) {
        (Some(Scale::Log), None) => {
            return Err(invalid(
                file,
                format!("{path}.scale"),
                "\"linear\" (offsets are searched linearly)",
                "\"log\"",
            ));
        }
        (Some(s), _) => s,
        (None, Some(i)) => i.scale,
        (None, None) => Scale::Linear,
    };
    if scale == Scale::Log && r.min <= 0.0 {
        let why = match (r.scale, info) {
            (None, Some(i)) => format!(
                "min > 0 for log scale (the model's default scale for '{}'; write \"scale\": \"linear\" to search a range through 0)",
                i.name
            ),
            _ => "min > 0 for log scale".to_string(),
        };
        return Err(invalid(file, format!("{path}.min"), why, r.min.to_string()));
    }
    if let Some(init) = r.init
        && !(r.min..=r.max).contains(&init)
    {
        let expected = format!("a value in [{}, {}]", r.min, r.max);
        return Err(invalid(
            file,
            format!("{path}.init"),
            expected,
            init.to_string(),
        ));
    }
    Ok(Spec::Free {
        lower: r.min,
        upper: r.max,
        scale,
        init: r.init,
    })
}

/// The error for a parameter name the model lacks, with a suggestion.
pub(crate) fn unknown_param(
    file: &Path,
    path: &str,
    model: &CompiledRig,
    name: &str,
) -> CampaignError {
    let names: Vec<&str> = model.params().iter().map(|p| p.name.as_str()).collect();
    let poly_max = names
        .iter()
        .filter_map(|n| n.strip_prefix('a').and_then(|d| d.parse::<usize>().ok()))
        .max();
    let asked = name.strip_prefix('a').and_then(|d| d.parse::<usize>().ok());
    let hint = match (poly_max, asked) {
        (Some(max), Some(k)) if k > max => {
            format!("; the polynomial degree is at most {max} (a0..a{max})")
        }
        // A name far longer than any parameter's is no typo of one.
        _ if name.len() > 100 => String::new(),
        // Names are case-sensitive: where only the case differs, say so.
        _ => match names.iter().find(|n| n.eq_ignore_ascii_case(name)) {
            Some(n) => format!("; did you mean '{n}'? (names are case-sensitive)"),
            None => names
                .iter()
                .map(|n| (strsim::levenshtein(n, name), *n))
                .min()
                .filter(|(d, _)| *d <= 2.max(name.len() / 3))
                .map(|(_, n)| format!("; did you mean '{n}'?"))
                .unwrap_or_default(),
        },
    };
    // Both echo the key: escaped and cut short, whatever the file holds.
    CampaignError::UnknownParam {
        file: file.to_path_buf(),
        path: crate::base::text::echo_bare(path),
        name: crate::base::text::echo_bare(name),
        model: model.id().to_string(),
        hint,
    }
}

/// Checks a `params` map at `at`; `experiment` says whether rig parameters are
/// refused. Returns specs by model index.
pub(crate) fn check_map(
    file: &Path,
    at: &str,
    model: &CompiledRig,
    map: &BTreeMap<String, RawParam>,
    experiment: bool,
) -> Result<BTreeMap<usize, (Spec, String)>, CampaignError> {
    let mut out = BTreeMap::new();
    for (name, raw) in map {
        let path = format!("{at}.{name}");
        let i = param_index(model, name).ok_or_else(|| unknown_param(file, &path, model, name))?;
        let info = &model.params()[i];
        if experiment && info.scope == ParamScope::Rig {
            return Err(CampaignError::RigParamInExperiment {
                file: file.to_path_buf(),
                path,
                name: name.clone(),
            });
        }
        check_domain(file, &path, raw, model, name)?;
        out.insert(i, (check_value(file, &path, raw, Some(info))?, path));
    }
    Ok(out)
}

/// Refuses a value, bound or `init` of parameter `name` outside the physical
/// domain its rig declares or implies ([`crate::rig::domain`]), naming
/// `path` (`.min`, `.max` or `.init` for a range) and the declaration.
pub(crate) fn check_domain(
    file: &Path,
    path: &str,
    raw: &RawParam,
    model: &CompiledRig,
    name: &str,
) -> Result<(), CampaignError> {
    let values: Vec<(f64, String)> = match raw {
        RawParam::Fixed(v) => vec![(*v, path.to_string())],
        RawParam::Free(r) => std::iter::once((r.min, format!("{path}.min")))
            .chain(std::iter::once((r.max, format!("{path}.max"))))
            .chain(r.init.map(|v| (v, format!("{path}.init"))))
            .collect(),
    };
    for (v, at) in values {
        domain_of_value(file, &at, model, name, v)?;
    }
    Ok(())
}

/// Refuses value `v` of parameter `name`, set at `path` of `file`, outside
/// its physical domain.
pub(crate) fn domain_of_value(
    file: &Path,
    path: &str,
    model: &CompiledRig,
    name: &str,
    v: f64,
) -> Result<(), CampaignError> {
    let rig = &model.desc;
    let Some(p) = rig.params.iter().find(|p| p.name == name) else {
        return Ok(());
    };
    let d = crate::rig::domain::of(rig, name);
    // A node's mass is refused by the rig's own check ("a mass > 0"), with
    // the same path, where no "domain" key says more.
    let mass = p.domain.is_none() && crate::rig::domain::is_node_mass(rig, name);
    if mass || d.domain.contains(v) {
        return Ok(());
    }
    Err(invalid(
        file,
        path,
        crate::rig::domain::expected(&rig.id, p, &d),
        v.to_string(),
    ))
}

/// Parameters of every experiment resolved into base vectors, sources and genes.
pub(crate) struct Resolved {
    pub base: Vec<Vec<f64>>,
    pub sources: Vec<Vec<Source>>,
    pub genes: Vec<Gene>,
    /// JSON path of each experiment's value of each parameter.
    pub paths: Vec<Vec<String>>,
    pub warnings: Vec<String>,
}

/// Resolves shared and per-experiment specs (`own[e]`) into genes and base
/// vectors. `names[e]` are the experiment names. Offsets are added by the caller.
pub(crate) fn resolve(
    file: &Path,
    model: &CompiledRig,
    shared: &BTreeMap<usize, (Spec, String)>,
    own: &[BTreeMap<usize, (Spec, String)>],
    names: &[String],
) -> Result<Resolved, CampaignError> {
    let infos = model.params();
    let missing_rig: Vec<String> = infos
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            p.scope == ParamScope::Rig && p.default.is_none() && !shared.contains_key(i)
        })
        .map(|(_, p)| p.name.to_string())
        .collect();
    if !missing_rig.is_empty() {
        return Err(CampaignError::MissingParams {
            file: file.to_path_buf(),
            path: "params".into(),
            names: missing_rig,
        });
    }
    let mut r = Resolved {
        base: Vec::new(),
        sources: Vec::new(),
        genes: Vec::new(),
        paths: Vec::new(),
        warnings: Vec::new(),
    };
    for (&i, (spec, path)) in shared {
        let Some(gene) = spec.gene(
            infos[i].name.to_string(),
            None,
            GeneTarget::Param(i),
            &infos[i].unit,
        ) else {
            continue;
        };
        if own.iter().all(|o| o.contains_key(&i)) {
            r.warnings.push(format!(
                "{}: {path}: free parameter is overridden in every experiment; it is not searched",
                file.display()
            ));
            continue;
        }
        r.genes.push(gene);
    }
    for (e, own_e) in own.iter().enumerate() {
        let mut base = Vec::with_capacity(infos.len());
        let mut sources = Vec::with_capacity(infos.len());
        let mut paths = Vec::with_capacity(infos.len());
        let mut missing = Vec::new();
        for (i, info) in infos.iter().enumerate() {
            let (spec, source, path) = match (own_e.get(&i), shared.get(&i), info.default) {
                (Some((s, p)), _, _) => (s.clone(), Source::Own, p.clone()),
                (None, Some((s, p)), _) => (s.clone(), Source::Shared, p.clone()),
                (None, None, Some(d)) => (
                    Spec::Fixed(d),
                    Source::Default,
                    format!("params.{} (model default)", info.name),
                ),
                (None, None, None) => {
                    missing.push(info.name.to_string());
                    (Spec::Fixed(f64::NAN), Source::Default, String::new())
                }
            };
            if source == Source::Own {
                let name = format!("{}.{}", names[e], info.name);
                r.genes
                    .extend(spec.gene(name, Some(e), GeneTarget::Param(i), &info.unit));
            }
            base.push(spec.base());
            sources.push(source);
            paths.push(path);
        }
        if !missing.is_empty() {
            return Err(CampaignError::MissingParams {
                file: file.to_path_buf(),
                path: format!("experiments[{e}].params"),
                names: missing,
            });
        }
        r.base.push(base);
        r.sources.push(sources);
        r.paths.push(paths);
    }
    Ok(r)
}

/// Runs the model's physical checks on the base vector and on both corners of
/// the free ranges of experiment `e`, naming the JSON path of the culprit.
pub(crate) fn check_physics(
    file: &Path,
    model: &CompiledRig,
    base: &[f64],
    lo: &[f64],
    hi: &[f64],
    paths: &[String],
    free: &dyn Fn(usize) -> bool,
) -> Result<(), CampaignError> {
    for (v, suffix) in [(lo, ".min"), (hi, ".max"), (base, ".init")] {
        if let Err((name, expected)) = model.check(v) {
            let i = param_index(model, name).unwrap_or(0);
            let path = if free(i) {
                format!("{}{suffix}", paths[i])
            } else {
                paths[i].clone()
            };
            return Err(invalid(
                file,
                path,
                format!("{name}: {expected}"),
                if v[i].is_infinite() {
                    "null".to_string()
                } else {
                    v[i].to_string()
                },
            ));
        }
    }
    Ok(())
}
