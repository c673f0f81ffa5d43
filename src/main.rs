//! The `isotrace` command line. Parses arguments, runs a command from the
//! library, renders any error once, and maps it to an exit code
//! (1: bad input, 2: no usable GPU device, 3: internal error).

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Usage errors exit with 1 like every other bad input (clap's default
    // is 2, which isotrace keeps for "no GPU device").
    let args = match cli::Cli::try_parse() {
        Ok(a) => a,
        Err(e) => {
            // clap quotes the arguments it rejects, and on a terminal it
            // passes escape sequences in them through. With a control
            // character in any argument the message is printed plain
            // (clap strips the sequences) with the rest made visible.
            let control = std::env::args_os().any(|a| a.to_string_lossy().chars().any(|c| c.is_control() && c != '\t'));
            if control && e.use_stderr() {
                eprint!("{}", isotrace::diag::escape_controls(&e.render().to_string()));
            } else {
                let _ = e.print();
            }
            return ExitCode::from(if e.use_stderr() { 1 } else { 0 });
        }
    };
    cli::signals::remove_temporaries_on_termination();
    match cli::run(args) {
        Ok(code) => code,
        Err(e) => {
            eprint!("{}", e.render());
            ExitCode::from(e.exit_code())
        }
    }
}
