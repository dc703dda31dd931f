//! Progress of a long run (fracture, dynamics) on stderr: what the command
//! line shows of the [`dhpd::Progress`] its observer receives.
//!
//! On a terminal: a bar with the position, the run's own numbers and an ETA,
//! drawn after 2 s (short runs stay silent). Elsewhere (a batch
//! job, a pipe, a log file) a bar cannot be drawn, so a line is printed every
//! [`PROGRESS_SECONDS`], e.g.
//!
//! ```text
//! dhpd: progress: step 41200/100000 (41.2 %), t = 4.12e-3 s, bonds broken 18; 0:30:02 elapsed, ETA 0:42:51
//! ```
//!
//! The ETA extrapolates the elapsed time by the fraction done (of the steps,
//! or of the maximal load factor). The environment variable
//! `DHPD_PROGRESS_SECONDS` overrides the interval (`0`: a line at every
//! update, at most one a millisecond; the tests use it).

use dhpd::Progress;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Runs shorter than this show no bar on a terminal.
const QUIET_FOR: Duration = Duration::from_secs(2);

/// Seconds between two progress lines when stderr is not a terminal.
pub const PROGRESS_SECONDS: f64 = 30.0;

/// Environment variable overriding [`PROGRESS_SECONDS`].
pub const PROGRESS_SECONDS_VAR: &str = "DHPD_PROGRESS_SECONDS";

/// A terminal draws a bar; other streams get a line at an interval.
enum Mode {
    Bar(Option<ProgressBar>),
    Lines { interval: Duration, next: Duration },
}

/// The progress display of one run.
pub struct Display {
    mode: Mode,
    start: Instant,
    /// Number of steps when known (a bar, and `step k/n` in a line).
    total: Option<u64>,
    /// What a position counts (`step`, `event`).
    unit: &'static str,
}

impl Display {
    /// Progress of `total` positions (None: unknown) counted as `unit`.
    fn new(total: Option<u64>, unit: &'static str) -> Self {
        let mode = if std::io::stderr().is_terminal() {
            Mode::Bar(None)
        } else {
            let interval = Duration::from_secs_f64(interval_seconds());
            Mode::Lines {
                interval,
                next: interval,
            }
        };
        Self {
            mode,
            start: Instant::now(),
            total,
            unit,
        }
    }

    /// Reports `position` with the run's own numbers (`message`, built only
    /// when shown) and the fraction of the run done (for the ETA).
    fn update(&mut self, position: u64, fraction: f64, message: impl FnOnce() -> String) {
        let elapsed = self.start.elapsed();
        match &mut self.mode {
            Mode::Lines { interval, next } => {
                if elapsed < *next {
                    return;
                }
                while *next <= elapsed {
                    *next += (*interval).max(Duration::from_millis(1));
                }
                let at = match self.total {
                    Some(n) => format!(
                        "{} {position}/{n} ({:.1} %)",
                        self.unit,
                        100.0 * position as f64 / n.max(1) as f64
                    ),
                    None => format!("{} {position}", self.unit),
                };
                let eta = if fraction > 0.0 && fraction.is_finite() {
                    clock(elapsed.as_secs_f64() * (1.0 - fraction.min(1.0)) / fraction)
                } else {
                    "unknown".into()
                };
                eprintln!(
                    "dhpd: progress: {at}, {}; {} elapsed, ETA {eta}",
                    message(),
                    clock(elapsed.as_secs_f64())
                );
            }
            Mode::Bar(bar) => {
                if elapsed < QUIET_FOR {
                    return;
                }
                let (total, unit) = (self.total, self.unit);
                let bar = bar.get_or_insert_with(|| {
                    let (bar, template) = match total {
                        Some(n) => (
                            ProgressBar::new(n),
                            format!(
                                "{{elapsed_precise}} [{{bar:30}}] {unit} {{pos}}/{{len}}, ETA {{eta}} | {{msg}}"
                            ),
                        ),
                        None => (
                            ProgressBar::new_spinner(),
                            format!("{{elapsed_precise}} {{spinner}} {unit} {{pos}} | {{msg}}"),
                        ),
                    };
                    if let Ok(style) = ProgressStyle::with_template(&template) {
                        bar.set_style(style.progress_chars("=> "));
                    }
                    bar.with_elapsed(elapsed)
                });
                bar.set_position(position);
                bar.set_message(message());
            }
        }
    }

    /// Clears the bar (lines need no ending).
    pub fn finish(&mut self) {
        if let Mode::Bar(bar) = &mut self.mode {
            if let Some(bar) = bar.take() {
                bar.finish_and_clear();
            }
        }
    }
}

/// Shows `progress` on `display` (created at the first report of a run): every
/// record of a fracture run, every 16th step of an explicit run (the clock is
/// read once per 16 steps).
pub fn show(display: &mut Option<Display>, progress: &Progress) {
    match *progress {
        Progress::Fracture {
            step,
            steps,
            load_factor,
            max_load_factor,
            broken,
        } => {
            let unit = if steps.is_some() { "step" } else { "event" };
            display
                .get_or_insert_with(|| Display::new(steps.map(|n| n as u64), unit))
                .update(step as u64, load_factor / max_load_factor, || {
                    format!(
                        "load factor {load_factor:.4e} of {max_load_factor:.4e}, bonds broken {broken}"
                    )
                });
        }
        Progress::Dynamics {
            step,
            steps,
            time,
            broken,
        } if step % 16 == 0 => {
            display
                .get_or_insert_with(|| Display::new(Some(steps as u64), "step"))
                .update(step as u64, step as f64 / steps.max(1) as f64, || {
                    format!("t = {time:.4e} s, bonds broken {broken}")
                });
        }
        Progress::Relaxation { step, steps } if step % 16 == 0 => {
            display
                .get_or_insert_with(|| Display::new(Some(steps as u64), "step"))
                .update(step as u64, step as f64 / steps.max(1) as f64, || {
                    "dynamic relaxation (ends at its tolerance, at the latest at the last step)"
                        .to_string()
                });
        }
        _ => {}
    }
}

/// The interval between progress lines: [`PROGRESS_SECONDS`], or
/// `DHPD_PROGRESS_SECONDS` when it holds a number of seconds ≥ 0 (else a
/// warning, and the default).
fn interval_seconds() -> f64 {
    let Some(value) = std::env::var_os(PROGRESS_SECONDS_VAR) else {
        return PROGRESS_SECONDS;
    };
    let text = value.to_string_lossy();
    match text.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && s >= 0.0 => s,
        _ => {
            eprintln!(
                "warning: {PROGRESS_SECONDS_VAR} = \"{}\" is not a number of seconds ≥ 0; \
                 progress lines every {PROGRESS_SECONDS} s",
                dhpd::error::echo(&text)
            );
            PROGRESS_SECONDS
        }
    }
}

/// `h:mm:ss` of a duration in seconds.
fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).min(1e9).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

#[cfg(test)]
mod tests {
    use super::clock;

    #[test]
    fn clock_shows_hours_minutes_seconds() {
        assert_eq!(clock(0.4), "0:00:00");
        assert_eq!(clock(3723.0), "1:02:03");
        assert_eq!(clock(f64::INFINITY), "277777:46:40");
    }
}
