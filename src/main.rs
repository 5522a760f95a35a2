//! The `rigfit` command line: `main` parses, `cli::dispatch` works, and every
//! error is printed with its full cause chain and a distinct exit code.

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = match cli::args::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(cli::EXIT_BAD_INPUT)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp_millis()
        .init();
    let json = cli.json;
    match cli::dispatch(cli) {
        Ok(code) => code,
        Err(err) => {
            let code = cli::exit_code(&err);
            // Every message is bounded, whatever a library quoted from the
            // input (the sources cut their own echoes to 60 characters).
            let bound = |s: String| {
                rigfit::base::text::shorten_quotes(&s, 4 * rigfit::base::text::ECHO_CHARS)
            };
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
                cli::print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
            }
            ExitCode::from(code)
        }
    }
}
