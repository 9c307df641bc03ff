//! A one-line progress bar on stderr for runs longer than about a second: step, simulated
//! time, steps per second, time left and iterations per step. Off when stderr is not a
//! terminal (CI logs, pipes) or with `--quiet`.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// The bar appears once a run has taken this long.
const DELAY: Duration = Duration::from_secs(1);
/// And is redrawn at most this often.
const REDRAW: Duration = Duration::from_millis(200);
const WIDTH: usize = 24;

pub(crate) struct Progress {
    enabled: bool,
    start: Instant,
    last: Option<Instant>,
    total: usize,
    iterations: usize,
    shown: bool,
}

impl Progress {
    pub fn new(total_steps: usize, quiet: bool) -> Progress {
        Progress {
            enabled: !quiet && std::io::stderr().is_terminal(),
            start: Instant::now(),
            last: None,
            total: total_steps.max(1),
            iterations: 0,
            shown: false,
        }
    }

    /// After a step: `step` steps done, at simulated time `time`, with `iterations` in it.
    pub fn step(&mut self, step: usize, time: f64, iterations: usize) {
        self.iterations += iterations;
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        let elapsed = now - self.start;
        if elapsed < DELAY || self.last.is_some_and(|l| now - l < REDRAW) {
            return;
        }
        self.last = Some(now);
        self.shown = true;
        eprint!(
            "\r{}",
            line(step, self.total, time, elapsed, self.iterations)
        );
        let _ = std::io::stderr().flush();
    }

    /// Clears the bar (if it was drawn).
    pub fn finish(&mut self) {
        if self.shown {
            eprint!("\r{:width$}\r", "", width = 100);
            let _ = std::io::stderr().flush();
            self.shown = false;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// The bar's text for `step` of `total` after `elapsed`.
pub fn line(step: usize, total: usize, time: f64, elapsed: Duration, iterations: usize) -> String {
    let done = step.min(total) as f64 / total as f64;
    let filled = (done * WIDTH as f64).round() as usize;
    let rate = step as f64 / elapsed.as_secs_f64().max(1e-9);
    let left = (total - step.min(total)) as f64 / rate.max(1e-9);
    format!(
        "[{}{}] step {step}/{total} t = {time:.4e}  {rate:.1} steps/s  {} left  {:.1} it/step",
        "#".repeat(filled),
        " ".repeat(WIDTH - filled),
        clock(left),
        iterations as f64 / step.max(1) as f64
    )
}

/// Seconds as m:ss (or h:mm:ss).
fn clock(seconds: f64) -> String {
    let s = seconds.round() as u64;
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_shows_the_fraction_the_rate_and_the_time_left() {
        let l = line(100, 400, 0.01, Duration::from_secs(2), 350);
        assert!(
            l.starts_with(&format!("[{}{}]", "#".repeat(6), " ".repeat(18))),
            "{l}"
        );
        assert!(l.contains("step 100/400"), "{l}");
        assert!(l.contains("50.0 steps/s"), "{l}");
        // 300 steps at 50 per second
        assert!(l.contains("0:06 left"), "{l}");
        assert!(l.contains("3.5 it/step"), "{l}");
        assert_eq!(clock(3725.0), "1:02:05");
    }
}
