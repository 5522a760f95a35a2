//! Exit codes, the binary's own input error, and how a failed command is
//! reported: the full cause chain on stderr, and with `--json` one JSON
//! document on stdout.

use std::process::ExitCode;

use super::output::print_stdout;
use rigfit::job::JobError;
use rigfit::search::SearchError;

/// Exit code of a job that failed after its input was accepted.
pub const EXIT_FAILED: u8 = 1;
/// Exit code of bad input or usage.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code of a job stopped by Ctrl-C / SIGTERM (checkpoint written).
pub const EXIT_INTERRUPTED: u8 = 130;

/// An input error found by the binary itself.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

/// Exit code for an error: 2 when the input was at fault, 1 otherwise.
pub fn exit_code(err: &anyhow::Error) -> u8 {
    let bad_input = err.chain().any(|e| {
        e.is::<rigfit::campaign::CampaignError>()
            || e.is::<rigfit::base::data::DataError>()
            || e.is::<rigfit::identify::IdentifyError>()
            || e.is::<BadInput>()
            || e.downcast_ref::<JobError>()
                .is_some_and(JobError::blames_input)
            || e.downcast_ref::<SearchError>()
                .is_some_and(SearchError::blames_input)
            || e.downcast_ref::<rigfit::series::SeriesError>()
                .is_some_and(rigfit::series::SeriesError::blames_input)
    });
    if bad_input {
        EXIT_BAD_INPUT
    } else {
        EXIT_FAILED
    }
}

/// Prints a failed command's error with its causes (and, with `--json`, as a
/// JSON document on stdout) and returns its exit code.
pub fn report(err: &anyhow::Error, json: bool) -> ExitCode {
    let code = exit_code(err);
    // Every message is bounded, whatever a library quoted from the
    // input (the sources cut their own echoes to 60 characters).
    let bound =
        |s: String| rigfit::base::text::shorten_quotes(&s, 4 * rigfit::base::text::ECHO_CHARS);
    let message = bound(err.to_string());
    let mut shown = message.clone();
    let mut causes = Vec::new();
    eprintln!("rigfit: error: {message}");
    for cause in err.chain().skip(1) {
        // A message that already quotes its cause needs no second copy.
        let text = bound(cause.to_string());
        if !shown.contains(&text) {
            eprintln!("  caused by: {text}");
            shown.push_str(&text);
            causes.push(text);
        }
    }
    if json {
        let doc = serde_json::json!({
            "error": message, "causes": causes, "exit_code": code,
        });
        print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
    }
    ExitCode::from(code)
}
