//! Command-line front end: argument types, one file per subcommand, exit codes.
//!
//! Exit codes: 0 on success (and on a broken pipe), 2 on bad input or usage, 1 on any other
//! failure; `check --exit-status` and `scene --exit-status` add 3 (unstable) and 4 (marginal). Data goes to stdout, messages and progress to stderr.

mod amax;
mod amax_certify;
mod args;
mod atomic;
mod boundary;
mod buzzfree;
mod check;
mod figure;
mod output;
mod passivity;
mod scene;
mod serve;
mod step;
mod table;
mod threads;

use std::process::ExitCode;

use std::io::{IsTerminal, Write};

use clap::{CommandFactory, Parser, Subcommand};

/// Exact stability boundaries for haptic rendering of virtual walls.
#[derive(Debug, Parser)]
#[command(name = "stabound", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Stop after this many seconds with exit status 1 and a message saying so (a file given
    /// with -o is then not written, as after Ctrl-C); for scripts and batch jobs whose
    /// requests may be slow (a fine tolerance, a long delay, many walls). When stderr is not
    /// a terminal the limit is 600 s unless given; 0 is no limit.
    #[arg(long = "time-limit", value_name = "SECONDS", global = true, value_parser = output::time_limit)]
    time_limit: Option<std::time::Duration>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Stability boundaries: closed curves around the stable region (CSV/JSON, SVG).
    Boundary(boundary::Args),
    /// Maximum stable stiffness alpha_max and the beta where it is reached.
    Amax(amax::Args),
    /// Lookup table of alpha_max over delta x d for firmware (csv, json, C, Rust).
    Table(table::Args),
    /// Test one wall for stability: verdict, spectral radius and roots.
    Check(check::Args),
    /// Check every wall of a scene file: verdict, margins, stable dampings, suggestion.
    #[command(long_about = scene::LONG_ABOUT)]
    Scene(scene::Args),
    /// Step responses from operator force to position, exact between samples (paper Fig. 11).
    Step(step::Args),
    /// Reproduce the paper's figures 5 to 11: SVG plus the CSV behind each.
    Figure(figure::Args),
    /// Passive region for a whole-sample delay and velocity filter, against the stable one.
    Passivity(passivity::Args),
    /// Explore one device in the browser: a local web page with its stable region, live.
    Serve(serve::Args),
    /// Shell completion script for SHELL on stdout (e.g. `stabound completions bash >
    /// ~/.local/share/bash-completion/completions/stabound`).
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// The manual page (roff) on stdout (e.g. `stabound man | man -l -`).
    Man,
}

/// Bad input found by the command line itself (not by the library): exit code 2.
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// Not a failure: the command finished and asks for this exit status (`check
/// --exit-status`); nothing is printed.
#[derive(Debug)]
pub struct ExitWith(pub u8);

impl std::fmt::Display for ExitWith {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "exit status {}", self.0)
    }
}

impl std::error::Error for ExitWith {}

/// Parses the command line and runs the subcommand.
pub fn run() -> anyhow::Result<()> {
    output::init()?;
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return Err(usage_error(e)),
    };
    // a computation run from a script or a batch job ends at a stated time; the explorer
    // serves until stopped, and the generated texts take no time
    let computes = !matches!(
        cli.command,
        Command::Serve(_) | Command::Completions { .. } | Command::Man
    );
    let unattended = computes && !std::io::stderr().is_terminal();
    let (limit, default) = match cli.time_limit {
        // exact: zero is the parsed spelling of "no limit"
        Some(given) => ((!given.is_zero()).then_some(given), false),
        None if unattended => (Some(output::DEFAULT_TIME_LIMIT), true),
        None => (None, false),
    };
    output::limited(limit, default, || dispatch(cli.command))
}

/// Runs the subcommand of `args` (the program name first) in this process, as the command
/// line would: how the explorer's exports write exactly the bytes of the command line.
pub fn run_args<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = Cli::try_parse_from(args).map_err(|e| UsageError(e.to_string()))?;
    dispatch(cli.command)
}

fn dispatch(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Check(a) => check::run(a),
        Command::Step(a) => step::run(a),
        Command::Amax(a) => amax::run(a),
        Command::Table(a) => table::run(a),
        Command::Scene(a) => scene::run(a),
        Command::Boundary(a) => boundary::run(a),
        Command::Figure(a) => figure::run(a),
        Command::Passivity(a) => passivity::run(a),
        Command::Serve(a) => serve::run(a),
        Command::Completions { shell } => {
            let mut buf = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "stabound", &mut buf);
            write_stdout(&buf)
        }
        Command::Man => {
            let mut buf = Vec::new();
            clap_mangen::Man::new(Cli::command()).render(&mut buf)?;
            write_stdout(&buf)
        }
    }
}

/// A clap error as one of ours: help and version as clap prints them (stdout, exit 0; bare
/// `stabound` shows its help on stderr, exit 2), a usage error as one line naming the
/// problem and where the help is (exit 2), like every other bad input.
fn usage_error(e: clap::Error) -> anyhow::Error {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit()
    }
    // clap's text: the message (possibly continued on indented lines), a blank line, a usage
    // block and a pointer to --help; keep the message and fold it onto one line
    let text = e.render().to_string();
    let message: Vec<&str> = text
        .lines()
        .take_while(|l| !l.trim().is_empty())
        .map(|l| l.trim().trim_start_matches("error:").trim())
        .filter(|l| !l.is_empty())
        .collect();
    let usage = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("Usage: "))
        .and_then(|u| u.split_whitespace().take(2).last())
        .filter(|sub| !sub.starts_with(['-', '<', '[']))
        .map_or("stabound --help".to_string(), |sub| {
            format!("stabound {sub} --help")
        });
    UsageError(format!("{}; see `{usage}`", message.join(" "))).into()
}

/// Writes generated text to stdout whole (a broken pipe exits 0 in [`report`]).
fn write_stdout(bytes: &[u8]) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)?;
    out.flush()?;
    Ok(())
}

/// Prints `err` as one line on stderr and picks the exit code.
pub fn report(err: &anyhow::Error) -> ExitCode {
    if let Some(ExitWith(code)) = err.downcast_ref::<ExitWith>() {
        return ExitCode::from(*code);
    }
    for cause in err.chain() {
        if let Some(io) = cause.downcast_ref::<std::io::Error>()
            && io.kind() == std::io::ErrorKind::BrokenPipe
        {
            return ExitCode::SUCCESS;
        }
    }
    let stopped = err
        .chain()
        .find_map(|c| match c.downcast_ref::<stabound::Error>() {
            Some(stabound::Error::Cancelled { time_limit }) => Some(*time_limit),
            _ => None,
        });
    match stopped {
        // an interrupt: the shell shows it; the exit status says so
        Some(None) => return ExitCode::from(output::INTERRUPTED as u8),
        Some(Some(seconds)) => {
            output::clear_line();
            eprintln!("error: {}", output::time_limit_message(seconds));
            return ExitCode::from(1);
        }
        None => {}
    }
    // one line, with any control character of a user-supplied name or path escaped
    // and numbers in exponent form where `{}` of an f64 wrote hundreds of digits
    let message = format!("{err:#}").replace('\n', " ");
    let message = stabound::export::text::numbers_shown(&message);
    eprintln!("error: {}", stabound::export::text::escape(&message));
    let bad_input = err.chain().any(|c| {
        c.downcast_ref::<UsageError>().is_some()
            || matches!(
                c.downcast_ref::<stabound::Error>(),
                Some(
                    stabound::Error::InvalidParameter { .. }
                        | stabound::Error::InvalidRequest(_)
                        | stabound::Error::Request(_)
                )
            )
    });
    ExitCode::from(if bad_input { 2 } else { 1 })
}
