//! The chunked algorithm's validators: the tree (once: it does not change between frames) and
//! each frame's selection. Tests call them after every frame; the mesh itself is checked by the
//! triangle-list validator like every algorithm's.
//!
//! Tree: every leaf's error is 0 (ε with synthesised detail); every internal chunk's is eq. 3.1
//! recomputed (its children's largest plus its own δ_m, rounded up once); every box holds its
//! children's and is the range of its samples; every skirt is as deep as [`SkirtDepth`] says
//! (the covering depth checked against every pair of chunks that touch without nesting,
//! O(chunks²)).
//!
//! Frame: drawn and culled chunks tile the terrain (each area once, every ancestor of one of
//! them refined, every child of a refined chunk accounted for); every refined chunk wants
//! refining (d < δ_c·C), is internal and not culled; every drawn chunk does not want refining
//! or is a leaf, or else is one whose children it requested (they were not available), and is
//! not culled; every culled chunk's box is outside the view volume; every
//! morph factor is eq. 3.5's; the draw order visits children nearest first with front-to-back
//! on (in south-west, south-east, north-west, north-east order without); the triangle list has
//! the triangles, skirts and culled regions the selection implies.

use super::super::block_lod::cull::box_outside_view;
use super::super::block_lod::grid::round_up_f32;
use super::ChunkedConfig;
use super::mesh::triangles_per_chunk;
use super::select::{Selection, SelectionSettings};
use super::source::Available;
use super::tree::{ChunkId, ChunkSource, ChunkTree, SkirtDepth};
use crate::sim::mesh::{TriangleList, TriangleRole};
use crate::sim::view::Camera;
use std::collections::{HashMap, HashSet};

/// The first thing found wrong with the chunk tree or a frame's selection.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ChunkedError {
    #[error("chunk {chunk:?} stores error {stored} m; eq. 3.1 gives {expected} m")]
    ErrorWrong {
        chunk: ChunkId,
        stored: f32,
        expected: f32,
    },
    #[error("chunk {chunk:?}: its height range {stored:?} is not its samples' {expected:?}")]
    HeightRangeWrong {
        chunk: ChunkId,
        stored: (f32, f32),
        expected: (f32, f32),
    },
    #[error("chunk {chunk:?}: skirt depth {depth} m, expected {expected} m ({rule})")]
    SkirtDepthWrong {
        chunk: ChunkId,
        depth: f32,
        expected: f32,
        rule: &'static str,
    },
    #[error("the drawn and culled chunks do not tile the terrain: {problem} (chunk {chunk:?})")]
    NotATiling {
        chunk: ChunkId,
        problem: &'static str,
    },
    #[error("chunk {chunk:?}: {problem}")]
    WrongDecision {
        chunk: ChunkId,
        problem: &'static str,
    },
    #[error("chunk {chunk:?} is drawn with morph factor {stored}; eq. 3.5 gives {expected}")]
    MorphFactorWrong {
        chunk: ChunkId,
        stored: f64,
        expected: f64,
    },
    #[error("the children of chunk {chunk:?} are not drawn in the expected order")]
    OrderWrong { chunk: ChunkId },
    #[error("the triangle list has {actual} {what}; the selection implies {expected}")]
    MeshCountWrong {
        what: &'static str,
        expected: u64,
        actual: u64,
    },
}

/// Checks the tree (see the module docs).
pub(super) fn validate_tree(tree: &ChunkTree, config: ChunkedConfig) -> Result<(), ChunkedError> {
    let leaf_level = tree.leaf_level();
    let all: Vec<ChunkId> = (0..=leaf_level)
        .flat_map(|level| {
            let per_side = 1u32 << level;
            (0..per_side * per_side).map(move |k| ChunkId {
                level,
                x: k % per_side,
                y: k / per_side,
            })
        })
        .collect();
    for &id in &all {
        let record = tree.record(id);
        let expected = if id.level == leaf_level {
            tree.leaf_error()
        } else {
            let children = id.children().map(|c| f64::from(tree.record(c).error));
            round_up_f32(children.into_iter().fold(0.0, f64::max) + tree.own_error(id))
        };
        if record.error.to_bits() != expected.to_bits() {
            return Err(ChunkedError::ErrorWrong {
                chunk: id,
                stored: record.error,
                expected,
            });
        }
        // The samples of the closed square.
        let (x0, y0, side) = tree.grid_square(id);
        let mut range = (f32::INFINITY, f32::NEG_INFINITY);
        for j in y0..=y0 + side {
            for i in x0..=x0 + side {
                let z = tree.sample(i, j);
                range = (range.0.min(z), range.1.max(z));
            }
        }
        if (record.z_min, record.z_max) != range {
            return Err(ChunkedError::HeightRangeWrong {
                chunk: id,
                stored: (record.z_min, record.z_max),
                expected: range,
            });
        }
    }
    let bound = |id: ChunkId| match (config.morph, id.parent()) {
        (true, Some(parent)) => tree.record(parent).error,
        _ => tree.record(id).error,
    };
    for &id in &all {
        let depth = tree.record(id).skirt_depth;
        match config.skirts {
            SkirtDepth::ChunkError => {
                if depth != tree.record(id).error {
                    return Err(ChunkedError::SkirtDepthWrong {
                        chunk: id,
                        depth,
                        expected: tree.record(id).error,
                        rule: "the chunk's own error, §3.2.6",
                    });
                }
            }
            SkirtDepth::Covering => {
                let geometry = tree.geometry();
                let (low, high) = geometry.square(id);
                let touches = |other: ChunkId| {
                    let ((a0, a1), (b0, b1)) = ((low.raw(), high.raw()), {
                        let (other_low, other_high) = geometry.square(other);
                        (other_low.raw(), other_high.raw())
                    });
                    a0.0 <= b1.0 && b0.0 <= a1.0 && a0.1 <= b1.1 && b0.1 <= a1.1
                };
                let beside = all
                    .iter()
                    .filter(|&&other| !id.contains(other) && !other.contains(id) && touches(other))
                    .map(|&other| f64::from(bound(other)))
                    .fold(0.0, f64::max);
                let expected = round_up_f32(f64::from(bound(id)) + beside);
                if depth != expected {
                    return Err(ChunkedError::SkirtDepthWrong {
                        chunk: id,
                        depth,
                        expected,
                        rule: "the deviation bounds of the chunk and its widest neighbour",
                    });
                }
            }
        }
    }
    Ok(())
}

/// What a frame's check reads.
pub(super) struct FrameView<'a> {
    pub(super) source: Available<'a>,
    pub(super) config: ChunkedConfig,
    pub(super) settings: &'a SelectionSettings,
    pub(super) selection: &'a Selection,
    pub(super) list: &'a TriangleList,
    pub(super) camera: &'a Camera,
}

/// Checks one frame's selection (see the module docs).
pub(super) fn validate_frame(view: &FrameView) -> Result<(), ChunkedError> {
    let (tree, selection, settings) = (&view.source, view.selection, view.settings);
    let geometry = view.source.tree.geometry();
    let finest_level = tree.finest_level();
    let requested: HashSet<ChunkId> = selection.requested.iter().copied().collect();
    let eye = view.camera.eye;
    let refined: HashSet<ChunkId> = selection.refined.iter().copied().collect();
    let mut area: u128 = 0;
    let full: u128 = 1u128 << (2 * finest_level);
    let mut seen = HashSet::new();
    let leaves = selection
        .drawn
        .iter()
        .map(|c| c.id)
        .chain(selection.culled.iter().copied());
    for id in leaves {
        if !seen.insert(id) {
            return Err(ChunkedError::NotATiling {
                chunk: id,
                problem: "drawn or culled twice",
            });
        }
        if refined.contains(&id) {
            return Err(ChunkedError::NotATiling {
                chunk: id,
                problem: "drawn or culled and refined",
            });
        }
        if let Some(parent) = id.parent()
            && !refined.contains(&parent)
        {
            return Err(ChunkedError::NotATiling {
                chunk: id,
                problem: "its parent is not refined",
            });
        }
        area += 1u128 << (2 * (finest_level - id.level));
    }
    if area != full {
        return Err(ChunkedError::NotATiling {
            chunk: ChunkId::ROOT,
            problem: "the areas do not add up to the terrain's",
        });
    }
    for &id in &selection.refined {
        if let Some(parent) = id.parent()
            && !refined.contains(&parent)
        {
            return Err(ChunkedError::NotATiling {
                chunk: id,
                problem: "refined, but its parent is not",
            });
        }
        let record = tree.record(id);
        let block = geometry.block_box(id, record);
        let d = block.lod_distance(eye, settings.projection);
        if !tree.is_internal(id) || !settings.threshold.refines(record.error, d) {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: "refined although d ≥ δ_c·C or a leaf",
            });
        }
        if settings.culling && box_outside_view(view.camera, &block) {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: "refined although outside the view volume",
            });
        }
    }
    for &id in &selection.culled {
        let block = geometry.block_box(id, tree.record(id));
        if !settings.culling || !box_outside_view(view.camera, &block) {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: "culled although culling is off or its box is in view",
            });
        }
    }
    for chunk in &selection.drawn {
        let id = chunk.id;
        let record = tree.record(id);
        let block = geometry.block_box(id, record);
        let d = block.lod_distance(eye, settings.projection);
        if d.to_bits() != chunk.distance.to_bits() {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: "drawn with another distance than its box's",
            });
        }
        let wants_children = tree.is_internal(id) && settings.threshold.refines(record.error, d);
        if wants_children != requested.contains(&id) {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: if wants_children {
                    "drawn although d < δ_c·C and internal, and its children not requested"
                } else {
                    "its children requested although it does not want refining"
                },
            });
        }
        if settings.culling && box_outside_view(view.camera, &block) {
            return Err(ChunkedError::WrongDecision {
                chunk: id,
                problem: "drawn although outside the view volume",
            });
        }
        let expected = match (settings.morph, id.parent()) {
            (true, Some(parent)) => {
                settings
                    .threshold
                    .morph_factor(record.error, tree.record(parent).error, d)
            }
            _ => 1.0,
        };
        if chunk.morph.to_bits() != expected.to_bits() || !(0.0..=1.0).contains(&chunk.morph) {
            return Err(ChunkedError::MorphFactorWrong {
                chunk: id,
                stored: chunk.morph,
                expected,
            });
        }
    }
    // Order: the first drawn chunk of each child's subtree, per refined chunk.
    let mut first_drawn: HashMap<ChunkId, usize> = HashMap::new();
    for (position, chunk) in selection.drawn.iter().enumerate() {
        for level in 0..=chunk.id.level {
            if let Some(ancestor) = chunk.id.ancestor_at(level) {
                first_drawn.entry(ancestor).or_insert(position);
            }
        }
    }
    for &id in &selection.refined {
        let children = id.children();
        let mut order = [0usize, 1, 2, 3];
        if view.config.front_to_back {
            let distance = |k: usize| {
                geometry
                    .block_box(children[k], tree.record(children[k]))
                    .distance(eye)
            };
            let distances = [0, 1, 2, 3].map(distance);
            order.sort_by(|&a, &b| distances[a].total_cmp(&distances[b]).then(a.cmp(&b)));
        }
        let positions: Vec<usize> = order
            .iter()
            .filter_map(|&k| first_drawn.get(&children[k]).copied())
            .collect();
        if positions.windows(2).any(|w| w[1] < w[0]) {
            return Err(ChunkedError::OrderWrong { chunk: id });
        }
    }
    let cells = geometry.cells;
    let n_drawn = selection.drawn.len() as u64;
    for (what, expected, actual) in [
        (
            "triangles",
            n_drawn * triangles_per_chunk(cells),
            view.list.n_triangles(),
        ),
        (
            "skirt triangles",
            n_drawn * 8 * u64::from(cells),
            view.list.role_count(TriangleRole::Skirt),
        ),
        (
            "culled regions",
            selection.culled.len() as u64,
            view.list.culled_regions().len() as u64,
        ),
    ] {
        if expected != actual {
            return Err(ChunkedError::MeshCountWrong {
                what,
                expected,
                actual,
            });
        }
    }
    Ok(())
}
