//! Detail beyond the source resolution (Lauritsen–Nielsen §3.3–3.4): the synthesised surface
//! below the finest source level, and the cache of the chunks made from it at run time.
//!
//! # The surface
//!
//! The paper keeps two height fields apart (§3.3.1): a **base** field, refined by an
//! interpolating subdivision, and a **displacement** field, the displacement function sampled at
//! the base field's samples; a drawn height is their sum, and the displacements are never fed
//! back into the subdivision (that would sum every earlier level's displacement).
//!
//! - **Subdivision** (§3.3.2): the paper uses Kobbelt's interpolatory subdivision for quad
//!   meshes. On a regular height grid that scheme is the tensor product of the four-point rule:
//!   a new sample between two old ones is (−p₀ + 9p₁ + 9p₂ − p₃)/16 along a row or column, and
//!   a new sample in the middle of a cell is the same rule, down the column, over the four new
//!   row samples (computed in `f64`, rounded once to `f32`). Old samples are kept (the scheme
//!   interpolates), so a synthesised chunk's even vertices are its parent's.
//! - **Borders** (§3.4.3): every chunk's base grid carries a border of two samples beyond its
//!   square, used only by the subdivision; two are exactly what the children's own two-sample
//!   borders need, so chunks stay independent and still agree along every shared border, and
//!   the synthesised surface is one function of position ([`DetailField`] computes it for the
//!   whole terrain: the audit's truth and the tests' reference). At the source level the border
//!   comes from the height field, clamped at the terrain's edges (the edge sample repeated).
//! - **Displacement** (§3.3.3): a fractal of gradient (Perlin) noise, the paper's basis
//!   function: octave o = 1..=levels has its lattice every 2^−(o−1) source cells and amplitude
//!   `amplitude_m`·`roughness`^(o−1). Gradient noise is zero on its own lattice, so every
//!   octave is zero on the source samples (the source is kept exactly, and the two audits,
//!   against the source and against the synthesised surface, agree wherever the drawn surface
//!   is exact) and a vertex first made at depth k below the source is moved by octaves 1..=k
//!   only. Gradients come from a seeded integer hash (SplitMix64) of (seed, octave, lattice
//!   point), one of eight exact directions; everything is `f64` arithmetic on dyadic positions,
//!   so the surface is the same on every run, platform and thread count.
//!
//! # Errors (§3.4.1)
//!
//! The static (source) leaves get one estimated error ε instead of 0, "by stochastic sampling":
//! the children of up to [`ERROR_SAMPLE_LEAVES`] leaves, chosen by the seed, are synthesised and
//! ε is the largest δ_m found (the largest distance of a child vertex the leaf lacks from the
//! leaf's surface, as eq. 3.1 measures δ_m). The errors above nest as before, so every source
//! chunk's error grows by ε. A synthesised chunk's error is half its parent's, the paper's
//! crude rule; chunks at the deepest synthesised level are leaves.
//!
//! # The cache (§3.2.14, §3.4.4)
//!
//! Synthesised chunks are made in sibling groups of four (a node has four children or none),
//! when the selection wanted a chunk's children and they were missing (listing 3.7: the chunk
//! is drawn in their place this frame, the children are there from the next). Requests are
//! served in visiting order (nearest first with front-to-back on) under §3.4.4's creation
//! limit as the thesis has it: at most `max_queued_chunks` chunks requested and not yet
//! finished (made but still on their way: the latency of the loading effect, or the frame they
//! were made in), "new requests will be denied as long as the old ones are not finished"
//! (4–8 in the thesis). Without loading a group is finished the frame after its request, so the
//! limit bounds the chunks made in one frame; with a latency it bounds those on their way. The
//! thesis's better solution is an option: with `max_speed_per_spacing` k, a group is requested
//! only while the viewpoint moves at most k of the new chunks' sample spacings per frame (the
//! ratio of the new nodes' sample density to the viewpoint's velocity, refused when too low);
//! both kinds of refusal are counted in `detail_refused`. The cache holds at most `cache_chunks` chunks: to make room a
//! group is evicted, least recently used first (a chunk is used when the selection visits it),
//! only a group none of whose chunks has cached children, and never one used this frame; when
//! no group can go, the request is refused (counted) and the cap holds.
//!
//! Memory: per cached chunk its bordered base grid ((2^c + 5)² `f32`) and its drawn heights
//! ((2^c + 1)² `f32`), about 36 KiB for 65² chunks, plus the map's entry; at most `cache_chunks`
//! of them, reported every frame (`detail_bytes`).

use super::super::block_lod::grid::{coarser_neighbours, round_up_f32};
use super::cache::GroupCache;
use super::tree::{ChunkId, ChunkRecord};
use crate::sim::hierarchy::{GridPoint, Hierarchy};

/// Samples of border kept around every base grid, on each side.
pub const BORDER: u32 = 2;

/// How many source leaves the estimate of ε samples (all of them when there are fewer).
pub const ERROR_SAMPLE_LEAVES: usize = 64;

/// The most synthesised levels: a chunk's vertices stay exact in the mesh's 16 fractional
/// bits as long as leaf level + detail levels ≤ 15 (the chunk numbering's limit).
pub const MAX_DETAIL_LEVELS: u32 = 8;

/// The largest [`DetailField`] the detail audit builds: 2^26 samples (256 MiB of heights).
pub const DETAIL_TRUTH_MAX_SAMPLES: u64 = 1 << 26;

/// The detail effect as the experiment declares it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetailConfig {
    /// Synthesised levels below the finest source level (1..=[`MAX_DETAIL_LEVELS`]).
    pub levels: u32,
    /// Seed of the displacement function.
    pub seed: u64,
    /// Amplitude of the first octave, metres (≥ 0).
    pub amplitude_m: f64,
    /// Each octave's amplitude over the previous one's (0..=1).
    pub roughness: f64,
    /// §3.4.4's creation limit: most chunks requested and not yet finished (≥ 4: one sibling
    /// group; the thesis suggests 4–8).
    pub max_queued_chunks: u32,
    /// §3.4.4's velocity-based limit: a group is requested only while the viewpoint moves at
    /// most this many of the new chunks' sample spacings per frame (> 0); `None`: off.
    pub max_speed_per_spacing: Option<f64>,
    /// Most synthesised chunks held (≥ 4).
    pub cache_chunks: u32,
}

/// The displacement function: a seeded fractal of gradient noise, metres, at a position in
/// source grid cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Displacement {
    seed: u64,
    octaves: u32,
    amplitude_m: f64,
    roughness: f64,
}

impl Displacement {
    pub fn new(config: &DetailConfig) -> Displacement {
        Displacement {
            seed: config.seed,
            octaves: config.levels,
            amplitude_m: config.amplitude_m,
            roughness: config.roughness,
        }
    }

    /// The displacement at (x, y) source cells. Zero on every source sample.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        let mut sum = 0.0;
        let mut amplitude = self.amplitude_m;
        for octave in 1..=self.octaves {
            let scale = f64::from(1u32 << (octave - 1));
            sum += amplitude * self.gradient_noise(octave, x * scale, y * scale);
            amplitude *= self.roughness;
        }
        sum
    }

    /// Perlin's gradient noise on the unit lattice: 0 at lattice points.
    fn gradient_noise(&self, octave: u32, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x.floor(), y.floor());
        let (tx, ty) = (x - fx, y - fy);
        let (ix, iy) = (fx as i64, fy as i64);
        let corner = |dx: i64, dy: i64| {
            let (gx, gy) = self.gradient(octave, ix + dx, iy + dy);
            gx * (tx - dx as f64) + gy * (ty - dy as f64)
        };
        let (u, v) = (fade(tx), fade(ty));
        let south = corner(0, 0) + u * (corner(1, 0) - corner(0, 0));
        let north = corner(0, 1) + u * (corner(1, 1) - corner(0, 1));
        south + v * (north - south)
    }

    /// One of eight exact gradient directions, by hash.
    fn gradient(&self, octave: u32, x: i64, y: i64) -> (f64, f64) {
        let key = splitmix64(
            self.seed ^ splitmix64(u64::from(octave) ^ splitmix64(x as u64 ^ splitmix64(y as u64))),
        );
        const DIRECTIONS: [(f64, f64); 8] = [
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
            (1.0, -1.0),
            (-1.0, -1.0),
        ];
        DIRECTIONS[(key >> 61) as usize]
    }
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// SplitMix64's finaliser: a bijective 64-bit mix.
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A square grid of base heights with a border of [`BORDER`] samples: `inner` cells per side
/// inside the border, indices −BORDER..=inner + BORDER.
#[derive(Clone, Debug, PartialEq)]
pub struct BorderedGrid {
    inner: u32,
    heights: Vec<f32>,
}

impl BorderedGrid {
    fn side(inner: u32) -> usize {
        (inner + 1 + 2 * BORDER) as usize
    }

    /// The grid of `inner` cells with heights `height(a, b)` for a, b in −BORDER..=inner+BORDER.
    pub fn from_fn(inner: u32, mut height: impl FnMut(i64, i64) -> f32) -> BorderedGrid {
        let side = Self::side(inner);
        let mut heights = Vec::with_capacity(side * side);
        let border = i64::from(BORDER);
        for b in 0..side as i64 {
            for a in 0..side as i64 {
                heights.push(height(a - border, b - border));
            }
        }
        BorderedGrid { inner, heights }
    }

    /// The height at (a, b), −BORDER ≤ a, b ≤ inner + BORDER.
    pub fn at(&self, a: i64, b: i64) -> f32 {
        let side = Self::side(self.inner) as i64;
        let border = i64::from(BORDER);
        self.heights[((b + border) * side + a + border) as usize]
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.heights.capacity() * std::mem::size_of::<f32>()
    }

    /// The subdivided grid of the quadrant (qx, qy) ∈ {0, 1}² of this grid (`inner` even): the
    /// same number of cells at half the spacing, its border included. Also the whole grid's
    /// refinement when `inner` is the whole extent (see [`DetailField`]).
    pub fn subdivide_quadrant(&self, qx: u32, qy: u32) -> BorderedGrid {
        let inner = self.inner;
        let (ox, oy) = (i64::from(qx * inner), i64::from(qy * inner));
        BorderedGrid::from_fn(inner, |a, b| self.refined(ox + a, oy + b))
    }

    /// The refined grid's sample at half-index (hx, hy) of this grid.
    fn refined(&self, hx: i64, hy: i64) -> f32 {
        let row = |hx: i64, py: i64| -> f64 {
            if hx.rem_euclid(2) == 0 {
                f64::from(self.at(hx.div_euclid(2), py))
            } else {
                let p = hx.div_euclid(2);
                four_point([-1, 0, 1, 2].map(|k| f64::from(self.at(p + k, py))))
            }
        };
        let value = if hy.rem_euclid(2) == 0 {
            row(hx, hy.div_euclid(2))
        } else {
            let p = hy.div_euclid(2);
            four_point([-1, 0, 1, 2].map(|k| row(hx, p + k)))
        };
        value as f32
    }
}

/// The four-point rule: the new value between p₁ and p₂.
fn four_point(p: [f64; 4]) -> f64 {
    (9.0 * (p[1] + p[2]) - (p[0] + p[3])) / 16.0
}

/// The source leaf `id`'s base grid, its border read from the height field (clamped at the
/// terrain's edges). `cells` per chunk side; `leaf_level` the source leaves' level.
pub fn source_leaf_base(hierarchy: &Hierarchy, id: ChunkId, cells: u32) -> BorderedGrid {
    let last = i64::from(hierarchy.lattice().cells());
    let (x0, y0) = (i64::from(id.x * cells), i64::from(id.y * cells));
    BorderedGrid::from_fn(cells, |a, b| {
        let i = (x0 + a).clamp(0, last) as u32;
        let j = (y0 + b).clamp(0, last) as u32;
        hierarchy.height(GridPoint::new(i, j))
    })
}

/// A synthesised chunk: its base grid, its drawn heights and its record.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthesisedChunk {
    pub base: BorderedGrid,
    /// (cells + 1)² drawn heights, row by row: base + displacement.
    pub heights: Vec<f32>,
    pub record: ChunkRecord,
}

/// Where synthesised chunks lie: chunk cells per side and the source leaves' level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetailGeometry {
    pub cells: u32,
    pub leaf_level: u32,
}

impl DetailGeometry {
    /// The position of vertex (a, b) of chunk `id`, in source cells (exact: dyadic).
    fn position(&self, id: ChunkId, a: u32, b: u32) -> (f64, f64) {
        let depth = id.level - self.leaf_level;
        let scale = 1.0 / f64::from(1u32 << depth);
        let cells = f64::from(self.cells);
        (
            (f64::from(id.x) * cells + f64::from(a)) * scale,
            (f64::from(id.y) * cells + f64::from(b)) * scale,
        )
    }

    /// The four children of `parent` (whose base grid is `base` and error `parent_error`),
    /// synthesised; skirt depths are left 0 for the caller.
    pub fn synthesise_children(
        &self,
        parent: ChunkId,
        base: &BorderedGrid,
        parent_error: f32,
        displacement: &Displacement,
    ) -> [(ChunkId, SynthesisedChunk); 4] {
        parent.children().map(|child| {
            let (qx, qy) = (child.x - 2 * parent.x, child.y - 2 * parent.y);
            let child_base = base.subdivide_quadrant(qx, qy);
            let side = self.cells + 1;
            let mut heights = Vec::with_capacity((side * side) as usize);
            let (mut z_min, mut z_max) = (f32::INFINITY, f32::NEG_INFINITY);
            for b in 0..=self.cells {
                for a in 0..=self.cells {
                    let (x, y) = self.position(child, a, b);
                    let z = (f64::from(child_base.at(i64::from(a), i64::from(b)))
                        + displacement.at(x, y)) as f32;
                    z_min = z_min.min(z);
                    z_max = z_max.max(z);
                    heights.push(z);
                }
            }
            let record = ChunkRecord {
                error: round_up_f32(f64::from(parent_error) * 0.5),
                z_min,
                z_max,
                skirt_depth: 0.0,
            };
            (
                child,
                SynthesisedChunk {
                    base: child_base,
                    heights,
                    record,
                },
            )
        })
    }

    /// δ_m of a parent whose drawn heights are `parent_heights` over its synthesised
    /// `children`: the largest distance of a child vertex the parent lacks from the line
    /// between its two coarser neighbours.
    pub fn own_error(&self, children: &[(ChunkId, SynthesisedChunk); 4]) -> f64 {
        let side = self.cells + 1;
        let mut largest: f64 = 0.0;
        for (_, child) in children {
            let h = |a: u32, b: u32| f64::from(child.heights[(b * side + a) as usize]);
            for b in 0..=self.cells {
                for a in 0..=self.cells {
                    if let Some([p, q]) = coarser_neighbours(a, b) {
                        let line = 0.5 * (h(p.0, p.1) + h(q.0, q.1));
                        largest = largest.max((h(a, b) - line).abs());
                    }
                }
            }
        }
        largest
    }

    /// ε, the source leaves' estimated error (§3.4.1): the largest δ_m over the synthesised
    /// children of up to [`ERROR_SAMPLE_LEAVES`] leaves chosen by the seed.
    pub fn estimate_leaf_error(&self, hierarchy: &Hierarchy, config: &DetailConfig) -> f32 {
        let per_side = 1u64 << self.leaf_level;
        let n_leaves = per_side * per_side;
        let displacement = Displacement::new(config);
        let mut chosen: Vec<u64> = if n_leaves as usize <= ERROR_SAMPLE_LEAVES {
            (0..n_leaves).collect()
        } else {
            (0..ERROR_SAMPLE_LEAVES as u64)
                .map(|k| splitmix64(config.seed ^ splitmix64(k)) % n_leaves)
                .collect()
        };
        chosen.sort_unstable();
        chosen.dedup();
        let mut largest: f64 = 0.0;
        for k in chosen {
            let leaf = ChunkId {
                level: self.leaf_level,
                x: (k % per_side) as u32,
                y: (k / per_side) as u32,
            };
            let base = source_leaf_base(hierarchy, leaf, self.cells);
            let children = self.synthesise_children(leaf, &base, 0.0, &displacement);
            largest = largest.max(self.own_error(&children));
        }
        round_up_f32(largest)
    }
}

/// The synthesised surface of the whole terrain at one depth below the source: the truth the
/// detail audit measures against, and the reference the chunks are tested against.
/// O(4^depth · samples) time and memory: for audits and tests, not for flights over terrains
/// too large for memory.
#[derive(Clone, Debug)]
pub struct DetailField {
    depth: u32,
    /// Samples per side: source cells · 2^depth + 1.
    side: u32,
    heights: Vec<f32>,
}

impl DetailField {
    /// The surface `depth` levels below `hierarchy`'s samples (0: the source itself).
    pub fn new(hierarchy: &Hierarchy, config: &DetailConfig, depth: u32) -> DetailField {
        let cells = hierarchy.lattice().cells();
        let last = i64::from(cells);
        let mut base = BorderedGrid::from_fn(cells, |a, b| {
            hierarchy.height(GridPoint::new(
                a.clamp(0, last) as u32,
                b.clamp(0, last) as u32,
            ))
        });
        let mut inner = cells;
        for _ in 0..depth {
            inner *= 2;
            let coarse = base;
            base = BorderedGrid::from_fn(inner, |a, b| coarse.refined(a, b));
        }
        let displacement = Displacement::new(config);
        let scale = 1.0 / f64::from(1u32 << depth);
        let side = inner + 1;
        let mut heights = Vec::with_capacity((side as usize) * (side as usize));
        for b in 0..side {
            for a in 0..side {
                let z = f64::from(base.at(i64::from(a), i64::from(b)))
                    + displacement.at(f64::from(a) * scale, f64::from(b) * scale);
                heights.push(z as f32);
            }
        }
        DetailField {
            depth,
            side,
            heights,
        }
    }

    /// Levels below the source.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Samples per side.
    pub fn side(&self) -> u32 {
        self.side
    }

    /// The height at sample (i, j) of this depth's grid.
    pub fn height(&self, i: u32, j: u32) -> f32 {
        self.heights[(j as usize) * (self.side as usize) + i as usize]
    }
}

/// The synthesised chunks held (see `cache.rs`).
pub(super) type DetailCache = GroupCache<SynthesisedChunk>;

impl DetailCache {
    /// Heap bytes held (grids, heights and the map's entries).
    pub(super) fn memory_bytes(&self) -> usize {
        self.iter_all()
            .map(|(_, chunk)| {
                chunk.base.memory_bytes()
                    + chunk.heights.capacity() * std::mem::size_of::<f32>()
                    + GroupCache::<SynthesisedChunk>::ENTRY_BYTES
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    fn config(levels: u32) -> DetailConfig {
        DetailConfig {
            levels,
            seed: 7,
            amplitude_m: 3.0,
            roughness: 0.5,
            max_queued_chunks: 8,
            max_speed_per_spacing: None,
            cache_chunks: 64,
        }
    }

    fn bumpy(level: u32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| ((k * 2654435761usize) % 89) as f32 * 0.5 + (k / side) as f32)
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 2.0, dy: 2.0 }).unwrap())
    }

    #[test]
    fn the_displacement_is_zero_on_the_source_samples_and_not_between_them() {
        let displacement = Displacement::new(&config(3));
        for (x, y) in [(0.0, 0.0), (3.0, 5.0), (-2.0, 7.0)] {
            assert_eq!(displacement.at(x, y), 0.0);
        }
        let between = (0..16)
            .map(|k| displacement.at(0.5 + f64::from(k), 0.25))
            .filter(|d| *d != 0.0)
            .count();
        assert!(between > 8, "{between}");
    }

    #[test]
    fn the_four_point_rule_reproduces_cubics_and_keeps_old_samples() {
        // A cubic along x is reproduced exactly by the four-point rule.
        let cubic = |x: f64| 0.01 * x * x * x - 0.2 * x * x + x;
        let grid = BorderedGrid::from_fn(4, |a, _| cubic(a as f64) as f32);
        let fine = grid.subdivide_quadrant(0, 0);
        assert_eq!(fine.at(2, 3), grid.at(1, 1));
        let expected = cubic(0.5);
        assert!((f64::from(fine.at(1, 0)) - expected).abs() < 1e-5);
    }

    #[test]
    fn synthesised_chunks_are_the_detail_field_and_agree_along_their_borders() {
        // 33×33, chunks of 9×9: source leaves at level 2. Two levels of detail.
        let hierarchy = bumpy(5);
        let config = config(2);
        let geometry = DetailGeometry {
            cells: 8,
            leaf_level: 2,
        };
        let displacement = Displacement::new(&config);
        let field = DetailField::new(&hierarchy, &config, 2);
        let mut compared = 0;
        for leaf_index in 0..16 {
            let leaf = ChunkId {
                level: 2,
                x: leaf_index % 4,
                y: leaf_index / 4,
            };
            let base = source_leaf_base(&hierarchy, leaf, 8);
            for (child, chunk) in geometry.synthesise_children(leaf, &base, 1.0, &displacement) {
                for (grandchild, fine) in
                    geometry.synthesise_children(child, &chunk.base, 0.5, &displacement)
                {
                    assert_eq!(fine.record.error, 0.25);
                    for b in 0..=8 {
                        for a in 0..=8 {
                            let (i, j) = (grandchild.x * 8 + a, grandchild.y * 8 + b);
                            assert_eq!(
                                fine.heights[(b * 9 + a) as usize].to_bits(),
                                field.height(i, j).to_bits(),
                                "{grandchild:?} ({a}, {b})"
                            );
                            compared += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(compared, 256 * 81);
        // Depth 0 is the source.
        let source = DetailField::new(&hierarchy, &config, 0);
        assert_eq!(source.height(3, 4), hierarchy.height(GridPoint::new(3, 4)));
        // The synthesised surface keeps the source samples.
        assert_eq!(field.height(12, 16), hierarchy.height(GridPoint::new(3, 4)));
    }

    #[test]
    fn the_leaf_error_is_the_largest_sampled_detail_and_grows_with_the_amplitude() {
        let hierarchy = bumpy(5);
        let geometry = DetailGeometry {
            cells: 8,
            leaf_level: 2,
        };
        let small = geometry.estimate_leaf_error(&hierarchy, &config(2));
        let large = geometry.estimate_leaf_error(
            &hierarchy,
            &DetailConfig {
                amplitude_m: 30.0,
                ..config(2)
            },
        );
        assert!(small > 0.0 && large > small, "{small} {large}");
    }

    #[test]
    fn eviction_takes_the_least_recently_used_group_without_children_and_never_this_frames() {
        let hierarchy = bumpy(5);
        let geometry = DetailGeometry {
            cells: 8,
            leaf_level: 2,
        };
        let displacement = Displacement::new(&config(2));
        let mut cache = DetailCache::default();
        let leaf = |x| ChunkId { level: 2, x, y: 0 };
        for (x, frame) in [(0, 5), (1, 3)] {
            let base = source_leaf_base(&hierarchy, leaf(x), 8);
            for (id, chunk) in geometry.synthesise_children(leaf(x), &base, 1.0, &displacement) {
                cache.insert(id, chunk, frame, frame);
            }
        }
        // Grandchildren below leaf 0's first child, used at frame 1 (older than everything).
        let first = leaf(0).children()[0];
        let base = cache.get_any(first).unwrap().base.clone();
        for (id, chunk) in geometry.synthesise_children(first, &base, 0.5, &displacement) {
            cache.insert(id, chunk, 1, 1);
        }
        assert_eq!(cache.len(), 12);
        // At frame 6 the grandchildren go first (oldest, and childless), then leaf 1's group
        // (used at 3) before leaf 0's (used at 5).
        assert_eq!(cache.evict_one(6), 4);
        assert!(cache.get_any(first.children()[0]).is_none());
        assert_eq!(cache.evict_one(6), 4);
        assert!(cache.get_any(leaf(1).children()[0]).is_none());
        assert!(cache.get_any(first).is_some());
        // Leaf 0's group was used at frame 5: not evictable at frame 5.
        assert_eq!(cache.evict_one(5), 0);
        assert_eq!(cache.len(), 4);
    }
}
