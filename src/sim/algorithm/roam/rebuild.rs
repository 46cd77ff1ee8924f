//! `roam-rebuild`: the reference of what ROAM's coherence saves. Every frame it resets the
//! bintree (and its buffers) to the two base triangles and splits greedily from the split queue
//! alone, through the same `Core` as `roam` (flags and strips included, no merge queue, no
//! deferral). Not here: the state and its operations (`core/`), the columns (`extras.rs`).

use super::core::{Core, FrameCounters};
use super::extras::columns;
use super::priority::ViewFrame;
use super::{MotionBound, REBUILD_NAME, RoamConfig, placeholder_camera, strips};
use crate::sim::algorithm::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{MeshOutput, VertexSet};
use crate::sim::stats::FrameStats;
use crate::sim::zone::SpeedBound;

/// `roam-rebuild`: split-only greedy refinement from the base mesh every frame. Per frame:
/// O(splits) plus O(grid/64) for the inserted/deleted counts, plus O(1) per split for flags and
/// strips when those are on.
pub struct RoamRebuild<'h> {
    core: Core<'h>,
    previous_mesh: VertexSet,
}

impl<'h> RoamRebuild<'h> {
    pub fn new(hierarchy: &'h Hierarchy, config: RoamConfig, speed: SpeedBound) -> RoamRebuild<'h> {
        let config = RoamConfig {
            deferral: false,
            ..config
        };
        let motion = MotionBound {
            metres_per_frame: speed.horizontal.hypot(speed.vertical),
            radians_per_frame: None,
        };
        let placeholder = placeholder_camera();
        let core = Core::new(hierarchy, config, motion, false, &placeholder);
        let previous_mesh = core.bintree.mesh().clone();
        RoamRebuild {
            core,
            previous_mesh,
        }
    }

    /// The largest priority in the split queue (0 when empty).
    pub fn max_split_priority(&self) -> f64 {
        self.core.queues.top_split().map_or(0.0, |(_, k)| k.value)
    }

    /// The priority of the last triangle this frame's rebuild chose to split.
    pub fn last_split_priority(&self) -> Option<f64> {
        self.core.last_split.map(|k| k.value)
    }
}

impl LodAlgorithm for RoamRebuild<'_> {
    fn memory_bytes(&self) -> usize {
        self.core.memory_bytes() + self.previous_mesh.memory_bytes()
    }

    fn name(&self) -> &'static str {
        REBUILD_NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        columns(&self.core.config, false)
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let core = &mut self.core;
        core.frame = input.frame;
        core.counters = FrameCounters::default();
        core.last_split = None;
        core.view = ViewFrame::new(input.camera);
        self.previous_mesh.clone_from(core.bintree.mesh());
        core.bintree.reset();
        core.draw.reset(&core.bintree, core.hierarchy);
        core.fill_root_geometry();
        core.queues.clear();
        core.update_flags();
        core.flag_changes.clear();
        for root in core.bintree.roots() {
            if core.config.strips
                && (!core.config.culling_flags || !core.bintree.get(root).flags.is_out())
            {
                strips::attach(&mut core.bintree, root);
            }
            core.queue_triangle(root);
        }
        core.adapt(true);

        let counters = core.counters;
        let mesh = core.bintree.mesh();
        stats.triangles = core.bintree.n_leaves();
        stats.splits = counters.splits;
        stats.merges = 0;
        stats.vertices_inserted = mesh
            .iter()
            .filter(|&id| !self.previous_mesh.contains(id))
            .count() as u64;
        stats.vertices_deleted = self
            .previous_mesh
            .iter()
            .filter(|&id| !mesh.contains(id))
            .count() as u64;
        stats.metric_evaluations = counters.evaluations;
        stats.extra = core.extras(columns(&core.config, false));
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.core.draw.prepare()
    }

    fn buffers(&self) -> &GpuBuffers {
        self.core.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(self.core.bintree.mesh())
    }

    fn triangle_count(&self) -> u64 {
        self.core.bintree.n_leaves()
    }
}

impl RoamRebuild<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        self.core.bintree.mesh()
    }
}
