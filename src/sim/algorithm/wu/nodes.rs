//! Wu's quadtree nodes (Wu et al. 2001 §3.1, Figure 1's node hierarchy) by dense index, their
//! signed lives and where they are in the view. Only index arithmetic and the lookups that join
//! a node to its zone (`zone.rs`) and its sphere (`visibility.rs`); no queue state.
//!
//! A node is a square block, numbered as in [`SquareIndex`]: coarsest level first, row-major
//! within a level. Level k has 2^k × 2^k nodes; node (k, a, b) is centred at
//! (half·(2a+1), half·(2b+1)) with half = 2^n / 2^(k+1). Quadtree parent, children and
//! neighbours are index arithmetic; nothing is stored per node.

use super::cull::Cone;
use super::visibility::{Sight, SphereShape};
use crate::sim::hierarchy::{GridPoint, Hierarchy, SquareIndex};
use crate::sim::zone::{
    NodeErrors, SpeedBound, ZoneVariant, signed_life, split_zone_of, split_zone_scaled,
};
use glam::DVec3;

/// Sentinel for "no node".
pub(super) const NO_NODE: u32 = u32::MAX;

/// Index arithmetic over the nodes of one terrain.
#[derive(Clone, Copy, Debug)]
pub(super) struct Nodes {
    cells: u32,
    levels: u32,
    index: SquareIndex,
}

/// A node's level and position within its level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct NodeCoordinates {
    pub level: u32,
    pub a: u32,
    pub b: u32,
}

impl Nodes {
    pub fn new(hierarchy: &Hierarchy) -> Nodes {
        let lattice = hierarchy.lattice();
        Nodes {
            cells: lattice.cells(),
            levels: lattice.level(),
            index: hierarchy.square_index(),
        }
    }

    pub fn count(&self) -> usize {
        self.index.n_squares()
    }

    pub fn root(&self) -> u32 {
        0
    }

    pub fn coordinates(&self, node: u32) -> NodeCoordinates {
        // Level k starts at (4^k − 1)/3, so 3·node + 1 lies in [4^k, 4^(k+1)).
        let scaled = 3 * u64::from(node) + 1;
        let level = (63 - scaled.leading_zeros()) / 2;
        let first = ((1u64 << (2 * level)) - 1) / 3;
        let local = u64::from(node) - first;
        // Row-major within the level, 2^level nodes a row: a mask and a shift, not a division.
        NodeCoordinates {
            level,
            a: (local & ((1u64 << level) - 1)) as u32,
            b: (local >> level) as u32,
        }
    }

    fn node_at(&self, c: NodeCoordinates) -> u32 {
        let per_side = 1u32 << c.level;
        ((1u32 << (2 * c.level)) - 1) / 3 + c.b * per_side + c.a
    }

    /// Half-size of the nodes of a level.
    pub fn half(&self, level: u32) -> u32 {
        self.cells >> (level + 1)
    }

    /// Centre vertex and half-size of a node.
    pub fn centre(&self, node: u32) -> (GridPoint, u32) {
        let c = self.coordinates(node);
        let half = self.half(c.level);
        (
            GridPoint::new(half * (2 * c.a + 1), half * (2 * c.b + 1)),
            half,
        )
    }

    /// The node centred at a square vertex of the given half-size.
    pub fn node_of(&self, centre: GridPoint, half: u32) -> u32 {
        self.index.index(centre, half) as u32
    }

    /// The quadtree parent, or [`NO_NODE`] for the root.
    pub fn parent(&self, node: u32) -> u32 {
        let c = self.coordinates(node);
        if c.level == 0 {
            return NO_NODE;
        }
        self.node_at(NodeCoordinates {
            level: c.level - 1,
            a: c.a / 2,
            b: c.b / 2,
        })
    }

    /// The four sub-blocks, or `None` at the finest level.
    pub fn children(&self, node: u32) -> Option<[u32; 4]> {
        let c = self.coordinates(node);
        if c.level + 1 >= self.levels {
            return None;
        }
        let at = |da, db| {
            self.node_at(NodeCoordinates {
                level: c.level + 1,
                a: 2 * c.a + da,
                b: 2 * c.b + db,
            })
        };
        Some([at(0, 0), at(1, 0), at(0, 1), at(1, 1)])
    }
}

/// What a node's life depends on besides the eye.
#[derive(Clone, Debug)]
pub(super) struct LifeRule {
    /// Zone radius per metre of node error (from θ, see `zone::radius_per_error`).
    pub radius_per_error: f64,
    pub zone: ZoneVariant,
    pub speed: SpeedBound,
    /// δ under the configured nesting rule.
    pub errors: NodeErrors,
    pub spheres: SphereShape,
}

impl LifeRule {
    /// The signed life ℓ of `node` seen from `eye` (+∞ for a node without error).
    pub fn life(&self, hierarchy: &Hierarchy, nodes: &Nodes, node: u32, eye: DVec3) -> f64 {
        let (centre, half) = nodes.centre(node);
        let zone = split_zone_scaled(
            hierarchy,
            &self.errors,
            centre,
            half,
            self.radius_per_error,
            self.zone,
        );
        signed_life(zone.as_ref(), eye, self.speed)
    }

    /// The life of `node` and where its sphere is relative to `cone`, from one lookup of the
    /// node's data.
    pub fn life_and_sight(
        &self,
        hierarchy: &Hierarchy,
        nodes: &Nodes,
        node: u32,
        cone: &Cone,
    ) -> (f64, Sight) {
        let (centre, half) = nodes.centre(node);
        let error_and_range = self.errors.error_and_range(hierarchy, centre, half);
        let zone = split_zone_of(
            hierarchy,
            centre,
            half,
            error_and_range,
            self.radius_per_error,
            self.zone,
        );
        let (_, z_min, z_max) = error_and_range;
        let sphere = self.spheres.sphere(centre, half, z_min, z_max);
        (
            signed_life(zone.as_ref(), cone.eye(), self.speed),
            Sight::new(cone, &sphere),
        )
    }

    /// Where `node`'s sphere is relative to `cone`.
    pub fn sight(&self, hierarchy: &Hierarchy, nodes: &Nodes, node: u32, cone: &Cone) -> Sight {
        let (centre, half) = nodes.centre(node);
        Sight::new(cone, &self.spheres.node_sphere(hierarchy, centre, half))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    #[test]
    fn node_indices_round_trip_through_their_centres() {
        let field = Heightfield::new(33, vec![0.0; 33 * 33], Spacing { dx: 1.0, dy: 1.0 }).unwrap();
        let hierarchy = Hierarchy::new(field);
        let nodes = Nodes::new(&hierarchy);
        assert_eq!(nodes.count(), (32 * 32 - 1) / 3);
        for node in 0..nodes.count() as u32 {
            let (centre, half) = nodes.centre(node);
            assert_eq!(nodes.node_of(centre, half), node);
            if let Some(children) = nodes.children(node) {
                for child in children {
                    assert_eq!(nodes.parent(child), node);
                    let (child_centre, child_half) = nodes.centre(child);
                    assert_eq!(child_half * 2, half);
                    assert_eq!(child_centre.i.abs_diff(centre.i), child_half);
                }
            } else {
                assert_eq!(half, 1);
            }
        }
        assert_eq!(nodes.parent(nodes.root()), NO_NODE);
    }
}
