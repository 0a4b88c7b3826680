//! Progress of a run on stderr: a bar with rate and ETA on a terminal, a plain line every
//! ~2 s otherwise, nothing with `--quiet`; failed machines are reported as they are found.

use super::row::Counts;
use std::io::IsTerminal;
use std::time::Instant;

/// Progress output: a bar on a terminal, plain lines otherwise, nothing with `--quiet`.
pub(super) enum Progress {
    Bar(indicatif::ProgressBar),
    Lines {
        total: u64,
        last: Instant,
        t0: Instant,
    },
    Quiet,
}

impl Progress {
    pub(super) fn new(total: u64, quiet: bool) -> Progress {
        if quiet {
            Progress::Quiet
        } else if std::io::stderr().is_terminal() {
            let pb = indicatif::ProgressBar::new(total);
            pb.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} machines  {per_sec}  ETA {eta}  {msg}",
                )
                .expect("valid template"),
            );
            Progress::Bar(pb)
        } else {
            Progress::Lines {
                total,
                last: Instant::now(),
                t0: Instant::now(),
            }
        }
    }
    /// Reports a failed machine.
    pub(super) fn error(&self, m: &str) {
        match self {
            Progress::Bar(pb) => pb.println(format!("error {m}")),
            Progress::Lines { .. } => eprintln!("error {m}"),
            Progress::Quiet => {}
        }
    }
    /// Shows `done` machines and the counts (plain lines: every ~2 s, or now if `force`).
    pub(super) fn update(&mut self, done: u64, c: &Counts, force: bool) {
        match self {
            Progress::Bar(pb) => {
                pb.set_position(done);
                pb.set_message(format!("{} failed, {} skipped", c.failed, c.skipped));
            }
            Progress::Lines { total, last, t0 } => {
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
        if let Progress::Bar(pb) = self {
            pb.finish();
        }
    }
}
