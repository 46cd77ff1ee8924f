//! The brute-force reference for Röttger's criterion (§2.2, eq. 3): f evaluated on every block
//! of the grid, no traversal, closure by iterating to a fixed point, fans found by walking the
//! mesh's triangles.
//!
//! It shares with the algorithm only the criterion (`criterion.rs`), the clipping test
//! (`clip.rs`) and the stored d2 codes it reads; it is the ground truth of the differential
//! tests. The definitions it computes:
//!
//! - a block is **subdivided by the criterion** when it and every block above it pass (f < 1,
//!   and with clipping, the enlarged box may be seen);
//! - the mesh is the closure under 4-8 parents of the corners and those blocks' centres, plus
//!   every edge midpoint whose parents are all in it; the block centres the closure added are
//!   the **forced** subdivisions;
//! - a triangle belongs to the fan of the smallest subdivided block whose centre is one of its
//!   corners; a fan is a maximal run of consecutive ring slots covered by its triangles;
//! - a drawn vertex's blend is its block's (a centre) or the smaller of its two blocks' (an
//!   edge midpoint); it is drawn at z̄ + b·(z − z̄), z̄ the mean of the ends of the edge it
//!   bisects, and **morphs** when that differs from z in exact arithmetic (b < 1, z ≠ z̄).
//!
//! O(samples × closure rounds) per call: for tests, not for runs.

use super::clip::{ViewFrustum, fan_may_be_seen, generation_may_see};
use super::criterion::{Criterion, SMALLEST_BLEND_BYTE, blend_byte, subdivides};
use super::fans::FanCounts;
use super::matrix::QuadtreeMatrix;
use crate::sim::hierarchy::{GridPoint, Hierarchy, VertexClass, square_points};
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::triangles::for_each_triangle;
use crate::sim::view::Camera;

/// What the from-scratch evaluation reads.
#[derive(Clone, Copy)]
pub struct FromScratchView<'a> {
    pub hierarchy: &'a Hierarchy,
    /// The d2 codes (its blend entries are not read).
    pub matrix: &'a QuadtreeMatrix,
    pub criterion: Criterion,
    pub camera: &'a Camera,
    pub clipping: bool,
}

/// Everything the algorithm reports about a frame, computed from scratch.
#[derive(Clone, Debug, PartialEq)]
pub struct FromScratchFrame {
    pub mesh: VertexSet,
    pub subdivided_by_criterion: u64,
    pub forced: u64,
    /// Blend byte per vertex id: the subdivided blocks' at their centres, 0 elsewhere.
    pub blend_bytes: Vec<u8>,
    pub fans: FanCounts,
    /// Vertices drawn at a height other than their sample's.
    pub morphing: u64,
    /// The heights those vertices are drawn at, by vertex id (with geomorphing on).
    pub morphed: std::collections::BTreeMap<u32, f64>,
}

/// The centre of the block of twice the size containing the block at `centre` (half-size `half`).
fn parent_block(centre: GridPoint, half: u32) -> GridPoint {
    let cell = 4 * half;
    GridPoint::new(
        centre.i / cell * cell + 2 * half,
        centre.j / cell * cell + 2 * half,
    )
}

/// Every block's centre and half-size, coarsest first.
fn every_block(hierarchy: &Hierarchy) -> Vec<(GridPoint, u32)> {
    let lattice = hierarchy.lattice();
    let mut blocks = Vec::new();
    let mut half = lattice.cells() / 2;
    while half >= 1 {
        blocks.extend(square_points(lattice, half).map(|p| (p, half)));
        half /= 2;
    }
    blocks
}

/// The frame the criterion asks for at this view.
pub fn frame_from_scratch(view: &FromScratchView) -> FromScratchFrame {
    let hierarchy = view.hierarchy;
    let lattice = hierarchy.lattice();
    let n = lattice.n_vertices();
    let mut by_criterion = vec![false; n];
    let mut blend_bytes = vec![0u8; n];
    let mut n_by_criterion = 0;
    let frustum = ViewFrustum::new(view.camera);
    for (centre, half) in every_block(hierarchy) {
        let id = lattice.id(centre) as usize;
        let above = centre == lattice.root()
            || by_criterion[lattice.id(parent_block(centre, half)) as usize];
        let visible = !view.clipping || generation_may_see(hierarchy, &frustum, centre, half);
        if !above || !visible {
            continue;
        }
        let f = view.criterion.decision_variable(
            hierarchy,
            centre,
            half,
            view.matrix.d2(centre, half),
            view.camera.eye,
        );
        if subdivides(f) {
            by_criterion[id] = true;
            blend_bytes[id] = blend_byte(f);
            n_by_criterion += 1;
        }
    }

    let mut mesh = VertexSet::base_mesh(lattice);
    for id in 0..n as u32 {
        if by_criterion[id as usize] {
            mesh.insert(id);
        }
    }
    loop {
        let mut changed = false;
        for id in 0..n as u32 {
            if mesh.contains(id) {
                for parent in &lattice.parents(lattice.point(id)) {
                    changed |= mesh.insert(lattice.id(*parent));
                }
            }
        }
        if !changed {
            break;
        }
    }
    let mut n_subdivided = 0;
    for id in 0..n as u32 {
        let p = lattice.point(id);
        if mesh.contains(id) && matches!(lattice.classify(p), VertexClass::Square { .. }) {
            n_subdivided += 1;
            if blend_bytes[id as usize] == 0 {
                blend_bytes[id as usize] = SMALLEST_BLEND_BYTE;
            }
        }
    }
    for id in 0..n as u32 {
        let p = lattice.point(id);
        if matches!(lattice.classify(p), VertexClass::Rotated { .. })
            && lattice
                .parents(p)
                .as_slice()
                .iter()
                .all(|q| blend_bytes[lattice.id(*q) as usize] != 0)
        {
            mesh.insert(id);
        }
    }

    let fans = fans_from_triangles(view, &mesh, n_subdivided == 0);
    let mut morphed = std::collections::BTreeMap::new();
    for id in mesh.iter() {
        let p = lattice.point(id);
        let byte = match lattice.classify(p) {
            VertexClass::Corner => continue,
            VertexClass::Square { .. } => blend_bytes[id as usize],
            VertexClass::Rotated { .. } => lattice
                .parents(p)
                .as_slice()
                .iter()
                .map(|q| blend_bytes[lattice.id(*q) as usize])
                .min()
                .unwrap_or(u8::MAX),
        };
        let z = f64::from(hierarchy.height(p));
        let [a, b] = lattice
            .bisected_edge(p)
            .expect("every vertex but a corner bisects an edge");
        let mean = 0.5 * (f64::from(hierarchy.height(a)) + f64::from(hierarchy.height(b)));
        if byte < u8::MAX && z != mean {
            let blend = f64::from(byte) / 255.0;
            morphed.insert(id, mean + blend * (z - mean));
        }
    }
    FromScratchFrame {
        mesh,
        subdivided_by_criterion: n_by_criterion,
        forced: n_subdivided - n_by_criterion,
        blend_bytes,
        fans,
        morphing: morphed.len() as u64,
        morphed,
    }
}

/// The position of `p` on the ring of the block centred at `centre` (half-size `half`): 0 at
/// the south-west corner, counter-clockwise, corners even, edge midpoints odd.
fn ring_position(centre: GridPoint, half: u32, p: GridPoint) -> usize {
    let unit = |a: u32, b: u32| (i64::from(a) - i64::from(b)) / i64::from(half);
    match (unit(p.i, centre.i), unit(p.j, centre.j)) {
        (-1, -1) => 0,
        (0, -1) => 1,
        (1, -1) => 2,
        (1, 0) => 3,
        (1, 1) => 4,
        (0, 1) => 5,
        (-1, 1) => 6,
        (-1, 0) => 7,
        other => panic!("{p:?} is not on the ring of {centre:?} (half {half}): {other:?}"),
    }
}

/// The fans, from the mesh's triangles.
fn fans_from_triangles(view: &FromScratchView, mesh: &VertexSet, base_mesh: bool) -> FanCounts {
    let hierarchy = view.hierarchy;
    let lattice = hierarchy.lattice();
    let frustum = ViewFrustum::new(view.camera);
    let seen = |centre: GridPoint, half: u32| {
        !view.clipping || fan_may_be_seen(hierarchy, &frustum, centre, half)
    };
    if base_mesh {
        return if seen(lattice.root(), lattice.cells() / 2) {
            FanCounts {
                fans: 1,
                triangles: 2,
                vertices: 4,
            }
        } else {
            FanCounts::default()
        };
    }
    // Per owning block centre: the ring slots covered and the triangles.
    let mut owners: std::collections::BTreeMap<u32, ([bool; 8], u64)> = Default::default();
    for_each_triangle(lattice, mesh, |triangle| {
        let corners = [triangle.apex, triangle.left, triangle.right];
        let owner = corners
            .iter()
            .filter_map(|&p| match lattice.classify(p) {
                VertexClass::Square { half } => Some((half, p)),
                _ => None,
            })
            .min()
            .unwrap_or_else(|| panic!("{triangle:?} has no block centre among its corners"));
        let (half, centre) = owner;
        let others: Vec<GridPoint> = corners.into_iter().filter(|&p| p != centre).collect();
        let (a, b) = (
            ring_position(centre, half, others[0]),
            ring_position(centre, half, others[1]),
        );
        let (first, span) = match (b + 8 - a) % 8 {
            1 => (a, 1),
            7 => (b, 1),
            2 => (a, 2),
            6 => (b, 2),
            gap => panic!("{triangle:?} spans {gap} ring positions"),
        };
        let entry = owners.entry(lattice.id(centre)).or_default();
        for s in first..first + span {
            entry.0[s % 8] = true;
        }
        entry.1 += 1;
    });
    let mut counts = FanCounts::default();
    for (id, (slots, triangles)) in owners {
        let centre = lattice.point(id);
        let VertexClass::Square { half } = lattice.classify(centre) else {
            unreachable!()
        };
        if !seen(centre, half) {
            continue;
        }
        let runs = if slots.iter().all(|&s| s) {
            1
        } else {
            (0..8).filter(|&s| slots[s] && !slots[(s + 7) % 8]).count() as u64
        };
        counts.fans += runs;
        counts.triangles += triangles;
        counts.vertices += triangles + 2 * runs;
    }
    counts
}
