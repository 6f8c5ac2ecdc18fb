//! Progress of long runs on stderr: one `indicatif` bar style for every study (position,
//! total, rate, ETA), and the study's per-item lines above it.
//!
//! A study takes a `&Progress` from its binary and calls [`Progress::set_total`] once it knows
//! the amount of work, then [`Progress::step`] per finished item. Where stderr is not a
//! terminal (CI logs, redirects) the bar is not drawn and the lines are written plainly;
//! [`Progress::quiet`] (the binaries' `--quiet`) writes nothing. Progress never goes to
//! stdout, which carries the results.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar with per-item lines (see the module docs).
pub struct Progress {
    bar: ProgressBar,
    quiet: bool,
}

impl Progress {
    /// A bar labelled `label` on stderr (drawn only where stderr is a terminal); `quiet`
    /// silences both the bar and the lines.
    pub fn new(label: &str, quiet: bool) -> Progress {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr())
        };
        let template = format!(
            "{{spinner}} {label} [{{bar:40}}] {{pos}}/{{len}} {{per_sec}} eta {{eta}} {{msg}}"
        );
        bar.set_style(
            ProgressStyle::with_template(&template)
                .expect("valid template")
                .progress_chars("=> "),
        );
        Progress { bar, quiet }
    }

    /// No output at all (library callers and tests).
    pub fn quiet() -> Progress {
        Progress::new("", true)
    }

    /// The number of items the run will step through.
    pub fn set_total(&self, total: usize) {
        self.bar.set_length(total as u64);
    }

    /// Items already done (a resumed run).
    pub fn set_done(&self, done: usize) {
        self.bar.set_position(done as u64);
    }

    /// One item finished; `line` describes it (empty: no line).
    pub fn step(&self, line: &str) {
        self.note(line);
        self.bar.inc(1);
    }

    /// A line without finishing an item (e.g. "built scene …").
    pub fn note(&self, line: &str) {
        if self.quiet || line.is_empty() {
            return;
        }
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    /// A short status after the bar (e.g. the current item).
    pub fn message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    /// Removes the bar (the lines stay).
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
