//! The stitching-strips validator, run after every frame in tests (the mesh itself is checked
//! by the triangle-list validator under `--check`: the surface tiles the domain, no holes, every
//! edge closed):
//!
//! 1. the selection equals a brute-force recomputation: every node of every depth is a leaf
//!    exactly when each of its ancestors splits by the criterion and it does not (or is at the
//!    deepest level), split when it and its ancestors split, and each leaf's factor is the
//!    criterion's, bit for bit;
//! 2. the triangle count is what the factors say: 2(n − 2)² + Σ(m + n − 2) per drawn M-block,
//!    (row a + row b − 2) per drawn strip, 2 or 4 per P-block;
//! 3. every vertex of a stitch triangle is (position and height) a vertex of an M-block's
//!    triangles (checked when nothing is culled: a culled block draws none).

use super::strips::{self, PBlockShape};
use super::tessellate::{EdgeSpacing, quad_patch_triangles};
use super::tree::NodeId;
use super::{NodeState, Stitching, StitchingMethod};
use crate::sim::mesh::{SubgridPoint, TriangleRole};
use crate::sim::view::Camera;
use std::collections::HashSet;

/// The first thing found wrong with a frame.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StitchingError {
    #[error("node {node:?} is {found} in the selection; the criterion makes it {expected}")]
    Selection {
        node: NodeId,
        expected: String,
        found: String,
    },
    #[error(
        "the list has {found} triangles; the drawn blocks, strips and P-blocks make {expected}"
    )]
    TriangleCount { expected: u64, found: u64 },
    #[error("stitch vertex {vertex:?} (height {z}) is no M-block's vertex")]
    StitchVertexAlone { vertex: (f64, f64), z: f32 },
}

fn describe(state: NodeState) -> String {
    match state {
        NodeState::Unselected => "unselected".to_string(),
        NodeState::Split => "split".to_string(),
        NodeState::Leaf(f) => format!("a leaf at F = {f}"),
    }
}

pub(super) fn validate(alg: &Stitching, camera: &Camera) -> Result<(), StitchingError> {
    let tree = &alg.tree;
    // 1. Brute force, depth by depth: a node is reached when its parent splits.
    let mut reached = vec![false; tree.n_nodes()];
    reached[0] = true;
    for depth in 0..=tree.depth_max() {
        for iy in 0..1u32 << depth {
            for ix in 0..1u32 << depth {
                let id = NodeId { depth, ix, iy };
                let index = tree.index(id);
                let expected = if !reached[index] {
                    NodeState::Unselected
                } else {
                    let (split, factor) = alg.decide(camera, id);
                    let split = split
                        || (alg.config.method == StitchingMethod::Uniform
                            && depth < tree.depth_max());
                    if split {
                        for child in id.children() {
                            reached[tree.index(child)] = true;
                        }
                        NodeState::Split
                    } else {
                        NodeState::Leaf(factor)
                    }
                };
                let found = alg.state[index];
                let same = match (expected, found) {
                    (NodeState::Leaf(a), NodeState::Leaf(b)) => a.to_bits() == b.to_bits(),
                    (a, b) => a == b,
                };
                if !same {
                    return Err(StitchingError::Selection {
                        node: id,
                        expected: describe(expected),
                        found: describe(found),
                    });
                }
            }
        }
    }

    validate_mesh(alg)
}

/// Checks 2 and 3 alone.
pub(super) fn validate_mesh(alg: &Stitching) -> Result<(), StitchingError> {
    let tree = &alg.tree;
    // 2. Counts.
    let mut expected = 0;
    for &id in &alg.frame.drawn_leaves {
        let k = alg.leaf_index[tree.index(id)] as usize;
        let factor = alg.factor(id).expect("a drawn leaf");
        let inner = match alg.config.method {
            StitchingMethod::PowerOfTwo => EdgeSpacing::Equal(factor as u32),
            _ => EdgeSpacing::FractionalEven(factor),
        };
        expected += quad_patch_triangles(inner, alg.outer_spacings(k));
    }
    let factor = |n: NodeId| alg.factor(n);
    let mut row = Vec::new();
    for &(id, arm) in &alg.frame.drawn_strips {
        let mut vertices = 0;
        for (child, side) in arm.rows() {
            row.clear();
            strips::collect_side(tree, &factor, id.children()[child], side, &mut row);
            vertices += row.len() as u64;
        }
        expected += vertices - 2;
    }
    expected += alg.frame.p_blocks
        * match alg.config.p_block {
            PBlockShape::TwoTriangles => 2,
            PBlockShape::Fan => 4,
        };
    let list = alg.mesh.list();
    let found = list.n_triangles();
    if expected != found {
        return Err(StitchingError::TriangleCount { expected, found });
    }

    // 3. Strip vertices on M-block edges.
    if list.culled_regions().is_empty() {
        let vertices = list.vertices();
        let is_leaf_group = |group: u32| {
            let state = alg.state[group as usize];
            matches!(state, NodeState::Leaf(_))
        };
        let mut block_vertices: HashSet<(SubgridPoint, u32)> = HashSet::new();
        for (corners, info) in list.triangles().iter().zip(list.info()) {
            if info.role != TriangleRole::Stitch && is_leaf_group(info.group) {
                for &c in corners {
                    let v = vertices[c as usize];
                    block_vertices.insert((v.position, v.z.to_bits()));
                }
            }
        }
        for (corners, info) in list.triangles().iter().zip(list.info()) {
            if info.role == TriangleRole::Stitch {
                for &c in corners {
                    let v = vertices[c as usize];
                    if !block_vertices.contains(&(v.position, v.z.to_bits())) {
                        return Err(StitchingError::StitchVertexAlone {
                            vertex: v.position.grid_units(),
                            z: v.z,
                        });
                    }
                }
            }
        }
    }
    Ok(())
}
