//! Shell integration: completion scripts (clap_complete) and man pages
//! (clap_mangen). Both are generated from the clap definition the parser
//! uses, so they cannot drift from the real flags.

use super::{input, CliError};
use clap::{Args, CommandFactory};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    shell: clap_complete::Shell,
}

#[derive(Args, Debug)]
pub struct ManArgs {
    /// A subcommand whose own page to generate (isotrace-render(1), …); default: the page of isotrace(1).
    #[arg(value_name = "COMMAND")]
    command: Option<String>,
    /// Write the page to FILE instead of stdout.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
}

/// Prints the completion script of `shell` to stdout.
pub fn completions(a: CompletionsArgs) -> Result<ExitCode, CliError> {
    let mut cmd = super::Cli::command();
    let mut script = Vec::new();
    clap_complete::generate(a.shell, &mut cmd, "isotrace", &mut script);
    let _ = std::io::stdout().lock().write_all(&script);
    Ok(ExitCode::SUCCESS)
}

/// Prints (or with `-o` writes) a man page in roff.
pub fn man(a: ManArgs) -> Result<ExitCode, CliError> {
    let mut cmd = super::Cli::command();
    cmd.build();
    let page = match &a.command {
        None => cmd,
        Some(name) => {
            let Some(sub) = cmd.find_subcommand(name) else {
                let names: Vec<&str> = cmd.get_subcommands().map(|c| c.get_name()).collect();
                return Err(CliError::Input(format!("unknown command '{name}' for man: expected one of {}", names.join(", "))));
            };
            // Built, a subcommand is named isotrace-render (its page's
            // title, as git names its pages) and used as `isotrace render`.
            sub.clone()
        }
    };
    let mut roff = Vec::new();
    clap_mangen::Man::new(page)
        .render(&mut roff)
        .map_err(|e| CliError::Internal(format!("cannot generate the man page: {e}")))?;
    match a.output {
        Some(path) => input::write_atomic(&path, &roff).map_err(CliError::Input)?,
        None => {
            let _ = std::io::stdout().lock().write_all(&roff);
        }
    }
    Ok(ExitCode::SUCCESS)
}
