//! Progress of a run on stderr: a bar with rate and ETA on a terminal (moved by every
//! machine as it finishes), a plain line every ~2 s otherwise, nothing with `--quiet`; the
//! first [`SHOWN_ERRORS`] failed machines are reported as they are found, the rest counted
//! (every one is in the summary's `status` and `message` columns).

use super::row::Counts;
use std::io::IsTerminal;
use std::time::Instant;

/// Failed machines printed as they are found; the others are counted, so a fleet with many
/// bad rows does not flood the terminal.
pub const SHOWN_ERRORS: u64 = 5;

/// Progress output: a bar on a terminal, plain lines otherwise, nothing with `--quiet`.
pub(super) enum Progress {
    Bar(indicatif::ProgressBar, Errors),
    Lines {
        total: u64,
        last: Instant,
        t0: Instant,
        errors: Errors,
    },
    Quiet,
}

/// Failed machines reported so far.
#[derive(Default)]
pub(super) struct Errors {
    seen: u64,
}

impl Progress {
    pub(super) fn new(total: u64, quiet: bool) -> Progress {
        if quiet {
            Progress::Quiet
        } else if std::io::stderr().is_terminal() {
            let pb = indicatif::ProgressBar::new(total);
            pb.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} machines  {rate}  ETA {eta}  {msg}",
                )
                .expect("valid template")
                // Machines per second as a whole number (indicatif's `per_sec` prints
                // `6,877.338/s`).
                .with_key(
                    "rate",
                    |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = write!(w, "{:.0} machines/s", s.per_sec());
                    },
                ),
            );
            Progress::Bar(pb, Errors::default())
        } else {
            Progress::Lines {
                total,
                last: Instant::now(),
                t0: Instant::now(),
                errors: Errors::default(),
            }
        }
    }
    /// A line said once, before the run (nothing with `--quiet`).
    pub(super) fn note(&self, line: &str) {
        match self {
            Progress::Bar(pb, _) => pb.println(line),
            Progress::Lines { .. } => eprintln!("{line}"),
            Progress::Quiet => {}
        }
    }

    /// Reports a failed machine: the first [`SHOWN_ERRORS`] in full, then one line saying
    /// that the rest are counted.
    pub(super) fn error(&mut self, m: &str) {
        let (pb, errors) = match self {
            Progress::Bar(pb, e) => (Some(&*pb), e),
            Progress::Lines { errors, .. } => (None, errors),
            Progress::Quiet => return,
        };
        errors.seen += 1;
        let line = match errors.seen {
            n if n <= SHOWN_ERRORS => format!("error {m}"),
            n if n == SHOWN_ERRORS + 1 => "error … further failed machines are counted, not shown: every one is in the summary (status, message)".to_string(),
            _ => return,
        };
        match pb {
            Some(pb) => pb.println(line),
            None => eprintln!("{line}"),
        }
    }
    /// A handle that moves the bar by one machine from any thread (`None` without a bar).
    pub(super) fn ticker(&self) -> Option<indicatif::ProgressBar> {
        match self {
            Progress::Bar(pb, _) => Some(pb.clone()),
            _ => None,
        }
    }
    /// Shows `done` machines and the counts (plain lines: every ~2 s, or now if `force`).
    pub(super) fn update(&mut self, done: u64, c: &Counts, force: bool) {
        match self {
            Progress::Bar(pb, _) => {
                pb.set_position(done);
                pb.set_message(format!("{} failed, {} skipped", c.failed, c.skipped));
            }
            Progress::Lines {
                total, last, t0, ..
            } => {
                if force || last.elapsed().as_secs_f64() >= 2.0 {
                    *last = Instant::now();
                    let t = t0.elapsed().as_secs_f64();
                    eprintln!(
                        "batch: {done}/{total} machines, {} failed, {} skipped, {:.0}/s, {:.1} s",
                        c.failed,
                        c.skipped,
                        done as f64 / t.max(1e-9),
                        t
                    );
                }
            }
            Progress::Quiet => {}
        }
    }
    /// Ends the bar.
    pub(super) fn finish(&self) {
        if let Progress::Bar(pb, _) = self {
            pb.finish();
        }
    }
}
