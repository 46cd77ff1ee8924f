//! The error segments of the samples in view, measured in batches (SPEC §7: each sample's
//! vertical distance to the drawn surface in projected and in view-angle pixels, and with
//! popping the change since the previous frame): [`ErrorBatch`] holds up to [`BATCH`] segments
//! as columns (a structure of arrays), so that their divisions and square roots run as vector
//! instructions, and hands the finished values to the tallies ([`Sinks`]). It does not find
//! the samples (the lattice and general paths do) nor summarise the values (`figures.rs`).
//!
//! Decisions (the audit's exact shortcuts, each leaving every figure bit-identical):
//!
//! - **The metrics' operations in their order.** Every value is computed with exactly the
//!   operations of [`projected_error_px_at`] and
//!   [`view_angle_error_px`](crate::sim::metrics::view_angle_error_px) (and popping's
//!   `projected_error_px`) in the same order (`geometry.rs`), so each is theirs to the bit.
//! - **Runs of samples measured whole.** For a 4-8 mesh against the source's samples, each run
//!   of a row's samples in tiles that may be in view is measured at once, with no branch,
//!   straight into the batch's free places: the sample's camera coordinates and
//!   `Camera::sees`, the error segment, and with popping the change's segment. The samples out
//!   of view are dropped after, by packing the rest (only in runs that have any). The camera
//!   products that depend only on the row or the frame are taken once, the sums in the same
//!   order as `Camera::to_camera`. The general path, which has holes and cracks to count,
//!   fills the same batch one sample in view at a time and measures it with the same loop.
//! - **`atan2` alone in its loop.** Each batch then calls `atan2` (the platform's, needed
//!   exactly: the mean sums every value) in a loop that does nothing else, puts in the special
//!   angles and the near-plane cases (a segment cut by the near plane is measured again as the
//!   metric measures it), and adds popping's sums in order. Rejected: a faster `atan2` (not
//!   bit-identical).

use super::figures::Figures;
use super::geometry::{ErrorGeometry, projected_segment, segment_figures};
use super::popping::PoppingSums;
use crate::sim::metrics::projected_error_px_at;
use crate::sim::view::Camera;
use glam::DVec3;

/// Segments measured at once: their columns stay in the first-level cache.
pub(super) const BATCH: usize = 128;

/// Error segments of samples in view waiting to be measured, as columns (a structure of
/// arrays), so that their divisions and square roots run as vector instructions. Every value
/// is computed with exactly the operations of [`projected_error_px_at`] and
/// [`view_angle_error_px`](crate::sim::metrics::view_angle_error_px) in the same order, so
/// each is bit-identical to theirs.
///
/// Two ways in: [`put_segment`] and [`ErrorBatch::measure`] (the general path: one segment at
/// a time, those of samples in view only), and [`ErrorBatch::measure_row`] (a 4-8 mesh
/// against the source's samples, with or without popping: a run of one row's samples measured
/// whole, with no branch, those out of view dropped after).
pub(super) struct ErrorBatch {
    /// Per segment: its base in camera coordinates (x, y, z), its base minus the eye on the
    /// world axes (x, y, z), and its length in metres. [`ErrorBatch::measure_row`] keeps only
    /// the base and the length, for the segments the near plane cuts.
    pub(super) segments: Box<[[f64; BATCH]; 7]>,
    /// Per segment waiting: [`SegmentFigures`]' projected length, sine, cosine and special
    /// angle.
    ///
    /// [`SegmentFigures`]: super::geometry::SegmentFigures
    results: Box<[[f64; BATCH]; 4]>,
    /// Per segment waiting: whether both its ends are in front of the near plane.
    in_front: Box<[bool; BATCH]>,
    /// Per segment waiting, with popping measured: the change of the drawn height since the
    /// previous frame (metres), the base of its segment (from the lower of the two heights) in
    /// camera coordinates (x, y, z), and its projected length when both ends are in front of
    /// the near plane.
    popping: Box<[[f64; BATCH]; 5]>,
    /// Per segment waiting, with popping measured: whether the change counts (neither height a
    /// hole) and whether both ends of its segment are in front of the near plane.
    popping_counts: Box<[bool; BATCH]>,
    popping_in_front: Box<[bool; BATCH]>,
    /// Segments waiting in `results`.
    waiting: usize,
}

/// One run of a row's samples (at most [`BATCH`]) as [`ErrorBatch::measure_row`] reads them:
/// the truth and drawn heights, and whether each is in view.
pub(super) struct RunColumns {
    truth: [f64; BATCH],
    drawn: [f64; BATCH],
    /// The drawn heights of the previous frame, with popping measured.
    before: [f64; BATCH],
    seen: [bool; BATCH],
}

impl Default for ErrorBatch {
    fn default() -> ErrorBatch {
        ErrorBatch {
            segments: Box::new([[0.0; BATCH]; 7]),
            results: Box::new([[0.0; BATCH]; 4]),
            in_front: Box::new([false; BATCH]),
            popping: Box::new([[0.0; BATCH]; 5]),
            popping_counts: Box::new([false; BATCH]),
            popping_in_front: Box::new([false; BATCH]),
            waiting: 0,
        }
    }
}

impl Default for RunColumns {
    fn default() -> RunColumns {
        RunColumns {
            truth: [0.0; BATCH],
            drawn: [0.0; BATCH],
            before: [0.0; BATCH],
            seen: [false; BATCH],
        }
    }
}

impl RunColumns {
    /// Loads the `m` samples of `row` from column `start`: the truth and drawn heights, and
    /// with `POPPING` the previous frame's.
    #[inline(always)]
    fn load<const POPPING: bool>(&mut self, row: &Row, start: usize, m: usize) {
        let heights = row.heights[start * row.stride..].iter().step_by(row.stride);
        for (truth, &height) in self.truth[..m].iter_mut().zip(heights) {
            *truth = f64::from(height);
        }
        for (drawn, &height) in self.drawn[..m].iter_mut().zip(&row.drawn[start..][..m]) {
            *drawn = f64::from(height);
        }
        if let (true, Some(previous)) = (POPPING, row.previous) {
            for (before, &height) in self.before[..m].iter_mut().zip(&previous[start..][..m]) {
                *before = f64::from(height);
            }
        }
    }
}

/// Writes segment `n` of a batch.
#[inline(always)]
pub(super) fn put_segment(
    segments: &mut [[f64; BATCH]; 7],
    n: usize,
    base_in_camera: DVec3,
    to_base: DVec3,
    length: f64,
) {
    let n = n % BATCH;
    segments[0][n] = base_in_camera.x;
    segments[1][n] = base_in_camera.y;
    segments[2][n] = base_in_camera.z;
    segments[3][n] = to_base.x;
    segments[4][n] = to_base.y;
    segments[5][n] = to_base.z;
    segments[6][n] = length;
}

/// Writes the popping of segment `n` of a batch: whether it counts, the change, and the base
/// of its segment in camera coordinates.
#[inline(always)]
pub(super) fn put_popping(
    batch: &mut ErrorBatch,
    n: usize,
    counts: bool,
    change: f64,
    base: DVec3,
) {
    let n = n % BATCH;
    batch.popping_counts[n] = counts;
    batch.popping[0][n] = change;
    batch.popping[1][n] = base.x;
    batch.popping[2][n] = base.y;
    batch.popping[3][n] = base.z;
}

/// One row of the lattice as [`ErrorBatch::measure_row`] reads it.
pub(super) struct Row<'a> {
    /// The source's heights of the row (every `stride`-th is audited) and the drawn heights of
    /// its audited samples.
    pub(super) heights: &'a [f32],
    pub(super) drawn: &'a [f32],
    pub(super) stride: usize,
    /// Per audited column: its x, as `Heightfield::position` has it.
    pub(super) x: &'a [f64],
    /// The drawn heights of the previous frame, with popping measured.
    pub(super) previous: Option<&'a [f32]>,
    /// The row's y minus the eye's, and its products with the camera's axes.
    pub(super) dy: f64,
    pub(super) right_y: f64,
    pub(super) up_y: f64,
    pub(super) forward_y: f64,
}

impl ErrorBatch {
    /// Measures the samples of `row` in `columns` that the camera sees, in order: the samples
    /// of the run measured at once (with no branch) into the batch's free places, then those
    /// out of view dropped (packing the rest, when there are any). With `popping`, the change
    /// since the previous frame too (`row.previous` must then be there).
    #[inline(always)]
    pub(super) fn measure_row(
        &mut self,
        run: &mut RunColumns,
        row: &Row,
        columns: std::ops::Range<usize>,
        geometry: &ErrorGeometry,
        camera: &Camera,
        sinks: &mut Sinks,
    ) {
        match (row.previous, sinks.popping.is_some()) {
            (Some(_), true) => {
                self.measure_row_as::<true>(run, row, columns, geometry, camera, sinks)
            }
            (None, false) => {
                self.measure_row_as::<false>(run, row, columns, geometry, camera, sinks)
            }
            _ => unreachable!("popping is measured exactly when there is a previous frame"),
        }
    }

    /// The samples of `row` in `columns` that the camera sees, in order, `POPPING` or not: each
    /// run that fits in the batch's free places measured at once (with no branch), then those
    /// out of view dropped.
    #[inline(always)]
    fn measure_row_as<const POPPING: bool>(
        &mut self,
        run: &mut RunColumns,
        row: &Row,
        columns: std::ops::Range<usize>,
        g: &ErrorGeometry,
        camera: &Camera,
        sinks: &mut Sinks,
    ) {
        let (eye, right, up, forward) = (camera.eye, camera.right, camera.up, camera.forward);
        let ((tan_x, tan_y), far) = (camera.tan_half_fov(), camera.settings.far);
        let mut start = columns.start;
        while start < columns.end {
            let free = self.waiting..BATCH;
            let m = (columns.end - start).min(free.len());
            let x = &row.x[start..][..m];
            run.load::<POPPING>(row, start, m);
            let [base_x, base_y, base_z, .., length] = self
                .segments
                .each_mut()
                .map(|column| &mut column[free.start..][..m]);
            let [out_projected, sine, cosine, special] = self
                .results
                .each_mut()
                .map(|column| &mut column[free.start..][..m]);
            let in_front = &mut self.in_front[free.start..][..m];
            let mut seen = 0;
            for k in 0..m {
                // `Camera::to_camera` of the sample, its sums in the same order, and
                // `Camera::sees_camera`.
                let (z, mesh_z) = (run.truth[k], run.drawn[k]);
                let (dx, dz) = (x[k] - eye.x, z - eye.z);
                let (right_xy, up_xy, forward_xy) = (
                    dx * right.x + row.right_y,
                    dx * up.x + row.up_y,
                    dx * forward.x + row.forward_y,
                );
                let (cx, cy, cz) = (
                    right_xy + dz * right.z,
                    up_xy + dz * up.z,
                    forward_xy + dz * forward.z,
                );
                run.seen[k] = (cz >= g.near)
                    & (cz <= far)
                    & (cx.abs() <= cz * tan_x)
                    & (cy.abs() <= cz * tan_y);
                seen += usize::from(run.seen[k]);
                // The segment from the lower of the sample and the surface, `length` long;
                // its base in camera coordinates differs from the sample's in the z terms
                // only.
                let in_camera_at = |z: f64| {
                    let dz = z - eye.z;
                    DVec3::new(
                        right_xy + dz * right.z,
                        up_xy + dz * up.z,
                        forward_xy + dz * forward.z,
                    )
                };
                let a = in_camera_at(z.min(mesh_z));
                let delta = (z - mesh_z).abs();
                let to_base = DVec3::new(dx, row.dy, z.min(mesh_z) - eye.z);
                let f = segment_figures(g, a, to_base, delta);
                (base_x[k], base_y[k], base_z[k], length[k]) = (a.x, a.y, a.z, delta);
                (out_projected[k], sine[k], cosine[k], special[k]) =
                    (f.projected, f.sine, f.cosine, f.special);
                in_front[k] = f.in_front;
            }
            if POPPING {
                self.measure_run_popping(run, row, start, m, g, camera);
            }
            if seen < m {
                self.drop_unseen::<POPPING>(&run.seen[..m]);
            }
            self.waiting += seen;
            if self.waiting == BATCH {
                self.finish(g, camera, sinks);
            }
            start += m;
        }
    }

    /// With popping, the change since the previous frame of the `m` samples of `row` from
    /// column `start` (loaded in `run`) and its segment, into the batch's free places: a loop
    /// of its own, so that it too runs as vector instructions.
    #[inline(always)]
    fn measure_run_popping(
        &mut self,
        run: &RunColumns,
        row: &Row,
        start: usize,
        m: usize,
        g: &ErrorGeometry,
        camera: &Camera,
    ) {
        let (eye, right, up, forward) = (camera.eye, camera.right, camera.up, camera.forward);
        let free = self.waiting..BATCH;
        let x = &row.x[start..][..m];
        let [change, pop_x, pop_y, pop_z, pop_projected] = self
            .popping
            .each_mut()
            .map(|column| &mut column[free.start..][..m]);
        let pop_counts = &mut self.popping_counts[free.start..][..m];
        let pop_in_front = &mut self.popping_in_front[free.start..][..m];
        // `PoppingSums::add`: the change since the previous frame, its segment from the lower
        // of the two heights.
        for k in 0..m {
            let (before, now) = (run.before[k], run.drawn[k]);
            let dx = x[k] - eye.x;
            let dz = before.min(now) - eye.z;
            let p = DVec3::new(
                (dx * right.x + row.right_y) + dz * right.z,
                (dx * up.x + row.up_y) + dz * up.z,
                (dx * forward.x + row.forward_y) + dz * forward.z,
            );
            let moved = (now - before).abs();
            (change[k], pop_x[k], pop_y[k], pop_z[k]) = (moved, p.x, p.y, p.z);
            (pop_projected[k], pop_in_front[k]) = projected_segment(g, p, moved);
            pop_counts[k] = !before.is_nan() & !now.is_nan();
        }
    }

    /// Drops the segments just measured into the batch's free places whose sample is not
    /// `seen`, packing those in view in order (`kept <= k`: no value is overwritten before it
    /// is read).
    #[inline(always)]
    fn drop_unseen<const POPPING: bool>(&mut self, seen: &[bool]) {
        let (free, m) = (self.waiting..BATCH, seen.len());
        let [base_x, base_y, base_z, .., length] = self
            .segments
            .each_mut()
            .map(|column| &mut column[free.start..][..m]);
        let [out_projected, sine, cosine, special] = self
            .results
            .each_mut()
            .map(|column| &mut column[free.start..][..m]);
        let in_front = &mut self.in_front[free.start..][..m];
        let [change, pop_x, pop_y, pop_z, pop_projected] = self
            .popping
            .each_mut()
            .map(|column| &mut column[free.start..][..m]);
        let pop_counts = &mut self.popping_counts[free.start..][..m];
        let pop_in_front = &mut self.popping_in_front[free.start..][..m];
        let mut kept = 0;
        for k in 0..m {
            if seen[k] {
                (base_x[kept], base_y[kept], base_z[kept]) = (base_x[k], base_y[k], base_z[k]);
                (length[kept], out_projected[kept]) = (length[k], out_projected[k]);
                (sine[kept], cosine[kept], special[kept]) = (sine[k], cosine[k], special[k]);
                in_front[kept] = in_front[k];
                if POPPING {
                    (change[kept], pop_projected[kept]) = (change[k], pop_projected[k]);
                    (pop_x[kept], pop_y[kept], pop_z[kept]) = (pop_x[k], pop_y[k], pop_z[k]);
                    (pop_counts[kept], pop_in_front[kept]) = (pop_counts[k], pop_in_front[k]);
                }
                kept += 1;
            }
        }
    }

    /// Measures the first `n` segments (general path) and adds their figures to `sinks`.
    pub(super) fn measure(
        &mut self,
        n: usize,
        geometry: &ErrorGeometry,
        camera: &Camera,
        sinks: &mut Sinks,
    ) {
        debug_assert_eq!(
            self.waiting, 0,
            "the general path measures its own segments"
        );
        let n = n.min(BATCH);
        let [
            base_x,
            base_y,
            base_z,
            to_base_x,
            to_base_y,
            to_base_z,
            length,
        ] = self.segments.each_ref().map(|column| &column[..n]);
        let [out_projected, out_sine, out_cosine, out_special] =
            self.results.each_mut().map(|column| &mut column[..n]);
        let in_front = &mut self.in_front[..n];
        // No branch: the compiler makes vector instructions of it.
        for k in 0..n {
            let a = DVec3::new(base_x[k], base_y[k], base_z[k]);
            let to_base = DVec3::new(to_base_x[k], to_base_y[k], to_base_z[k]);
            let f = segment_figures(geometry, a, to_base, length[k]);
            (out_projected[k], out_sine[k], out_cosine[k], out_special[k]) =
                (f.projected, f.sine, f.cosine, f.special);
            in_front[k] = f.in_front;
        }
        if sinks.popping.is_some() {
            let [change, pop_x, pop_y, pop_z, pop_projected] =
                self.popping.each_mut().map(|column| &mut column[..n]);
            for k in 0..n {
                let p = DVec3::new(pop_x[k], pop_y[k], pop_z[k]);
                (pop_projected[k], self.popping_in_front[k]) =
                    projected_segment(geometry, p, change[k]);
            }
        }
        self.waiting = n;
        self.finish(geometry, camera, sinks);
    }

    /// Adds the figures of the segments waiting to `sinks`, in order, and empties the batch.
    #[inline(always)]
    pub(super) fn finish(&mut self, g: &ErrorGeometry, camera: &Camera, sinks: &mut Sinks) {
        let n = std::mem::take(&mut self.waiting);
        let [out_projected, out_sine, out_cosine, out_special] =
            self.results.each_mut().map(|column| &mut column[..n]);
        // The view angles: the calls of `atan2` alone in their loop (nothing else lives across
        // them), then those of the special segments put in, with no branch.
        for (sine, &cosine) in out_sine.iter_mut().zip(&*out_cosine) {
            *sine = sine.atan2(cosine);
        }
        for (angle, &special) in out_sine.iter_mut().zip(&*out_special) {
            let measured = *angle / g.pixel_angle;
            *angle = if special >= 0.0 { special } else { measured };
        }
        // The projected errors: as measured when both ends are in front of the near plane;
        // otherwise (rare) packed, a segment cut by the near plane measured again, one behind
        // it left out.
        let kept = if self.in_front[..n].iter().all(|&in_front| in_front) {
            n
        } else {
            let mut kept = 0;
            for k in 0..n {
                let projected_px = if self.in_front[k] {
                    Some(out_projected[k])
                } else {
                    let a = DVec3::new(
                        self.segments[0][k],
                        self.segments[1][k],
                        self.segments[2][k],
                    );
                    projected_error_px_at(camera, a, self.segments[6][k])
                };
                // `kept <= k`: the packed value never overwrites one still to be read.
                out_projected[kept] = projected_px.unwrap_or(0.0);
                kept += usize::from(projected_px.is_some());
            }
            kept
        };
        Figures::extend_both(
            (sinks.projected, &out_projected[..kept]),
            (sinks.view_angle, &out_sine[..n]),
        );
        // Popping's sums, in order (a segment the near plane cuts measured again).
        if let Some(popping) = sinks.popping.as_deref_mut() {
            let [change, pop_x, pop_y, pop_z, pop_projected] = &*self.popping;
            for k in (0..n).filter(|&k| self.popping_counts[k]) {
                let px = if self.popping_in_front[k] {
                    Some(pop_projected[k])
                } else {
                    let p = DVec3::new(pop_x[k], pop_y[k], pop_z[k]);
                    projected_error_px_at(camera, p, change[k])
                };
                popping.add_measured(change[k], px);
            }
        }
    }
}

/// Where a batch's figures go: the values of the two error figures and, with popping
/// measured, popping's sums.
pub(super) struct Sinks<'a> {
    pub(super) projected: &'a mut Figures,
    pub(super) view_angle: &'a mut Figures,
    pub(super) popping: Option<&'a mut PoppingSums>,
}
