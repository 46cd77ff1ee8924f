//! The validator of Lindstrom's block quadtree (`blocks.rs`): what the coarse step relies on. Only
//! tests call it; it checks the structure built once, not a frame's decisions (the differential
//! tests against `brute_force.rs` do that).
//!
//! Checks that the owned sets partition the non-corner vertices, that every owned vertex lies in
//! its node's box (square × height range), that each node's list is sorted by δ, largest first,
//! with the δ the hierarchy gives, and that the subtree maxima and counts are what a
//! recomputation gives. O(samples + nodes).

use super::blocks::BlockTree;
use crate::sim::hierarchy::{Hierarchy, VertexClass};

/// The first thing found wrong with a block tree, as a sentence.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("block tree: {0}")]
pub struct BlockTreeError(String);

/// Checks `blocks` against the hierarchy and nested errors it was built from.
pub(super) fn validate_blocks(
    blocks: &BlockTree,
    hierarchy: &Hierarchy,
    nested_errors: &[f32],
) -> Result<(), BlockTreeError> {
    let lattice = hierarchy.lattice();
    let mut owners = vec![u32::MAX; lattice.n_vertices()];
    for (index, node) in blocks.nodes().iter().enumerate() {
        if node.depth > blocks.depth() || node.side != lattice.cells() >> node.depth {
            return Err(BlockTreeError(format!("node {index}: wrong depth or side")));
        }
        let ids = blocks.owned_ids(node);
        let deltas: Vec<f32> = blocks.owned_deltas(node).collect();
        if deltas.windows(2).any(|pair| pair[0] < pair[1]) {
            return Err(BlockTreeError(format!("node {index}: δ not sorted")));
        }
        for (&id, &delta) in ids.iter().zip(&deltas) {
            let point = lattice.point(id);
            if owners[id as usize] != u32::MAX {
                return Err(BlockTreeError(format!("{point:?} owned twice")));
            }
            owners[id as usize] = index as u32;
            if delta != nested_errors[id as usize] {
                return Err(BlockTreeError(format!("{point:?}: wrong δ {delta}")));
            }
            let z = f64::from(hierarchy.height(point));
            let inside = (node.i0..=node.i0 + node.side).contains(&point.i)
                && (node.j0..=node.j0 + node.side).contains(&point.j)
                && (node.z_min..=node.z_max).contains(&z);
            if !inside {
                return Err(BlockTreeError(format!(
                    "{point:?} lies outside the box of node {index}"
                )));
            }
        }
    }
    for id in 0..lattice.n_vertices() as u32 {
        let corner = matches!(lattice.classify(lattice.point(id)), VertexClass::Corner);
        if corner == (owners[id as usize] != u32::MAX) {
            return Err(BlockTreeError(format!(
                "{:?}: owned {} but corner {corner}",
                lattice.point(id),
                owners[id as usize] != u32::MAX
            )));
        }
    }
    for (index, node) in blocks.nodes().iter().enumerate() {
        let (mut delta_max, mut vertices, mut nodes) = (0.0f32, 0u64, 0u64);
        let mut stack = vec![index as u32];
        while let Some(k) = stack.pop() {
            let descendant = blocks.node(k);
            nodes += 1;
            vertices += blocks.owned_ids(descendant).len() as u64;
            delta_max = blocks
                .owned_deltas(descendant)
                .fold(delta_max, |a, b| a.max(b));
            stack.extend(blocks.children(k).into_iter().flatten());
        }
        if (delta_max, vertices, nodes)
            != (
                node.subtree_delta_max,
                node.subtree_vertices,
                node.subtree_nodes,
            )
        {
            return Err(BlockTreeError(format!("node {index}: wrong subtree data")));
        }
    }
    Ok(())
}
