//! Two small algorithms, for tests only, that draw what the block-based families draw, through
//! the public API an algorithm outside roamsim would use: the proof that the general mesh path
//! (triangle lists, skirts, collapsed borders, degenerate triangles, morphed heights) is audited,
//! checked, exported and drawn like the 4-8 meshes.
//!
//! - [`Patches`]: the terrain as a grid of square patches of 2^`patch_level` cells, each drawn
//!   as a regular grid at step 2^k (k from its distance: a geomipmap), cells split along their
//!   south-west–north-east diagonal. Borders between patches of different steps leave
//!   T-junctions, closed as the config says: skirts hung below every patch border (crack policy
//!   skirted), the finer patch's border vertices moved onto the coarser neighbour's (collapsed:
//!   zero-area triangles of role degenerate), or nothing (declared skirted, so the validator
//!   must refuse it). Optionally the vertices a patch's next coarser level lacks are geomorphed
//!   towards it (interior vertices only, so that borders stay where the neighbours expect them),
//!   and each patch's rows are joined by two degenerate triangles as one strip would be.
//!   Groups are patches; levels are 0 for the coarsest step, `patch_level` for full resolution.
//! - [`MorphingLattice`]: a 4-8 mesh of every vertex whose coordinates are multiples of 2^m,
//!   whose finest vertices (those the next coarser such mesh lacks) are geomorphed towards the
//!   coarser surface as the eye moves away: the 4-8 fast path with morphed heights.

use glam::DVec3;
use roamsim::sim::algorithm::{FrameInput, LodAlgorithm};
use roamsim::sim::draw::emit::RebuiltBuffers;
use roamsim::sim::draw::{DrawCounts, GpuBuffers};
use roamsim::sim::hierarchy::{GridPoint, Hierarchy};
use roamsim::sim::mesh::{
    CrackPolicy, MeshOutput, MorphedHeights, SubgridPoint, TriangleInfo, TriangleList,
    TriangleRole, VertexSet,
};
use roamsim::sim::stats::FrameStats;

/// How [`Patches`] closes the borders between patches of different steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Borders {
    /// A vertical skirt of this depth below every patch border edge (crack policy skirted).
    Skirts { depth_m: f64 },
    /// The finer patch's border vertices moved onto the coarser neighbour's (collapsed).
    Collapsed,
    /// Nothing: T-junctions left open, yet declared skirted (an invalid mesh, on purpose).
    Open,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchConfig {
    /// Patches of 2^patch_level cells a side (at most the terrain's level).
    pub patch_level: u32,
    pub borders: Borders,
    /// Geomorph interior vertices towards the patch's next coarser step.
    pub morph: bool,
    /// Join each patch's rows with two degenerate triangles.
    pub strip_joins: bool,
    /// A patch at distance d is drawn at step 2^⌊log2(d / detail_distance_m)⌋ (clamped).
    pub detail_distance_m: f64,
}

/// The geomipmap-like test algorithm.
pub struct Patches<'h> {
    hierarchy: &'h Hierarchy,
    config: PatchConfig,
    /// Patches per side.
    patches: u32,
    /// Per patch (row-major): this frame's step level k and morph factor.
    levels: Vec<(u32, f64)>,
    previous_levels: Vec<(u32, f64)>,
    list: TriangleList,
    draw: RebuiltBuffers,
}

impl<'h> Patches<'h> {
    pub fn new(hierarchy: &'h Hierarchy, config: PatchConfig) -> Patches<'h> {
        let lattice = hierarchy.lattice();
        assert!(config.patch_level >= 1 && config.patch_level <= lattice.level());
        let patches = lattice.cells() >> config.patch_level;
        let policy = match config.borders {
            Borders::Skirts { .. } | Borders::Open => CrackPolicy::Skirted,
            Borders::Collapsed => CrackPolicy::Collapsed,
        };
        let n = (patches * patches) as usize;
        Patches {
            hierarchy,
            config,
            patches,
            levels: vec![(u32::MAX, 0.0); n],
            previous_levels: vec![(u32::MAX, 0.0); n],
            list: TriangleList::new(lattice, policy),
            draw: RebuiltBuffers::new(),
        }
    }

    /// Patch (px, py)'s step level k this frame.
    pub fn step_level(&self, px: u32, py: u32) -> u32 {
        self.levels[(py * self.patches + px) as usize].0
    }

    fn patch_cells(&self) -> u32 {
        1 << self.config.patch_level
    }

    /// Step level and morph factor of the patch whose centre is at `centre` seen from `eye`.
    fn choose_level(&self, centre: DVec3, eye: DVec3) -> (u32, f64) {
        let ratio = (centre.distance(eye) / self.config.detail_distance_m).max(1.0);
        let exact = ratio.log2();
        let k = (exact.floor() as u32).min(self.config.patch_level);
        let morph = if k < self.config.patch_level {
            (exact - f64::from(k)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (k, morph)
    }

    /// The step (in cells) of patch (px, py), or `None` outside the terrain.
    fn step_of(&self, px: i64, py: i64) -> Option<u32> {
        let n = i64::from(self.patches);
        ((0..n).contains(&px) && (0..n).contains(&py))
            .then(|| 1 << self.levels[(py * n + px) as usize].0)
    }

    /// Builds patch (px, py) into the list.
    fn build_patch(&mut self, px: u32, py: u32) {
        let hierarchy = self.hierarchy;
        let cells = self.patch_cells();
        let patch = (py * self.patches + px) as usize;
        let (k, morph) = self.levels[patch];
        let step = 1u32 << k;
        let n = cells / step;
        let (x0, y0) = (px * cells, py * cells);
        // The step of the neighbour across each side (west, east, south, north).
        let neighbour = |dx: i64, dy: i64| self.step_of(i64::from(px) + dx, i64::from(py) + dy);
        let collapse_to = [
            neighbour(-1, 0),
            neighbour(1, 0),
            neighbour(0, -1),
            neighbour(0, 1),
        ]
        .map(|s| match (self.config.borders, s) {
            (Borders::Collapsed, Some(s)) if s > step => s,
            _ => step,
        });
        let mut index = vec![0u32; ((n + 1) * (n + 1)) as usize];
        for b in 0..=n {
            for a in 0..=n {
                let (mut i, mut j) = (x0 + a * step, y0 + b * step);
                // Collapse a border vertex onto the coarser neighbour's (the lower multiple).
                let snap = |v: u32, origin: u32, s: u32| origin + (v - origin) / s * s;
                if a == 0 || a == n {
                    let s = collapse_to[if a == 0 { 0 } else { 1 }];
                    j = snap(j, y0, s);
                }
                if b == 0 || b == n {
                    let s = collapse_to[if b == 0 { 2 } else { 3 }];
                    i = snap(i, x0, s);
                }
                let point = GridPoint::new(i, j);
                let sample = hierarchy.height(point);
                let interior = a > 0 && a < n && b > 0 && b < n;
                let lacks = (a % 2 == 1 || b % 2 == 1) && k < self.config.patch_level;
                let position = SubgridPoint::grid(i, j);
                index[(b * (n + 1) + a) as usize] =
                    if self.config.morph && interior && lacks && morph > 0.0 {
                        // The next coarser step's surface here: its cell's edge or diagonal.
                        let (di, dj) = (
                            if a % 2 == 1 { step } else { 0 },
                            if b % 2 == 1 { step } else { 0 },
                        );
                        let low = hierarchy.height(GridPoint::new(i - di, j - dj));
                        let high = hierarchy.height(GridPoint::new(i + di, j + dj));
                        let coarse = 0.5 * (f64::from(low) + f64::from(high));
                        let z = f64::from(sample) + morph * (coarse - f64::from(sample));
                        self.list.add_morphing_vertex(position, z as f32)
                    } else {
                        self.list.add_vertex(position, sample)
                    };
            }
        }
        let level = self.config.patch_level - k;
        let info = |role| TriangleInfo {
            role,
            group: patch as u32,
            level,
        };
        let at = |a: u32, b: u32| index[(b * (n + 1) + a) as usize];
        let mut triangles = Vec::new();
        let mut skirts = Vec::new();
        {
            let vertices = self.list.vertices();
            let flat = |c: [u32; 3]| {
                let [p, q, r] = c.map(|v| vertices[v as usize].position.raw());
                (q.0 - p.0) * (r.1 - p.1) - (q.1 - p.1) * (r.0 - p.0) == 0
            };
            for b in 0..n {
                for a in 0..n {
                    let (sw, se, nw, ne) = (at(a, b), at(a + 1, b), at(a, b + 1), at(a + 1, b + 1));
                    for corners in [[sw, se, ne], [sw, ne, nw]] {
                        let role = if flat(corners) {
                            TriangleRole::Degenerate
                        } else {
                            TriangleRole::Surface
                        };
                        triangles.push((corners, role));
                    }
                }
                if self.config.strip_joins && b + 1 < n {
                    let (end, next) = (at(n, b + 1), at(0, b + 1));
                    triangles.push(([end, end, next], TriangleRole::Degenerate));
                    triangles.push(([end, next, next], TriangleRole::Degenerate));
                }
            }
            if let Borders::Skirts { depth_m } = self.config.borders {
                let ring: Vec<(u32, u32)> = (0..n)
                    .map(|a| (a, 0))
                    .chain((0..n).map(|b| (n, b)))
                    .chain((0..n).map(|a| (n - a, n)))
                    .chain((0..n).map(|b| (0, n - b)))
                    .collect();
                for (k, &(a, b)) in ring.iter().enumerate() {
                    let (c, d) = ring[(k + 1) % ring.len()];
                    let (top_a, top_b) = (at(a, b), at(c, d));
                    let below = |v: u32| {
                        let p = vertices[v as usize];
                        (p.position, (f64::from(p.z) - depth_m) as f32)
                    };
                    skirts.push((top_a, top_b, below(top_a), below(top_b)));
                }
            }
        }
        for (corners, role) in triangles {
            self.list.add_triangle(corners, info(role));
        }
        for (top_a, top_b, (pa, za), (pb, zb)) in skirts {
            let bottom_a = self.list.add_vertex(pa, za);
            let bottom_b = self.list.add_vertex(pb, zb);
            self.list
                .add_triangle([top_a, top_b, bottom_b], info(TriangleRole::Skirt));
            self.list
                .add_triangle([top_a, bottom_b, bottom_a], info(TriangleRole::Skirt));
        }
    }
}

impl LodAlgorithm for Patches<'_> {
    fn name(&self) -> &'static str {
        "test-patches"
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        &[]
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let eye = input.camera.eye;
        let spacing = self.hierarchy.field().spacing();
        let cells = self.patch_cells();
        std::mem::swap(&mut self.levels, &mut self.previous_levels);
        for py in 0..self.patches {
            for px in 0..self.patches {
                let centre = GridPoint::new(px * cells + cells / 2, py * cells + cells / 2);
                let position = DVec3::new(
                    f64::from(centre.i) * spacing.dx,
                    f64::from(centre.j) * spacing.dy,
                    f64::from(self.hierarchy.height(centre)),
                );
                self.levels[(py * self.patches + px) as usize] = self.choose_level(position, eye);
            }
        }
        self.list.clear();
        for py in 0..self.patches {
            for px in 0..self.patches {
                self.build_patch(px, py);
            }
        }
        let (mut finer, mut coarser) = (0, 0);
        for (now, before) in self.levels.iter().zip(&self.previous_levels) {
            if now.0 < before.0 {
                finer += 1;
            } else if now.0 > before.0 {
                coarser += 1;
            }
        }
        stats.triangles = self.list.n_triangles();
        stats.splits = finer;
        stats.merges = coarser;
        stats.metric_evaluations = u64::from(self.patches * self.patches);
        stats.extra.clear();
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw
            .prepare(MeshOutput::triangles(&self.list), self.hierarchy)
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::triangles(&self.list)
    }

    fn triangle_count(&self) -> u64 {
        self.list.n_triangles()
    }

    fn memory_bytes(&self) -> usize {
        self.list.memory_bytes()
    }
}

/// The 4-8 test algorithm with morphed heights.
pub struct MorphingLattice<'h> {
    hierarchy: &'h Hierarchy,
    vertices: VertexSet,
    /// The vertices the next coarser uniform mesh lacks.
    finest: Vec<GridPoint>,
    morphed: MorphedHeights,
    draw: RebuiltBuffers,
    /// Full morph beyond this distance, none nearer than `near_m`.
    near_m: f64,
    far_m: f64,
}

impl<'h> MorphingLattice<'h> {
    /// Every vertex with both coordinates multiples of 2^`step_level` (a closed 4-8 mesh);
    /// those with an odd multiple morph from their own height (nearer than `near_m`) to the
    /// coarser surface (beyond `far_m`).
    pub fn new(hierarchy: &'h Hierarchy, step_level: u32, near_m: f64, far_m: f64) -> Self {
        let lattice = hierarchy.lattice();
        let step = 1u32 << step_level;
        let mut vertices = VertexSet::new(lattice);
        let mut finest = Vec::new();
        for j in (0..lattice.side()).step_by(step as usize) {
            for i in (0..lattice.side()).step_by(step as usize) {
                let p = GridPoint::new(i, j);
                vertices.insert(lattice.id(p));
                if (i / step) % 2 == 1 || (j / step) % 2 == 1 {
                    finest.push(p);
                }
            }
        }
        MorphingLattice {
            hierarchy,
            vertices,
            finest,
            morphed: MorphedHeights::new(),
            draw: RebuiltBuffers::new(),
            near_m,
            far_m,
        }
    }
}

impl LodAlgorithm for MorphingLattice<'_> {
    fn name(&self) -> &'static str {
        "test-morphing-lattice"
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        &[]
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let lattice = self.hierarchy.lattice();
        let field = self.hierarchy.field();
        self.morphed.clear();
        for &p in &self.finest {
            let position = field.position(p.i as usize, p.j as usize);
            let distance = position.distance(input.camera.eye);
            let t = ((distance - self.near_m) / (self.far_m - self.near_m)).clamp(0.0, 1.0);
            let id = lattice.id(p);
            if t > 0.0 {
                // Towards the midpoint of the edge the vertex bisects: the coarser surface.
                let z = position.z - t * self.hierarchy.vertex_error(p);
                self.morphed.set(id, z as f32);
            }
        }
        stats.triangles = self.vertices.triangle_count(lattice);
        stats.extra.clear();
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        let mesh = MeshOutput::morphed_lattice(&self.vertices, &self.morphed);
        self.draw.prepare(mesh, self.hierarchy)
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::morphed_lattice(&self.vertices, &self.morphed)
    }

    fn triangle_count(&self) -> u64 {
        self.vertices.triangle_count(self.hierarchy.lattice())
    }

    fn memory_bytes(&self) -> usize {
        self.vertices.memory_bytes() + self.morphed.memory_bytes()
    }
}
