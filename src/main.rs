//! The `rigfit` command line.

fn main() -> std::process::ExitCode {
    eprintln!("rigfit: command line under construction");
    std::process::ExitCode::from(2)
}
