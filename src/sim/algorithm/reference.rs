//! `reference`: Wu's view-angle criterion evaluated from scratch every frame, SPEC §6's
//! brute-force reference for Wu (the nodes of Wu et al. 2001 §3.1, the split zones and lives of
//! §4.3 and §5, through `zone.rs`). It is not in the paper, and it holds no triangle budget.
//!
//! Top-down over Wu's quadtree from the root block: a node splits when it has an error (δ > 0)
//! and its signed life ℓ meets the [`SplitThreshold`] (by default ℓ ≤ 0, i.e. the eye is in its
//! split zone) and, with [`Refinement::InView`] (Wu's `refine` option), its bounding sphere meets
//! the view cone ([`ViewThreshold::InView`], by default) or lies within its margin of it
//! ([`ViewThreshold::WithinMargin`], the loosest test Wu's deferred merges can leave behind; see
//! `wu/visibility.rs`); then its four sub-blocks are tested. Splitting activates the node's centre
//! and, first, whatever closure needs (its parents, recursively: the forced splits). After the
//! traversal every edge midpoint whose parents are both active is inserted (boundary vertices are
//! "free": Wu's nodes are the block centres, and a shared edge is subdivided as soon as both blocks
//! beside it are split). No queues, no deferral, no state carried between frames but the previous
//! mesh (for the inserted/deleted counts).
//!
//! This is the ground truth that the incremental algorithms are tested against, and the
//! denominator of every "what coherence saves" ratio. Counters: `splits` = nodes activated by this
//! frame's rebuild (forced ones included), `merges` = 0, `vertices_inserted`/`deleted` = the
//! difference from the previous frame's mesh (what changed on screen, the meaning the incremental
//! algorithms give them), `metric_evaluations` = lives computed.
//!
//! **Whole terrain or in view.** The default refines the whole terrain (the *whole-terrain
//! reference*). With [`Refinement::InView`] (the experiment's `"refine": "in_view"`) it refines
//! only what Wu's in-view refinement and cone culling refine: the same cone (`wu/cull.rs`), the
//! same node spheres and the same test ([`Sight::in_view`], `wu/visibility.rs`), so it is the
//! from-scratch reference to set against a `wu` entry with `cone_culling`.
//!
//! **What a GPU draws** (issue #31): the cheapest honest emit of a reference, which is not a
//! renderer: the mesh as one indexed triangle list written whole every frame
//! (`sim::draw::emit`). Upload is O(mesh) per frame by design.
//!
//! Memory: two `VertexSet`s, one bit per vertex each (this frame's mesh and the previous one, in a
//! `RebuiltMesh`), with their active-vertex lists; the traversal stack; and with the
//! `max_plus_own` nesting, the centres' nested errors (4 bytes per sample, `zone.rs`).

use super::wu::{Cone, ConeMotion, NodeSphere, Refinement, Sight};
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::emit::RebuiltBuffers;
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::{GridPoint, Hierarchy, NestingRule, VertexClass};
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::rebuilt::RebuiltMesh;
use crate::sim::stats::FrameStats;
use crate::sim::view::ViewSettings;
use crate::sim::zone::{
    NodeErrors, SpeedBound, ZoneVariant, radius_per_error, signed_life, split_zone_scaled,
};

pub(super) const NAME: &str = "reference";

/// When a node splits, in terms of its signed life ℓ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitThreshold {
    /// Split iff ℓ ≤ the value (ℓ ≤ 0: the eye is in the zone).
    LifeAtMost(f64),
    /// Split iff ℓ < the value.
    LifeBelow(f64),
}

impl SplitThreshold {
    fn splits(self, life: f64) -> bool {
        match self {
            SplitThreshold::LifeAtMost(limit) => life <= limit,
            SplitThreshold::LifeBelow(limit) => life < limit,
        }
    }
}

/// With in-view refinement, how far outside the view cone a node may be and still split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewThreshold {
    /// Its bounding sphere meets the cone (Wu's split test).
    InView,
    /// Its sphere is at most its margin (one frame of cone motion) outside the cone: what Wu may
    /// still hold when a budget defers its merges by a frame.
    WithinMargin,
}

/// Parameters of the reference algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceConfig {
    /// Screen-space tolerance τ in pixels (θ = τ·fovy/h).
    pub tau_px: f64,
    pub zone: ZoneVariant,
    pub threshold: SplitThreshold,
    /// How δ nests (see `WuConfig::nesting`).
    pub nesting: NestingRule,
    /// Split only in view, as Wu's `refine` option.
    pub refine: Refinement,
    /// What "in view" means with [`Refinement::InView`].
    pub view_threshold: ViewThreshold,
}

/// The from-scratch reference. Per frame: O(nodes tested + active vertices).
pub struct Reference<'h> {
    /// The buffers a GPU draws this frame's mesh from.
    draw: RebuiltBuffers,
    hierarchy: &'h Hierarchy,
    config: ReferenceConfig,
    theta: f64,
    speed: SpeedBound,
    motion: ConeMotion,
    errors: NodeErrors,
    mesh: RebuiltMesh,
    n_triangles: u64,
    stack: Vec<(GridPoint, u32)>,
}

impl<'h> Reference<'h> {
    pub fn new(
        hierarchy: &'h Hierarchy,
        config: ReferenceConfig,
        view: &ViewSettings,
        speed: SpeedBound,
    ) -> Reference<'h> {
        Reference {
            draw: RebuiltBuffers::new(),
            hierarchy,
            config,
            theta: config.tau_px * view.pixel_angle(),
            speed,
            motion: ConeMotion::new(speed),
            errors: NodeErrors::new(hierarchy, config.nesting),
            mesh: RebuiltMesh::new(hierarchy.lattice()),
            n_triangles: 2,
            stack: Vec::new(),
        }
    }

    /// Activates `p` and, first, its parents (recursively). Returns the number of square nodes
    /// activated.
    fn activate_closed(&mut self, p: GridPoint) -> u64 {
        let lattice = self.hierarchy.lattice();
        let id = lattice.id(p);
        if self.mesh.mesh().contains(id) {
            return 0;
        }
        let parents = lattice.parents(p);
        let mut squares = 0;
        for parent in &parents {
            squares += self.activate_closed(*parent);
        }
        self.mesh.insert(id);
        self.n_triangles += parents.len() as u64;
        if matches!(lattice.classify(p), VertexClass::Square { .. }) {
            squares += 1;
        }
        squares
    }
}

impl Reference<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        self.mesh.mesh()
    }
}

impl LodAlgorithm for Reference<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        &[]
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let hierarchy = self.hierarchy;
        let lattice = hierarchy.lattice();
        self.mesh.start_frame(lattice);
        self.n_triangles = 2;

        let eye = input.camera.eye;
        let cone = (self.config.refine == Refinement::InView).then(|| Cone::new(input.camera));
        let mut splits = 0;
        let mut evaluations = 0;
        // r/δ once per frame, not a sine per node.
        let radius_per_error = radius_per_error(self.theta);
        self.stack.clear();
        self.stack.push((lattice.root(), lattice.cells() / 2));
        while let Some((node, half)) = self.stack.pop() {
            evaluations += 1;
            let zone = split_zone_scaled(
                hierarchy,
                &self.errors,
                node,
                half,
                radius_per_error,
                self.config.zone,
            );
            if zone.is_none() {
                continue;
            }
            if !self
                .config
                .threshold
                .splits(signed_life(zone.as_ref(), eye, self.speed))
            {
                continue;
            }
            if let Some(cone) = &cone {
                let sight = Sight::new(cone, &NodeSphere::of_node(hierarchy, node, half));
                let in_view = match self.config.view_threshold {
                    ViewThreshold::InView => sight.in_view(),
                    ViewThreshold::WithinMargin => !sight.beyond_margin(&self.motion),
                };
                if !in_view {
                    continue;
                }
            }
            splits += self.activate_closed(node);
            if let Some(sub_blocks) = lattice.sub_blocks(node, half) {
                self.stack
                    .extend(sub_blocks.iter().rev().map(|&sub| (sub, half / 2)));
            }
        }
        // Free boundary vertices: every edge midpoint whose parents are all active.
        let n_before = self.mesh.active().len();
        for k in 0..n_before {
            let p = lattice.point(self.mesh.active()[k]);
            let VertexClass::Square { half } = lattice.classify(p) else {
                continue;
            };
            for boundary in lattice.boundary_vertices(p, half) {
                let parents = lattice.parents(boundary);
                if parents
                    .as_slice()
                    .iter()
                    .all(|q| self.mesh.mesh().contains_point(lattice, *q))
                    && self.mesh.insert(lattice.id(boundary))
                {
                    self.n_triangles += parents.len() as u64;
                }
            }
        }

        stats.triangles = self.n_triangles;
        stats.splits = splits;
        stats.merges = 0;
        stats.vertices_inserted = self.mesh.inserted_since_previous();
        stats.vertices_deleted = self.mesh.deleted_since_previous();
        stats.metric_evaluations = evaluations;
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw
            .prepare(MeshOutput::lattice(self.mesh.mesh()), self.hierarchy)
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(self.mesh.mesh())
    }

    fn triangle_count(&self) -> u64 {
        self.n_triangles
    }

    fn memory_bytes(&self) -> usize {
        self.errors.memory_bytes()
            + self.mesh.memory_bytes()
            + self.stack.capacity() * std::mem::size_of::<(GridPoint, u32)>()
    }
}
