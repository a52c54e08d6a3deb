//! The `smlt` binary: parses the command line and runs the subcommand (`cmd`), with
//! one-line errors and the exit codes of a command-line tool.

use std::process::ExitCode;

mod cmd;

use clap::Parser;
use cmd::Cli;

fn main() -> ExitCode {
    // Like other command-line tools, end quietly when stdout is a closed pipe (`smlt … | head`)
    // instead of panicking in println!. Rust ignores SIGPIPE by default; restore the default.
    // SAFETY: called first thing in main, before any other thread exists.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        smlt::gpu::provide_runtime_dir();
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // One line naming the problem (clap's first line, with the argument it lists on
            // the next where it ends in a colon), not clap's usage epilogue.
            let text = e.to_string();
            let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
            let first = lines.next().unwrap_or("error: invalid arguments");
            match lines.next().filter(|_| first.ends_with(':')) {
                Some(named) => eprintln!("{first} {named}"),
                None => eprintln!("{first}"),
            }
            return ExitCode::from(2);
        }
        Err(e) => {
            let _ = e.print(); // --help, --version
            return ExitCode::SUCCESS;
        }
    };
    match cli.command.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
