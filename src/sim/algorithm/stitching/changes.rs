//! The stitching strips' `vertices_inserted` and `vertices_deleted`: per node, whether what it
//! draws this frame (its block, or its cross of strips and P-block) has other vertices than
//! what it drew last frame (positions or heights; then all of the new count as inserted and all
//! of the old as deleted).
//!
//! A block is compared through its patch words, without tessellating it: a patch's vertices
//! are (n − 1)² interior ones on the inner spacing's lines 1 ..= n − 1 in each direction, then
//! each side's m + 1 in order, and a height is a function of its position alone (the resampled
//! height map), so two patches of one rectangle have the same vertices exactly when their
//! segment counts agree and every line and side vertex lies at the same raw position (interior
//! vertices lie strictly inside the rectangle and a side's are increasing, so a different count
//! moves some vertex). Usually the first position compared differs; same words need none. A
//! cross is compared vertex by vertex with last frame's (kept in a copy), not through a hash
//! (hashing was a third of the update).
//!
//! What it is not: the selection's `splits` and `merges`, or a record of the mesh
//! (`lazy_mesh.rs`).

use super::buffers::{BlockTessellator, PATCH_WORDS};
use super::tessellate::{self, EAST, NORTH, SOUTH, quad_patch_vertices};
use crate::sim::mesh::SurfacePoint;

/// What a node drew in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Drawn {
    /// Its block: patch `patch` of that frame's words.
    Block { patch: u32 },
    /// Its cross: `len` vertices of that frame's CPU list from index `first`.
    Cross { first: u32, len: u32 },
}

/// Per node, what it drew last frame and this frame. O(nodes) words; per frame O(nodes + the
/// crosses' vertices).
#[derive(Debug)]
pub struct VertexChanges {
    now: Vec<Option<Drawn>>,
    before: Vec<Option<Drawn>>,
    words_before: Vec<u32>,
    cross_vertices_before: Vec<SurfacePoint>,
}

impl VertexChanges {
    /// Nothing drawn before, for a tree of `n_nodes` nodes.
    pub fn new(n_nodes: usize) -> VertexChanges {
        VertexChanges {
            now: vec![None; n_nodes],
            before: vec![None; n_nodes],
            words_before: Vec::new(),
            cross_vertices_before: Vec::new(),
        }
    }

    /// Forgets what this frame has drawn so far.
    pub fn begin_frame(&mut self) {
        self.now.fill(None);
    }

    /// Node `index` draws its block as patch `patch` of this frame.
    pub fn record_block(&mut self, index: usize, patch: usize) {
        let patch = u32::try_from(patch).expect("fewer than 2^32 blocks");
        self.now[index] = Some(Drawn::Block { patch });
    }

    /// Node `index` draws its cross as the CPU list's vertices `first` .. `end`.
    pub fn record_cross(&mut self, index: usize, first: usize, end: usize) {
        let count = |n: usize| u32::try_from(n).expect("fewer than 2^32 vertices");
        self.now[index] = Some(Drawn::Cross {
            first: count(first),
            len: count(end - first),
        });
    }

    /// Compares this frame (its patch `words` and CPU list `cross_vertices`) with the last and
    /// keeps it for the next. Returns (vertices inserted, vertices deleted).
    pub fn end_frame(
        &mut self,
        tessellator: &BlockTessellator,
        words: &[u32],
        cross_vertices: &[SurfacePoint],
    ) -> (u64, u64) {
        let (mut inserted, mut deleted) = (0, 0);
        let vertices = |drawn: Option<Drawn>, words: &[u32]| match drawn {
            None => 0,
            Some(Drawn::Block { patch: k }) => {
                let (_, inner, outer) = tessellator.patch(patch(words, k));
                quad_patch_vertices(inner, outer)
            }
            Some(Drawn::Cross { len, .. }) => u64::from(len),
        };
        for (&now, &before) in self.now.iter().zip(&self.before) {
            let same = match (now, before) {
                (None, None) => true,
                (Some(Drawn::Block { patch: a }), Some(Drawn::Block { patch: b })) => {
                    same_patch_vertices(tessellator, patch(words, a), patch(&self.words_before, b))
                }
                (
                    Some(Drawn::Cross { first: a, len: n }),
                    Some(Drawn::Cross { first: b, len: m }),
                ) => same_vertices(
                    &cross_vertices[a as usize..(a + n) as usize],
                    &self.cross_vertices_before[b as usize..(b + m) as usize],
                ),
                _ => false,
            };
            if !same {
                inserted += vertices(now, words);
                deleted += vertices(before, &self.words_before);
            }
        }
        std::mem::swap(&mut self.now, &mut self.before);
        self.words_before.clear();
        self.words_before.extend_from_slice(words);
        self.cross_vertices_before.clear();
        self.cross_vertices_before.extend_from_slice(cross_vertices);
        (inserted, deleted)
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        (self.now.capacity() + self.before.capacity()) * size_of::<Option<Drawn>>()
            + self.words_before.capacity() * size_of::<u32>()
            + self.cross_vertices_before.capacity() * size_of::<SurfacePoint>()
    }
}

/// Patch `k` of a frame's `words`.
fn patch(words: &[u32], k: u32) -> &[u32] {
    let k = k as usize * PATCH_WORDS;
    &words[k..k + PATCH_WORDS]
}

/// Whether two vertex lists are the same, heights compared bit for bit.
fn same_vertices(a: &[SurfacePoint], b: &[SurfacePoint]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(a, b)| a.position == b.position && a.z.to_bits() == b.z.to_bits())
}

/// Whether patches `a` and `b` (their words) tessellate to the same vertices in the same order,
/// from their words alone (see the module doc). O(1) when they differ early, O(n + Σ m) at most.
pub fn same_patch_vertices(tessellator: &BlockTessellator, a: &[u32], b: &[u32]) -> bool {
    if a == b {
        return true;
    }
    let (rect, inner_a, outer_a) = tessellator.patch(a);
    let (rect_b, inner_b, outer_b) = tessellator.patch(b);
    let n = inner_a.segments();
    if rect != rect_b || n != inner_b.segments() {
        return false;
    }
    let same_lines = |lo: i64, hi: i64, ks: std::ops::Range<usize>, m: usize, sa, sb| {
        ks.into_iter().all(|k| {
            tessellate::edge_position(lo, hi, sa, m, k)
                == tessellate::edge_position(lo, hi, sb, m, k)
        })
    };
    if !same_lines(rect.x0, rect.x1, 1..n, n, inner_a, inner_b)
        || !same_lines(rect.y0, rect.y1, 1..n, n, inner_a, inner_b)
    {
        return false;
    }
    (SOUTH..=tessellate::WEST).all(|side| {
        let (sa, sb) = (outer_a[side], outer_b[side]);
        let m = sa.segments();
        let (lo, hi) = if side == SOUTH || side == NORTH {
            (rect.x0, rect.x1)
        } else {
            debug_assert!(side == EAST || side == tessellate::WEST);
            (rect.y0, rect.y1)
        };
        m == sb.segments() && same_lines(lo, hi, 0..m + 1, m, sa, sb)
    })
}

#[cfg(test)]
mod tests {
    use super::super::buffers::SpacingMode;
    use super::super::tessellate::{EdgeSpacing, PatchScratch, Rect};
    use super::*;
    use crate::sim::hierarchy::Hierarchy;
    use crate::sim::mesh::{CrackPolicy, SUBGRID_UNITS_PER_CELL, TriangleInfo, TriangleRole};
    use crate::sim::terrain::{Heightfield, Spacing};

    fn hierarchy() -> Hierarchy {
        let side = 65;
        let heights = (0..side * side)
            .map(|k| ((k % side) as f32 * 0.7).sin() * 9.0 + (k / side) as f32)
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap())
    }

    fn tessellated(tessellator: &BlockTessellator, patch: &[u32]) -> Vec<SurfacePoint> {
        let mut list = tessellator.empty_list(CrackPolicy::Stitched);
        let info = TriangleInfo {
            role: TriangleRole::Surface,
            group: 0,
            level: 0,
        };
        tessellator.add_patch(patch, &mut list, info, &mut PatchScratch::default());
        list.vertices().to_vec()
    }

    /// Factors an ulp apart (which mostly move no vertex), a segment apart, and a side apart.
    #[test]
    fn patches_have_the_same_vertices_exactly_when_their_tessellations_do() {
        let hierarchy = hierarchy();
        let rect = Rect {
            x0: 16 * SUBGRID_UNITS_PER_CELL,
            y0: 0,
            x1: 32 * SUBGRID_UNITS_PER_CELL,
            y1: 16 * SUBGRID_UNITS_PER_CELL,
        };
        let factors: Vec<f64> = [2.0f32, 2.5, 3.0, 4.0, 7.3, 63.9]
            .into_iter()
            .flat_map(|f| {
                [
                    f,
                    f32::from_bits(f.to_bits() - 1),
                    f32::from_bits(f.to_bits() + 1),
                ]
            })
            .map(f64::from)
            .collect();
        let fractional = BlockTessellator::new(&hierarchy, SpacingMode::FractionalEven);
        let spacing = EdgeSpacing::FractionalEven;
        let patch = |inner: f64, east: f64| {
            let outer = [
                spacing(inner),
                spacing(east),
                spacing(inner),
                spacing(inner),
            ];
            fractional.words(rect, spacing(inner), outer)
        };
        let (mut same, mut different) = (0, 0);
        for &inner_a in &factors {
            for &inner_b in &factors {
                for &east in &factors[..6] {
                    let (a, b) = (patch(inner_a, east), patch(inner_b, east));
                    let expected = tessellated(&fractional, &a) == tessellated(&fractional, &b);
                    assert_eq!(
                        same_patch_vertices(&fractional, &a, &b),
                        expected,
                        "inner {inner_a} against {inner_b}, east side {east}"
                    );
                    if expected {
                        same += 1;
                    } else {
                        different += 1;
                    }
                }
            }
        }
        // Beyond the pairs of equal words, some an ulp apart draw alike; most pairs do not.
        assert!(
            same > 6 * factors.len() && different > same,
            "{same} alike, {different} not"
        );
        let equal = BlockTessellator::new(&hierarchy, SpacingMode::Equal);
        for (m_a, m_b) in [(4, 4), (4, 8), (2, 1)] {
            let a = equal.words(rect, EdgeSpacing::Equal(4), [EdgeSpacing::Equal(m_a); 4]);
            let b = equal.words(rect, EdgeSpacing::Equal(4), [EdgeSpacing::Equal(m_b); 4]);
            assert_eq!(same_patch_vertices(&equal, &a, &b), m_a == m_b);
        }
    }
}
