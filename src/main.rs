//! The `isotrace` command line. Parses arguments, runs a command from the
//! library, renders any error once, and maps it to an exit code
//! (1: bad input, 2: no usable GPU device, 3: internal error).

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(code) => code,
        Err(e) => {
            eprint!("{}", e.render());
            ExitCode::from(e.exit_code())
        }
    }
}
