//! The one shape of a study and the one entry every study binary goes through.
//!
//! A study declares its flags, its configuration and its record, and five steps: `config`
//! (flags → a validated configuration, at the edge), `run` (configuration → record; never
//! prints), `save` / `load` (the record's files in `--out`, with provenance), `figures`
//! (record → drawings) and `report` (record → the text printed on stdout). [`main`] owns what
//! every binary shares:
//!
//! - `--out DIR` (default [`Study::DEFAULT_OUT`]): where the record and `figures/` go;
//! - `--render-only`: load the saved record and redraw, without running;
//! - `--json`: print the record as JSON (one writer, [`crate::provenance::json_text`])
//!   instead of the report;
//! - `--quiet`: no progress bar or progress lines on stderr;
//! - `--resume` (only where [`Study::RESUMABLE`]): reuse the checkpoints of an interrupted
//!   run of the same build and configuration;
//! - the exit codes of [`crate::error::run_main`]: 0, 2 for an error (one line on stderr), 3
//!   for a run outside its model, 4 for a run in which a method failed on every scene it ran
//!   on ([`Study::failure`]; its record is written and its report printed first).
//!
//! After a run the record is saved and read back, so that the figures, the report and the
//! JSON come from the saved files exactly as with `--render-only` (where only the report is
//! printed after a run, `--no-figures` without `--json`, a study may read back less of what
//! it has just written: `load_report`; `--render-only` reads the whole record).
//!
//! A binary is then `fn main() -> ExitCode { study::main::<TheStudy>() }`. Each study's
//! module has the same files: `mod.rs` (configuration, record and run), `figures.rs` and
//! `report.rs`.

use crate::error::Result;
use crate::plot::{render_panels, Figure};
use crate::progress::Progress;
use crate::provenance::Provenance;
use clap::{Args, CommandFactory, FromArgMatches, Parser};
use serde::{de::DeserializeOwned, Serialize};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// One image: its panels, laid out `cols` per row in a canvas of `size` pixels; written as
/// `<name>.{png,svg}` in [`Study::FIGURES_DIR`] under `--out`.
#[derive(Clone, Debug)]
pub struct Drawing {
    /// File stem.
    pub name: String,
    /// The panels (one figure: the whole image).
    pub panels: Vec<Figure>,
    /// Panels per row.
    pub cols: usize,
    /// Canvas size (width, height) in pixels.
    pub size: (u32, u32),
}

impl Drawing {
    /// One figure drawn at its own size.
    pub fn single(name: impl Into<String>, fig: Figure) -> Drawing {
        let size = fig.size;
        Drawing {
            name: name.into(),
            panels: vec![fig],
            cols: 1,
            size,
        }
    }

    /// Renders into `dir` (`<dir>/<name>.png` and `.svg`).
    pub fn render(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        render_panels(&self.panels, self.cols, &dir.join(&self.name), self.size)
    }
}

/// The saved record of a study whose record is its rows: `<name>.json` holds this (the run's
/// provenance with its configuration, and the rows), `<name>.csv` the rows.
#[derive(Serialize, serde::Deserialize)]
pub struct RowsDocument<R> {
    /// [`crate::provenance::Provenance::record`] of the run.
    pub provenance: serde_json::Value,
    /// The rows.
    pub rows: Vec<R>,
}

/// Writes `out/<name>.json` ([`RowsDocument`], `provenance` recording `fields`) and
/// `out/<name>.csv`, `name` the provenance's experiment (the study's name).
pub fn save_rows<R: Serialize + Clone>(
    out: &Path,
    provenance: &Provenance,
    fields: serde_json::Value,
    rows: &[R],
) -> Result<()> {
    use crate::provenance::{write_csv, write_json};
    std::fs::create_dir_all(out).map_err(|e| crate::Error::io(out.display(), e))?;
    let name = provenance.experiment.as_str();
    let doc = RowsDocument {
        provenance: provenance.record(fields),
        rows: rows.to_vec(),
    };
    write_json(&out.join(format!("{name}.json")), &doc)?;
    write_csv(&out.join(format!("{name}.csv")), rows)
}

/// The rows of `out/<name>.json` ([`save_rows`]).
pub fn load_rows<R: DeserializeOwned>(out: &Path, name: &str) -> Result<Vec<R>> {
    let doc: RowsDocument<R> = crate::provenance::read_json(&out.join(format!("{name}.json")))?;
    Ok(doc.rows)
}

/// What a run gets besides its configuration.
pub struct RunContext<'a> {
    /// Progress on stderr (silent with `--quiet`).
    pub progress: &'a Progress,
    /// The output directory (for checkpoints).
    pub out: &'a Path,
    /// `--resume` was given (only for [`Study::RESUMABLE`] studies).
    pub resume: bool,
    /// `--force` was given: replace what the run would otherwise refuse to overwrite.
    pub force: bool,
    /// `--quiet` was given (for a study that draws its own progress).
    pub quiet: bool,
    /// The run's provenance, made once by the entry (the study's name, the commit, the crate
    /// versions, the command line): every record the study writes carries it.
    pub provenance: &'a Provenance,
}

/// One study (module doc).
pub trait Study {
    /// The binary's name.
    const NAME: &'static str;
    /// One line for `--help`.
    const ABOUT: &'static str;
    /// The progress bar's label.
    const PROGRESS: &'static str;
    /// `--out`'s default.
    const DEFAULT_OUT: &'static str;
    /// Whether the study checkpoints and takes `--resume`.
    const RESUMABLE: bool = false;
    /// Where under `--out` the drawings go (`""`: `--out` itself).
    const FIGURES_DIR: &'static str = "figures";
    /// Whether the study keeps a record in `--out` (`false`: a one-shot command such as
    /// `solve`, which refuses `--out` and `--render-only` with one line).
    const SAVES: bool = true;
    /// The study's own flags (clap).
    type Flags: Args;
    /// The validated configuration (its JSON identifies a run in `--out`:
    /// [`super::out_guard`]).
    type Config: Serialize;
    /// What a run returns and the saved files hold.
    type Record: Serialize + DeserializeOwned;

    /// Flags → configuration, validated (an error names the flag and the bad value).
    fn config(flags: &Self::Flags) -> Result<Self::Config>;
    /// Runs the study.
    fn run(cfg: &Self::Config, ctx: &RunContext) -> Result<Self::Record>;
    /// Writes the record's files into `out`, with the entry's `provenance` where the record
    /// does not already carry it.
    fn save(
        out: &Path,
        cfg: &Self::Config,
        record: &Self::Record,
        provenance: &Provenance,
    ) -> Result<()>;
    /// Reads the record back from `out`.
    fn load(out: &Path) -> Result<Self::Record>;
    /// Reads back, after a run, what [`Study::report`] alone needs (`--no-figures` without
    /// `--json`): the whole record unless the study reads less.
    fn load_report(out: &Path) -> Result<Self::Record> {
        Self::load(out)
    }
    /// The record's drawings.
    fn figures(record: &Self::Record) -> Result<Vec<Drawing>>;
    /// The text printed on stdout (without `--json`).
    fn report(record: &Self::Record) -> String;
    /// Text after the options in `--help` (exit statuses, units).
    fn after_help() -> String {
        String::new()
    }
    /// An output directory the configuration names itself (`sweep merge OUT ...`), in place of
    /// `--out`.
    fn out_override(_cfg: &Self::Config) -> Option<PathBuf> {
        None
    }
    /// Whether the entry guards `--out` for this run ([`super::out_guard`]); `false` for a
    /// run that checks its output folder itself (`sweep merge`).
    fn guards_out(_cfg: &Self::Config) -> bool {
        true
    }
    /// The message of exit status 4 ([`crate::Error::MethodFailed`]) where the record says a
    /// method failed on every scene it ran on ([`super::outcomes::Tally::all_failed`]); the
    /// report (or JSON) and the figures come first. `None` by default.
    fn failure(_record: &Self::Record) -> Option<String> {
        None
    }
    /// What `--json` prints: the record by default.
    fn json(record: &Self::Record) -> Result<String> {
        crate::provenance::json_text(Self::NAME, record)
    }
}

/// The flags every study binary shares, around the study's own.
#[derive(Parser, Debug)]
struct Cli<F: Args> {
    #[command(flatten)]
    flags: F,
    /// Output directory.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Redraw the figures (and print the report) from the saved record, without running.
    #[arg(long)]
    render_only: bool,
    /// Print the record as JSON on stdout instead of the report.
    #[arg(long)]
    json: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
    /// Reuse the checkpoints an interrupted run of the same build and options left in `--out`.
    #[arg(long, hide = true)]
    resume: bool,
    /// Replace what --out holds from another run (its data files removed first; never
    /// mixed); for solve, overwrite the files of --write-system.
    #[arg(long)]
    force: bool,
    /// Skip the figures.
    #[arg(long, global = true)]
    no_figures: bool,
}

/// The `main` of a study binary (module doc).
pub fn main<S: Study>() -> ExitCode {
    // faer's dense kernels split their work over its global thread pool by default, and the
    // rounding then depends on the number of threads (`solve --method optimal` differed from
    // the sweep's row in the 8th digit on two cores). Every study parallelises over its own
    // jobs instead, so the library's kernels run sequentially: the same bits for any thread
    // count.
    faer::set_global_parallelism(faer::Par::Seq);
    let mut cmd = Cli::<S::Flags>::command()
        .name(S::NAME)
        .bin_name(S::NAME)
        .about(S::ABOUT)
        .version(crate::provenance::VERSION)
        .args_conflicts_with_subcommands(true);
    let after = S::after_help();
    if !after.is_empty() {
        cmd = cmd.after_help(after);
    }
    if S::SAVES {
        cmd = cmd.mut_arg("out", |a| a.default_value(S::DEFAULT_OUT));
    } else {
        for hidden in ["out", "render_only", "no_figures"] {
            cmd = cmd.mut_arg(hidden, |a| a.hide(true));
        }
    }
    if S::RESUMABLE {
        cmd = cmd.mut_arg("resume", |a| a.hide(false));
    }
    let matches = match cmd.try_get_matches() {
        Ok(m) => m,
        Err(e) => return command_line_error(e),
    };
    let cli = match Cli::<S::Flags>::from_arg_matches(&matches) {
        Ok(c) => c,
        Err(e) => return command_line_error(e),
    };
    crate::error::run_main(std::panic::AssertUnwindSafe(move || entry::<S>(&cli)))
}

/// A command line clap refuses: `--help` and `--version` print as clap prints them (exit 0);
/// an error becomes one line on stderr — clap's message with its possible values, without
/// the usage lines — and exit status 2, as every other bad input.
fn command_line_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit()
    }
    let text = e.render().to_string();
    let line = text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:"))
        .filter(|l| !l.is_empty() && !l.starts_with("For more information"))
        .collect::<Vec<_>>()
        .join(" ");
    eprintln!("{line}");
    ExitCode::from(2)
}

fn entry<S: Study>(cli: &Cli<S::Flags>) -> Result<()> {
    let out = cli
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(S::DEFAULT_OUT));
    if cli.resume && !S::RESUMABLE {
        return Err(crate::Error::unsupported(
            "--resume",
            format!(
                "a study that keeps checkpoints ({} keeps no checkpoints)",
                S::NAME
            ),
        ));
    }
    if !S::SAVES && (cli.out.is_some() || cli.render_only) {
        return Err(crate::Error::unsupported(
            "--out/--render-only",
            format!("a study that keeps a record ({} keeps no record)", S::NAME),
        ));
    }
    if S::SAVES && out.exists() && !out.is_dir() {
        return Err(crate::Error::bad_file(
            out.display(),
            "--out names a file; it must be a folder (created where missing)",
        ));
    }
    let (record, out, guard) = if cli.render_only {
        let record = S::load(&out).map_err(|e| match e {
            crate::Error::Io { .. } => crate::Error::bad_file(
                out.display(),
                format!(
                    "no saved {} record to redraw ({e}); run without --render-only first",
                    S::NAME
                ),
            ),
            e => e,
        })?;
        (record, out, None)
    } else {
        let cfg = S::config(&cli.flags)?;
        let out = S::out_override(&cfg).unwrap_or(out);
        let guard = if S::SAVES && S::guards_out(&cfg) {
            let config = serde_json::to_value(&cfg).map_err(|e| {
                crate::Error::Numerical(format!("cannot write the configuration as JSON: {e}"))
            })?;
            let who = super::out_guard::Claimant {
                study: S::NAME,
                config,
                figures_dir: S::FIGURES_DIR,
                resumable: S::RESUMABLE,
            };
            Some(super::out_guard::claim(&out, who, cli.resume, cli.force)?)
        } else {
            None
        };
        if S::RESUMABLE {
            resume_hint_on_interrupt(&out);
        }
        let progress = Progress::new(S::PROGRESS, cli.quiet);
        let provenance = Provenance::new(S::NAME);
        let ctx = RunContext {
            progress: &progress,
            out: &out,
            resume: cli.resume,
            force: cli.force,
            quiet: cli.quiet,
            provenance: &provenance,
        };
        let record = match S::run(&cfg, &ctx) {
            Ok(r) => r,
            Err(e) => {
                if let Some(g) = guard {
                    g.abandon();
                }
                return Err(e);
            }
        };
        progress.finish();
        if S::SAVES {
            // What follows is drawn and printed from the saved files, as --render-only would.
            S::save(&out, &cfg, &record, &provenance)?;
            // Where only the report is printed, the study may read back less of what it
            // has just written (`--render-only` always reads the whole record).
            let record = if cli.no_figures && !cli.json {
                S::load_report(&out)?
            } else {
                S::load(&out)?
            };
            (record, out, guard)
        } else {
            (record, out, guard)
        }
    };
    if S::SAVES && !cli.no_figures {
        let dir = out.join(S::FIGURES_DIR);
        let mut files = 0;
        for d in S::figures(&record)? {
            files += d.render(&dir)?.len();
        }
        if !cli.quiet {
            eprintln!("rendered {files} figure files into {}", dir.display());
        }
    }
    if let Some(g) = guard {
        g.finish()?;
    }
    if cli.json {
        println!("{}", S::json(&record)?);
    } else {
        print!("{}", S::report(&record));
    }
    match S::failure(&record) {
        Some(msg) => Err(crate::Error::MethodFailed(msg)),
        None => Ok(()),
    }
}

/// Ctrl-C (SIGINT) during the run of a resumable study: one line on stderr saying
/// where the finished part is kept and the command that finishes the run (the same command
/// with `--resume`), then exit status 130. What a killed run leaves is what `--resume`
/// expects (rows flushed per unit of work, a torn last line repaired).
fn resume_hint_on_interrupt(out: &Path) {
    let quote = |a: String| {
        if !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
        {
            a
        } else {
            format!("'{}'", a.replace('\'', r"'\''"))
        }
    };
    let mut args: Vec<String> = std::env::args().map(quote).collect();
    if !args.iter().any(|a| a == "--resume") {
        args.push("--resume".into());
    }
    let (cmd, out) = (args.join(" "), out.display().to_string());
    // A second handler (a library caller's own) is kept: then no hint.
    let _ = ctrlc::try_set_handler(move || {
        eprintln!("\ninterrupted: what finished is kept in {out}; finish the run with: {cmd}");
        std::process::exit(130);
    });
}
