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
    // HDF5 is read in a child rigfit, so that a crash of libhdf5 on a
    // corrupted file is an error about that file (record/hdf5_child.rs).
    if let Ok(exe) = std::env::current_exe() {
        rigfit::record::hdf5_child::read_in_child(exe);
    }
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp_millis()
        .init();
    let json = cli.json;
    match cli::dispatch(cli) {
        Ok(code) => code,
        Err(err) => cli::exit::report(&err, json),
    }
}
