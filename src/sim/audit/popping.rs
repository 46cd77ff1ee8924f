//! Popping (SPEC §7): the change of the drawn surface from one frame to the next, as RMSE and
//! maximum of the height difference, after the 2019 stitching-strips paper (its §1 measures
//! the height difference between a coarse model and the original along vertical rays, its
//! Figure 1; its §4.1 reads popping from how that difference changes between frames, by RMSE,
//! its Table 3). This file holds the running sums ([`PoppingSums`]) and what the auditor keeps
//! between frames for them; the change at each sample is measured in the batch with the error
//! segments (`batch.rs`).
//!
//! Decisions:
//!
//! - **Where and what.** At the audited samples in view of the current frame, from the drawn
//!   height there now and at the previous frame: RMSE and maximum of the change in metres, and
//!   of the same change as a vertical segment at the sample (from the lower of the two heights)
//!   projected from the current eye, in pixels. Samples that were a hole in either frame are
//!   left out; the first frame has no previous one, so no popping.
//! - **An effect the experiment switches on** (`effects.audit.popping`, off by default). Off, the
//!   auditor keeps no previous frame.
//! - **The promise about the next camera.** A run knows its flight, so it tells the auditor the
//!   next frame's camera ([`super::Auditor::audit_followed_by`]); this frame's heights are then
//!   kept only in the tiles either camera may see (`tiles.rs`), and the next call must come with
//!   that camera (a panic otherwise: the heights it would read were not kept). Told nothing,
//!   every tile's heights are kept.

use super::Auditor;
use crate::sim::metrics::projected_error_px;
use crate::sim::stats::PoppingFrame;
use crate::sim::view::Camera;
use glam::DVec3;

/// Running sums of one frame's popping.
#[derive(Default)]
pub(super) struct PoppingSums {
    samples: u64,
    squares_m: f64,
    max_m: f64,
    px_samples: u64,
    squares_px: f64,
    max_px: f64,
}

impl PoppingSums {
    /// Adds the change at one sample in view from `before` to `now` (either NaN: a hole, left
    /// out). The reference's way; the batch measures the same with [`PoppingSums::add_measured`].
    pub(super) fn add(&mut self, camera: &Camera, sample: DVec3, before: f64, now: f64) {
        if before.is_nan() || now.is_nan() {
            return;
        }
        let change = (now - before).abs();
        let base = DVec3::new(sample.x, sample.y, before.min(now));
        self.add_measured(change, projected_error_px(camera, base, change));
    }

    /// Adds a change of `change` metres, `px` pixels when its segment is not behind the near
    /// plane.
    #[inline]
    pub(super) fn add_measured(&mut self, change: f64, px: Option<f64>) {
        self.samples += 1;
        self.squares_m += change * change;
        self.max_m = self.max_m.max(change);
        if let Some(px) = px {
            self.px_samples += 1;
            self.squares_px += px * px;
            self.max_px = self.max_px.max(px);
        }
    }

    /// The frame's popping, when it was `measured` (there was a previous frame) at a sample.
    pub(super) fn summary(&self, measured: bool) -> Option<PoppingFrame> {
        (measured && self.samples > 0).then(|| PoppingFrame {
            samples: self.samples,
            rmse_m: (self.squares_m / self.samples as f64).sqrt(),
            max_m: self.max_m,
            rmse_px: (self.squares_px / self.px_samples.max(1) as f64).sqrt(),
            max_px: self.max_px,
        })
    }
}

impl Auditor {
    /// Checks that `camera` is the one the previous call promised (the previous frame kept
    /// heights only where that camera may see), and takes the promise `next` for the next call.
    ///
    /// # Panics
    /// With popping on, when the previous call promised another camera.
    pub(super) fn keep_promise(&mut self, camera: &Camera, next: Option<&Camera>) {
        // The previous frame kept heights only where the camera it was promised may see.
        if let Some(promised) = self.promised_next.take() {
            assert!(
                promised == *camera,
                "the audit was promised the next frame's camera {promised:?} and is given {camera:?}"
            );
        }
        if self.popping {
            self.promised_next = next.copied();
        }
    }

    /// Keeps this frame's heights for the next, with popping on; the old buffer becomes next
    /// frame's scratch (both paths write every sample of the tiles kept, and only those are
    /// read).
    pub(super) fn keep_heights_for_next_frame(&mut self) {
        if self.popping {
            let previous = self
                .previous_height
                .get_or_insert_with(|| vec![0.0; self.mesh_height.len()]);
            std::mem::swap(previous, &mut self.mesh_height);
        }
    }
}
