//! The LOD algorithms, behind one small trait, chosen at run time from the experiment: Wu's
//! (SPEC §5), the baselines and the other papers' systems (SPEC §6), one module each. This file
//! is the trait and the choice; what each paper leaves open is in its module's doc.
//!
//! Each algorithm owns its own data structure and is driven one frame at a time through
//! [`LodAlgorithm::update`]. It hands its mesh to the runner as a [`MeshOutput`]: a 4-8
//! `VertexSet` (optionally with morphed heights), or a general triangle list. The runner
//! validates, culls and audits every algorithm the same way, through the mesh's triangle
//! visitor. No algorithm reads another's state.

mod block_lod;
pub mod chunked;
pub mod columns;
pub mod geomipmap;
pub mod lindstrom;
mod reference;
mod roam;
pub mod rottger;
pub mod stitching;
pub mod vanek;
mod wu;

pub use block_lod::{BlockGoal, Projection};
pub use chunked::{Chunked, ChunkedConfig, SkirtDepth};
pub use geomipmap::{Geomipmap, GeomipmapConfig, LevelDifference};
pub use lindstrom::{Lindstrom, LindstromConfig};
pub use reference::{Reference, ReferenceConfig, SplitThreshold, ViewThreshold};
pub use roam::{
    BintreeError, MotionBound, PriorityCheck, QueueKind, Roam, RoamConfig, RoamGoal, RoamRebuild,
    ThicknessScope, UPLOAD_BYTES_PER_CHANGE as ROAM_UPLOAD_BYTES_PER_CHANGE,
};
pub use wu::{BudgetConfig, Refinement, TauRecentring, Wu, WuConfig, initial_tau_px};

pub use crate::sim::flight::BrokenBounds;
pub use rottger::{Rottger, RottgerConfig};
pub use stitching::{
    BlockDistance, PBlockShape, Stitching, StitchingConfig, StitchingMethod, ViewDirection,
};
pub use vanek::{LodCurve, LodRounding, PatchDistance, Vanek, VanekConfig};

use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::MeshOutput;
use crate::sim::stats::FrameStats;
use crate::sim::view::{Camera, ViewSettings};
use crate::sim::zone::SpeedBound;

/// What an algorithm gets to see of a frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    pub frame: u64,
    pub camera: &'a Camera,
    /// The bounds the camera broke since the previous frame (the eye moved too far, the look
    /// direction turned too fast): anything deferred on the strength of a broken bound must be
    /// revalidated.
    pub broken_bounds: BrokenBounds,
}

/// A view-dependent terrain LOD algorithm.
pub trait LodAlgorithm {
    /// The algorithm's name as the experiment file spells it.
    fn name(&self) -> &'static str;
    /// Names of the algorithm-specific columns it fills in [`FrameStats::extra`].
    fn extra_columns(&self) -> &'static [&'static str];
    /// Brings the mesh up to date for this frame. Fills the counters the algorithm owns
    /// (`triangles`, splits, merges, vertices, metric evaluations, `extra`); the runner fills the
    /// rest (timing, culling, audit).
    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats);
    /// Brings the buffers a GPU draws up to date with the mesh `update` left, and issues this
    /// frame's draw list; returns what the frame wrote into GPU buffers (in `update` and here)
    /// and issued. The runner times `update` and this together as the frame's `frame_ns`: the
    /// CPU work from a new camera to drawable buffers. Each algorithm keeps the representation
    /// its paper draws (its module doc says which); the buffers must draw exactly
    /// [`LodAlgorithm::mesh`] (`crate::sim::draw::check`).
    fn prepare_draw(&mut self) -> DrawCounts;
    /// Appends to `extra` the algorithm-specific columns that describe what
    /// [`LodAlgorithm::prepare_draw`] kept (declared last in [`LodAlgorithm::extra_columns`]);
    /// the runner calls it after `prepare_draw`, outside the timing. Default: none.
    fn draw_columns(&self, _extra: &mut Vec<f64>) {}
    /// The algorithm's own check of what it keeps beyond the mesh and the buffers (such as
    /// strips), run by `--check` and the tests after each frame; O(mesh). Default: nothing.
    fn check_own(&self) -> Result<(), String> {
        Ok(())
    }
    /// The buffers as the GPU holds them after [`LodAlgorithm::prepare_draw`].
    fn buffers(&self) -> &GpuBuffers;
    /// The current mesh, in whichever form the algorithm draws (see [`MeshOutput`]).
    fn mesh(&self) -> MeshOutput<'_>;
    /// The algorithm's own triangle count (validated against the mesh in checked runs).
    fn triangle_count(&self) -> u64;
    /// Heap bytes of the algorithm's own state (not the shared preprocessed terrain).
    fn memory_bytes(&self) -> usize;
    /// Facts about the run worth reporting once (e.g. the τ a budget started from).
    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
}

/// A count an entry holds every frame: its budget or target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountGoal {
    /// The `frames.csv` column that counts it (`triangles`, `triangles_rendered`, …).
    pub column: &'static str,
    pub target: u64,
}

/// An algorithm and its parameters, as validated from an experiment.
#[derive(Clone, Debug, PartialEq)]
pub enum AlgorithmConfig {
    Reference(ReferenceConfig),
    Wu(WuConfig),
    Lindstrom(LindstromConfig),
    Roam(RoamConfig),
    RoamRebuild(RoamConfig),
    Geomipmap(GeomipmapConfig),
    Chunked(ChunkedConfig),
    Rottger(RottgerConfig),
    Vanek(VanekConfig),
    Stitching(StitchingConfig),
}

impl AlgorithmConfig {
    pub fn name(&self) -> &'static str {
        match self {
            AlgorithmConfig::Reference(_) => reference::NAME,
            AlgorithmConfig::Wu(_) => wu::NAME,
            AlgorithmConfig::Lindstrom(_) => lindstrom::NAME,
            AlgorithmConfig::Roam(_) => roam::NAME,
            AlgorithmConfig::RoamRebuild(_) => roam::REBUILD_NAME,
            AlgorithmConfig::Geomipmap(_) => geomipmap::NAME,
            AlgorithmConfig::Chunked(_) => chunked::NAME,
            AlgorithmConfig::Rottger(_) => rottger::NAME,
            AlgorithmConfig::Vanek(_) => vanek::NAME,
            AlgorithmConfig::Stitching(_) => stitching::NAME,
        }
    }

    /// Whether the algorithm reads the hierarchy's Wu node table (node errors or block height
    /// ranges), so that a run builds it before the first entry (`Hierarchy::build_node_table`;
    /// an undeclared reader still gets it, built on first read).
    pub fn reads_node_table(&self) -> bool {
        match self {
            AlgorithmConfig::Reference(_) | AlgorithmConfig::Wu(_) => true,
            AlgorithmConfig::Lindstrom(_) => true,
            AlgorithmConfig::Rottger(config) => config.clipping,
            AlgorithmConfig::Roam(_)
            | AlgorithmConfig::RoamRebuild(_)
            | AlgorithmConfig::Geomipmap(_)
            | AlgorithmConfig::Chunked(_)
            | AlgorithmConfig::Vanek(_)
            | AlgorithmConfig::Stitching(_) => false,
        }
    }

    /// The count this entry is asked to hold every frame (a budget or a target), as the name of
    /// the `frames.csv` column that counts it and the number; `None` for tolerance-driven
    /// entries.
    pub fn count_goal(&self) -> Option<CountGoal> {
        use block_lod::BlockGoal;
        use rottger::LoadCount;
        let goal = |column, target| Some(CountGoal { column, target });
        match self {
            AlgorithmConfig::Wu(config) => config.budget.and_then(|budget| {
                // With the in-view count kept, the budget holds the triangles of in-view
                // blocks (Wu's count); else the whole mesh.
                let column = if config.cone_culling {
                    columns::wu::TRIANGLES_IN_VIEW_BLOCKS
                } else {
                    "triangles"
                };
                goal(column, budget.triangles)
            }),
            AlgorithmConfig::Roam(config) | AlgorithmConfig::RoamRebuild(config) => {
                match config.goal {
                    roam::RoamGoal::TargetTriangles(n) => goal("triangles", n),
                    roam::RoamGoal::TolerancePx(_) => None,
                }
            }
            AlgorithmConfig::Geomipmap(geomipmap::GeomipmapConfig { goal: g, .. })
            | AlgorithmConfig::Chunked(chunked::ChunkedConfig { goal: g, .. }) => match g {
                BlockGoal::TargetTriangles(n) => goal("triangles", *n),
                BlockGoal::TolerancePx(_) => None,
            },
            AlgorithmConfig::Rottger(config) => config.load.and_then(|load| match load.count {
                LoadCount::Triangles => goal(columns::rottger::FAN_TRIANGLES, load.target),
                LoadCount::FanVertices => goal(columns::rottger::FAN_VERTICES, load.target),
            }),
            AlgorithmConfig::Vanek(config) => {
                config.target_triangles.and_then(|n| goal("triangles", n))
            }
            AlgorithmConfig::Reference(_)
            | AlgorithmConfig::Lindstrom(_)
            | AlgorithmConfig::Stitching(_) => None,
        }
    }

    /// The surface an entry that synthesises detail draws beyond the source (the detail audit's
    /// truth); `None` for every other entry. O(4^levels · samples).
    pub fn detail_truth(&self, hierarchy: &Hierarchy) -> Option<chunked::detail::DetailField> {
        match self {
            AlgorithmConfig::Chunked(config) => chunked::detail_truth(hierarchy, config),
            _ => None,
        }
    }

    /// Builds the algorithm on a preprocessed terrain.
    pub fn build<'h>(
        &self,
        hierarchy: &'h Hierarchy,
        view: &ViewSettings,
        speed: SpeedBound,
    ) -> Box<dyn LodAlgorithm + 'h> {
        match self {
            AlgorithmConfig::Reference(config) => {
                Box::new(Reference::new(hierarchy, *config, view, speed))
            }
            AlgorithmConfig::Wu(config) => Box::new(Wu::new(hierarchy, *config, view, speed)),
            AlgorithmConfig::Lindstrom(config) => {
                Box::new(Lindstrom::new(hierarchy, *config, view))
            }
            AlgorithmConfig::Roam(config) => Box::new(Roam::new(hierarchy, *config, speed)),
            AlgorithmConfig::RoamRebuild(config) => {
                Box::new(RoamRebuild::new(hierarchy, *config, speed))
            }
            AlgorithmConfig::Geomipmap(config) => {
                Box::new(Geomipmap::new(hierarchy, *config, view))
            }
            AlgorithmConfig::Chunked(config) => Box::new(Chunked::new(hierarchy, *config, view)),
            AlgorithmConfig::Rottger(config) => Box::new(Rottger::new(hierarchy, *config)),
            AlgorithmConfig::Vanek(config) => Box::new(Vanek::new(hierarchy, *config)),
            AlgorithmConfig::Stitching(config) => Box::new(Stitching::new(hierarchy, *config)),
        }
    }
}
