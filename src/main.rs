//! The `rigfit` command line: `main` parses, `cli::dispatch` works, and every
//! error is printed with its full cause chain and a distinct exit code.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = match cli::args::Cli::try_parse_args() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(cli::exit::EXIT_BAD_INPUT)
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
        Err(err) => cli::exit::report(&err, json),
    }
}
