//! Plain progress lines for runs whose stderr is not a terminal (batch jobs, logs, pipes; README,
//! "Commands"). It is not the terminal's progress bar (the CLI's, `main.rs`), and it reads no
//! frame's statistics: only how many frames and entries are done.
//!
//! A terminal gets the CLI's progress bar; anything else gets [`LineProgress`]: one line every
//! [`PROGRESS_LINE_INTERVAL`] of wall time at most (decided: 10 s — a ten-minute run writes
//! about sixty lines, a quickstart none but the last), each saying the frames done of the total
//! over every entry, the entries finished, the time elapsed and an estimate of the time left
//! (the frames left at the mean rate so far), and one last line when the point is done. A run
//! that is killed therefore leaves in its log how far it got. Sweep points start a new count.
//!
//! Lines look like
//! `progress: 1 600/4 000 frames (40%), 1/10 entries done, 12 s elapsed, about 18 s left`.
//! Nothing here reads the clock but `advance` and `finish`; the writer is any `Write`, so tests
//! collect the lines in memory.

use crate::edge::session::ProgressSink;
use std::io::Write;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The least wall time between two progress lines.
pub const PROGRESS_LINE_INTERVAL: Duration = Duration::from_secs(10);

/// Writes a progress line at most every `interval` (see the module doc).
pub struct LineProgress {
    interval: Duration,
    state: Mutex<LineState>,
}

struct LineState {
    out: Box<dyn Write + Send>,
    total_frames: u64,
    frames_done: u64,
    entries: usize,
    entries_done: usize,
    started: Instant,
    last_line: Instant,
}

impl LineProgress {
    /// Progress lines on stderr every [`PROGRESS_LINE_INTERVAL`].
    pub fn to_stderr() -> LineProgress {
        LineProgress::new(Box::new(std::io::stderr()), PROGRESS_LINE_INTERVAL)
    }

    /// Progress lines into `out`, at most one per `interval` (zero: one per report).
    pub fn new(out: Box<dyn Write + Send>, interval: Duration) -> LineProgress {
        let now = Instant::now();
        LineProgress {
            interval,
            state: Mutex::new(LineState {
                out,
                total_frames: 0,
                frames_done: 0,
                entries: 0,
                entries_done: 0,
                started: now,
                last_line: now,
            }),
        }
    }

    fn state(&self) -> std::sync::MutexGuard<'_, LineState> {
        self.state
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl LineState {
    fn write_line(&mut self, now: Instant) {
        let elapsed = now.duration_since(self.started).as_secs_f64();
        let left = if self.frames_done > 0 && self.total_frames >= self.frames_done {
            let rate = elapsed / self.frames_done as f64;
            format!(
                ", about {} left",
                seconds((self.total_frames - self.frames_done) as f64 * rate)
            )
        } else {
            String::new()
        };
        let percent = (100 * self.frames_done)
            .checked_div(self.total_frames)
            .unwrap_or(100);
        // A progress line that cannot be written is not worth failing the run for.
        let _ = writeln!(
            self.out,
            "progress: {}/{} frames ({percent}%), {}/{} entries done, {} elapsed{left}",
            self.frames_done,
            self.total_frames,
            self.entries_done,
            self.entries,
            seconds(elapsed),
        );
        let _ = self.out.flush();
        self.last_line = now;
    }
}

/// Seconds as `12 s`, or `3 min 05 s` from a minute on.
fn seconds(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else {
        format!("{} min {:02} s", s / 60, s % 60)
    }
}

impl ProgressSink for LineProgress {
    fn start(&self, total_frames: u64) {
        let mut state = self.state();
        let now = Instant::now();
        state.total_frames = total_frames;
        state.frames_done = 0;
        state.entries_done = 0;
        state.started = now;
        state.last_line = now;
    }

    fn entries(&self, count: usize) {
        self.state().entries = count;
    }

    fn advance(&self, frames: u64) {
        let mut state = self.state();
        state.frames_done += frames;
        let now = Instant::now();
        if now.duration_since(state.last_line) >= self.interval {
            state.write_line(now);
        }
    }

    fn entry_finished(&self) {
        self.state().entries_done += 1;
    }

    fn finish(&self) {
        let mut state = self.state();
        state.write_line(Instant::now());
    }

    fn point(&self, index: usize, count: usize, choice: &str) {
        let mut state = self.state();
        let _ = writeln!(state.out, "sweep point {}/{count}: {choice}", index + 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// A writer whose bytes the test can read back.
    #[derive(Clone, Default)]
    struct Shared(Arc<Mutex<Vec<u8>>>);

    impl Write for Shared {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    fn lines(shared: &Shared) -> Vec<String> {
        String::from_utf8(shared.0.lock().unwrap().clone())
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect()
    }

    #[test]
    fn every_line_says_frames_entries_elapsed_and_time_left() {
        let shared = Shared::default();
        let progress = LineProgress::new(Box::new(shared.clone()), Duration::ZERO);
        progress.entries(2);
        progress.start(200);
        progress.advance(50);
        progress.entry_finished();
        progress.advance(50);
        progress.finish();
        let lines = lines(&shared);
        assert_eq!(lines.len(), 3, "{lines:?}");
        assert!(
            lines[0].starts_with("progress: 50/200 frames (25%), 0/2 entries done, "),
            "{}",
            lines[0]
        );
        assert!(lines[0].contains(" elapsed, about "), "{}", lines[0]);
        assert!(lines[0].ends_with(" left"), "{}", lines[0]);
        assert!(
            lines[2].starts_with("progress: 100/200 frames (50%), 1/2 entries done, "),
            "{}",
            lines[2]
        );
    }

    #[test]
    fn no_line_before_the_interval_has_passed_but_always_one_at_the_end() {
        let shared = Shared::default();
        let progress = LineProgress::new(Box::new(shared.clone()), Duration::from_secs(3600));
        progress.entries(1);
        progress.start(32);
        progress.advance(16);
        progress.advance(16);
        progress.entry_finished();
        assert!(lines(&shared).is_empty());
        progress.finish();
        let lines = lines(&shared);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].starts_with("progress: 32/32 frames (100%), 1/1 entries done, "));
    }

    #[test]
    fn long_times_are_written_in_minutes_and_seconds() {
        assert_eq!(seconds(4.4), "4 s");
        assert_eq!(seconds(185.0), "3 min 05 s");
    }
}
