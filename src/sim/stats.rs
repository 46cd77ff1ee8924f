//! Per-frame statistics and their summaries: what each algorithm did and what it cost (SPEC §1's
//! counters, §5's statistics the paper reports, §7's audit figures). These are values, not a
//! format: `frames.csv` and `summary.json` are written by the edge.
//!
//! [`FrameStats`] is one row of `frames.csv`. The columns every algorithm fills are fields;
//! algorithm-specific counters (Wu's `base_b`, ROAM's queue sizes, …) go in `extra`, aligned
//! with the names the algorithm declares in [`crate::sim::algorithm::LodAlgorithm::extra_columns`].
//! Summaries (mean, p50, p95, max; percentiles by nearest rank) are computed here; formatting
//! them is the edge's business.
//!
//! The mesh counts of the families beyond plain 4-8 meshes ([`MeshCounts`]) are filled by the
//! runner from the mesh. What a frame costs a GPU (`upload_bytes`, `draw_calls`,
//! `triangles_submitted`) comes from the buffers each algorithm keeps (`crate::sim::draw`),
//! the same way for every algorithm.

/// Error statistics over the samples of one frame, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    pub max: f64,
    pub mean: f64,
    pub p95: f64,
}

/// What the audit measured on one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AuditFrame {
    /// Samples inside the view volume that were measured.
    pub samples_in_view: u64,
    /// Projected screen-space error; `None` when no sample was in view.
    pub projected: Option<ErrorSummary>,
    /// Wu's view-angle error; `None` when no sample was in view.
    pub view_angle: Option<ErrorSummary>,
    /// Holes and cracks of a triangle-list mesh; `None` for a 4-8 mesh (closed by construction,
    /// which its validator checks).
    pub coverage: Option<SurfaceCoverage>,
    /// The change of the drawn surface since the previous frame, when the experiment measures
    /// popping; `None` on the first frame or when no sample in view was covered both times.
    pub popping: Option<PoppingFrame>,
}

/// Where a triangle-list mesh's surface is missing or torn, over the audited samples in view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceCoverage {
    /// Samples that no surface triangle covers (left out of the error figures).
    pub holes: u64,
    /// Samples where the surface triangles meeting there disagree on the height (a crack: a
    /// T-junction, or heights that differ across a border).
    pub crack_samples: u64,
    /// The largest such disagreement, metres (0 without cracks).
    pub crack_gap_max_m: f64,
    /// The same gap as projected screen-space pixels (its largest; 0 without cracks or when
    /// every crack is behind the near plane).
    pub crack_gap_max_px: f64,
    /// Crack samples where the skirts hung there leave part of the gap open (every crack
    /// sample, when the mesh has no skirts).
    pub cracks_uncovered: u64,
    /// The largest part of a crack gap no skirt spans, metres (0 when the skirts cover every
    /// crack).
    pub crack_uncovered_max_m: f64,
    /// The same as projected screen-space pixels (a vertical segment from the crack's lower
    /// end).
    pub crack_uncovered_max_px: f64,
}

/// The change of the drawn surface height at the audited samples in view since the previous
/// frame (the 2019 stitching-strips paper's popping measure).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoppingFrame {
    /// Samples in view covered by the surface in both frames.
    pub samples: u64,
    pub rmse_m: f64,
    pub max_m: f64,
    /// The changes as projected screen-space pixels from the current eye (a vertical segment
    /// of the change's length); over the samples in front of the near plane.
    pub rmse_px: f64,
    pub max_px: f64,
}

/// What the mesh families beyond plain 4-8 meshes are counted by (the runner reads them off the
/// mesh): triangles by role, morphing vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshCounts {
    /// Surface, skirt, degenerate and stitch triangles, in the order of
    /// [`crate::sim::mesh::TriangleRole::ALL`].
    pub triangles_by_role: [u64; 4],
    /// Vertices drawn at a morphed height.
    pub morphing_vertices: u64,
}

/// One algorithm's statistics for one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameStats {
    pub frame: u64,
    /// Triangles of the whole mesh.
    pub triangles: u64,
    /// Triangles that meet the view volume (equal to `triangles` when culling is off).
    pub triangles_rendered: u64,
    pub splits: u64,
    pub merges: u64,
    pub vertices_inserted: u64,
    pub vertices_deleted: u64,
    /// Evaluations of the algorithm's error metric (or valid life) this frame.
    pub metric_evaluations: u64,
    /// Wall-clock time of the algorithm's update, in nanoseconds.
    pub update_ns: u64,
    /// Wall-clock time from the new camera to drawable buffers (the update, then the
    /// algorithm's buffer upkeep: `LodAlgorithm::prepare_draw`), in nanoseconds: the study's
    /// time axis.
    pub frame_ns: u64,
    /// Bytes written into GPU buffers this frame (vertices, indices, per-draw data).
    pub upload_bytes: u64,
    /// Draw calls issued this frame.
    pub draw_calls: u64,
    /// Triangles the draw calls submit, degenerate ones included.
    pub triangles_submitted: u64,
    /// Values of the algorithm's extra columns, in the order it declares them.
    pub extra: Vec<f64>,
    /// Filled by the runner from the mesh, for triangle lists and morphed 4-8 meshes.
    pub mesh: Option<MeshCounts>,
    /// The audit against the source height field.
    pub audit: Option<AuditFrame>,
    /// The audit against the detail-extended surface, for an entry that synthesises detail
    /// below the source (popping is not measured there).
    pub audit_detail: Option<AuditFrame>,
}

/// Mean, median, 95th percentile and maximum of a column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnSummary {
    pub mean: f64,
    pub p50: f64,
    pub p95: f64,
    pub max: f64,
}

/// Summarises a column; `None` for an empty one. Percentiles use the nearest-rank rule: the
/// p-th percentile of n sorted values is the value at rank ⌈p·n⌉ (1-based).
pub fn summarise(values: &[f64]) -> Option<ColumnSummary> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mean = sorted.iter().sum::<f64>() / sorted.len() as f64;
    Some(ColumnSummary {
        mean,
        p50: nearest_rank(&sorted, 0.50),
        p95: nearest_rank(&sorted, 0.95),
        max: sorted[sorted.len() - 1],
    })
}

/// The value at rank ⌈p·n⌉ (1-based) of a sorted, non-empty slice.
pub fn nearest_rank(sorted: &[f64], p: f64) -> f64 {
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_of_one_to_twenty() {
        let values: Vec<f64> = (1..=20).rev().map(f64::from).collect();
        let summary = summarise(&values).unwrap();
        assert_eq!(summary.mean, 10.5);
        assert_eq!(summary.p50, 10.0);
        assert_eq!(summary.p95, 19.0);
        assert_eq!(summary.max, 20.0);
    }

    #[test]
    fn an_empty_column_has_no_summary() {
        assert_eq!(summarise(&[]), None);
    }
}

/// Indices of the points on the Pareto front when both coordinates are to be minimised: no other
/// point is at least as good in both and better in one. Sorted by increasing x; points with a
/// non-finite coordinate are left out.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&k| points[k].0.is_finite() && points[k].1.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front = Vec::new();
    let mut best_y = f64::INFINITY;
    for k in order {
        if points[k].1 < best_y {
            best_y = points[k].1;
            front.push(k);
        }
    }
    front
}

#[cfg(test)]
mod pareto_tests {
    use super::pareto_front;

    #[test]
    fn the_front_keeps_only_undominated_points_in_x_order() {
        let points = [
            (3.0, 1.0),
            (1.0, 5.0),
            (2.0, 2.0),
            (2.5, 3.0),
            (1.0, 6.0),
            (f64::NAN, 0.0),
        ];
        assert_eq!(pareto_front(&points), vec![1, 2, 0]);
        assert!(pareto_front(&[]).is_empty());
    }
}
