//! What a run tells its caller while it goes: frames done, entries done, sweep points, tuning
//! probes and notices, through a [`ProgressSink`] (the CLI's progress bar or plain lines, or
//! [`NoProgress`]). Not how progress is shown: that is the CLI's (`main.rs`) and
//! `edge::progress`'s.
//!
//! **Frames in batches of 16.** Every pass of an entry reports its frames done 16 at a time (and
//! at its last frame) through `FrameProgress`.
//!
//! **A word before a large run.** After an entry's first frame, a mesh of
//! [`LARGE_MESH_TRIANGLES`] or more, or a flight projected at that frame's pace to take
//! [`LONG_RUN_SECONDS`] or more, is announced ([`large_work_notice`]) with what stops such a run
//! (`limits.max_triangles`) and how to make a shorter probe (`--frames N`).

/// Receives progress from every running algorithm at once (so it must be `Sync`).
pub trait ProgressSink: Sync {
    /// The total number of frames all entries will run.
    fn start(&self, total_frames: u64);
    /// `frames` more frames are done.
    fn advance(&self, frames: u64);
    fn finish(&self);
    /// The number of algorithm entries about to run (before `start`).
    fn entries(&self, count: usize) {
        let _ = count;
    }
    /// One more entry has run all its frames.
    fn entry_finished(&self) {}
    /// Point `index` of `count` of the experiment's top-level sweep is about to load and run.
    fn point(&self, index: usize, count: usize, choice: &str) {
        let _ = (index, count, choice);
    }
    /// A tuned entry's probe is done: one line (see `edge::output::tuning::probe_line`).
    fn tuning(&self, line: &str) {
        eprintln!("{line}");
    }
    /// Something the user should know while the run goes on (see [`large_work_notice`]).
    fn notice(&self, message: &str) {
        eprintln!("note: {message}");
    }
}

/// A first frame with this many triangles is worth a word before the rest of the run.
pub const LARGE_MESH_TRIANGLES: u64 = 1_000_000;
/// A flight projected to take this long (seconds, from its first frame) is worth a word.
pub const LONG_RUN_SECONDS: f64 = 300.0;

/// What to tell the user after an entry's first frame when its work looks large: a mesh of
/// [`LARGE_MESH_TRIANGLES`] or more, or a flight projected at the first frame's pace to take
/// [`LONG_RUN_SECONDS`] or more. `None` when neither.
pub fn large_work_notice(
    label: &str,
    triangles: u64,
    first_frame_seconds: f64,
    n_frames: u64,
    max_triangles: u64,
) -> Option<String> {
    let projected = first_frame_seconds * n_frames as f64;
    if triangles < LARGE_MESH_TRIANGLES && projected < LONG_RUN_SECONDS {
        return None;
    }
    let duration = if projected >= 3600.0 {
        format!("{:.1} h", projected / 3600.0)
    } else if projected >= 60.0 {
        format!("{:.0} min", projected / 60.0)
    } else {
        format!("{projected:.0} s")
    };
    Some(format!(
        "entry '{label}': frame 0 has {triangles} triangles and took {first_frame_seconds:.2} s; \
         at that pace its {n_frames} frames take about {duration} (incremental algorithms are \
         usually faster after their first frame). A frame over {max_triangles} triangles stops \
         the run (limits.max_triangles); --frames N makes a shorter probe"
    ))
}

/// Progress that goes nowhere.
pub struct NoProgress;

impl ProgressSink for NoProgress {
    fn start(&self, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
    fn notice(&self, _: &str) {}
    fn tuning(&self, _: &str) {}
}

/// One pass of one entry over the flight, reporting its frames done to the sink 16 at a time
/// (and at the last frame).
pub(super) struct FrameProgress<'p> {
    sink: &'p dyn ProgressSink,
    n_frames: u64,
    reported: u64,
}

impl<'p> FrameProgress<'p> {
    /// A pass of `n_frames` frames, none reported yet.
    pub(super) fn new(sink: &'p dyn ProgressSink, n_frames: u64) -> FrameProgress<'p> {
        FrameProgress {
            sink,
            n_frames,
            reported: 0,
        }
    }

    /// Frame `frame` of the pass is done.
    pub(super) fn frame_done(&mut self, frame: u64) {
        let done = frame + 1;
        if done.is_multiple_of(16) || done == self.n_frames {
            self.sink.advance(done - self.reported);
            self.reported = done;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_large_first_frame_or_a_long_projected_run_is_announced_with_its_figures() {
        assert_eq!(
            large_work_notice("small", 20_000, 0.01, 1000, 2_000_000),
            None
        );
        let big = large_work_notice("roam τ=0.1px", 2_700_000, 1.0, 1000, 4_000_000)
            .expect("2.7 M triangles");
        assert!(
            big.contains("frame 0 has 2700000 triangles and took 1.00 s"),
            "{big}"
        );
        assert!(big.contains("its 1000 frames take about 17 min"), "{big}");
        assert!(big.contains("limits.max_triangles"), "{big}");
        let slow = large_work_notice("slow", 50_000, 0.5, 10_000, 2_000_000).expect("83 min");
        assert!(slow.contains("about 1.4 h"), "{slow}");
    }
}
