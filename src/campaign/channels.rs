//! An experiment's measured channels: each column of its record that the
//! campaign fits, against one of the rig's outputs.
//!
//! Without `"channels"`, an experiment has one: `data.column` against output
//! 0. With them, each channel is fitted as an experiment of its own (named
//! `<experiment>.<output>`) that shares the experiment's parameters, drive,
//! offset and record: its own column, scale, fit window and weight (the
//! experiment's weight times the channel's). The joint fitness weighs each
//! channel's `1 − R²` as it weighs experiments.

use std::path::Path;

use super::CampaignError;
use super::error::invalid;
use super::raw::RawExperiment;
use crate::model::CompiledRig;

/// Experiment `e` as one view per channel: the experiment with that channel's
/// column, scale, window and weight, the index of the rig output it measures
/// and its name in the problem.
pub(super) fn views(
    file: &Path,
    model: &CompiledRig,
    e: usize,
    x: &RawExperiment,
) -> Result<Vec<(RawExperiment, usize, String)>, CampaignError> {
    let Some(channels) = &x.channels else {
        return Ok(vec![(x.clone(), 0, x.name.clone())]);
    };
    let at = format!("experiments[{e}]");
    if x.data.force_column.is_some() || x.data.force_scale != 1.0 {
        return Err(invalid(
            file,
            format!("{at}.data"),
            "no \"column\" or \"scale\" where \"channels\" name the columns",
            "both",
        ));
    }
    if channels.is_empty() {
        return Err(invalid(
            file,
            format!("{at}.channels"),
            "at least one channel",
            "an empty list",
        ));
    }
    let outputs: Vec<&str> = model.desc.outputs.iter().map(|o| o.name.as_str()).collect();
    let mut views = Vec::with_capacity(channels.len());
    let mut seen: Vec<usize> = Vec::new();
    for (c, ch) in channels.iter().enumerate() {
        let path = format!("{at}.channels[{c}]");
        let Some(output) = outputs.iter().position(|&o| o == ch.output) else {
            return Err(invalid(
                file,
                format!("{path}.output"),
                format!(
                    "one of rig '{}''s outputs ({})",
                    model.id(),
                    outputs.join(", ")
                ),
                format!("{:?}", ch.output),
            ));
        };
        if let Some(first) = seen.iter().position(|&o| o == output) {
            return Err(invalid(
                file,
                format!("{path}.output"),
                "each output in one channel",
                format!("{:?}, already channels[{first}]", ch.output),
            ));
        }
        seen.push(output);
        for (key, value, ok) in [
            ("scale", ch.scale, ch.scale != 0.0),
            ("weight", ch.weight, ch.weight > 0.0),
        ] {
            if !(ok && value.is_finite()) {
                let expected = if key == "scale" {
                    "a non-zero multiplier"
                } else {
                    "a weight > 0"
                };
                let found = crate::base::text::number(value);
                return Err(invalid(file, format!("{path}.{key}"), expected, found));
            }
        }
        let mut view = x.clone();
        view.channels = None;
        view.data.force_column = Some(ch.column.clone());
        view.data.force_scale = ch.scale;
        view.weight = x.weight * ch.weight;
        if ch.fit_window.is_some() {
            view.fit_window = ch.fit_window.clone();
        }
        views.push((view, output, format!("{}.{}", x.name, ch.output)));
    }
    Ok(views)
}
