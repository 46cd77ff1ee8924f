//! The spacing of each drawn M-block's four edges, per method (the module doc of `mod.rs`
//! gives the rules): the strips method cuts every edge at the block's own factor, Method II at
//! the larger of the two blocks' factors across it, Method I at one integer spacing that both
//! sides share, found through a map of which leaf owns each finest cell.
//!
//! What it is not: the selection of the leaves and their factors (`select.rs`, `mod.rs`) or the
//! tessellation of an edge (`tessellate.rs`).

use super::tessellate::{EAST, EdgeSpacing, NORTH, SOUTH, WEST};
use super::tree::NodeId;
use super::{Stitching, StitchingMethod};

impl Stitching<'_> {
    /// Method I: records which leaf owns each finest cell.
    pub(super) fn fill_owners(&mut self) {
        if self.config.method == StitchingMethod::PowerOfTwo {
            let finest = 1u32 << self.tree.depth_max();
            for (k, id) in self.leaves.iter().enumerate() {
                let size = 1u32 << (self.tree.depth_max() - id.depth);
                for y in id.iy * size..(id.iy + 1) * size {
                    for x in id.ix * size..(id.ix + 1) * size {
                        self.owners[(y * finest + x) as usize] = k as u32;
                    }
                }
            }
        }
    }

    /// Method I: the leaves (indices into `leaves`) across side `side` of leaf `k`, in order.
    fn neighbours_across(&self, k: usize, side: usize, out: &mut Vec<u32>) {
        out.clear();
        let id = self.leaves[k];
        let finest = 1i64 << self.tree.depth_max();
        let size = 1i64 << (self.tree.depth_max() - id.depth);
        let (x0, y0) = (i64::from(id.ix) * size, i64::from(id.iy) * size);
        let cells: Box<dyn Iterator<Item = (i64, i64)>> = match side {
            SOUTH => Box::new((x0..x0 + size).map(move |x| (x, y0 - 1))),
            NORTH => Box::new((x0..x0 + size).map(move |x| (x, y0 + size))),
            WEST => Box::new((y0..y0 + size).map(move |y| (x0 - 1, y))),
            _ => Box::new((y0..y0 + size).map(move |y| (x0 + size, y))),
        };
        for (x, y) in cells {
            if !(0..finest).contains(&x) || !(0..finest).contains(&y) {
                continue;
            }
            let owner = self.owners[(y * finest + x) as usize];
            if out.last() != Some(&owner) {
                out.push(owner);
            }
        }
    }

    /// Method I: a leaf's side length and interior spacing, raw units.
    fn pow2_size_and_spacing(&self, k: usize) -> (i64, i64) {
        let id = self.leaves[k];
        let square = self.tree.square(id);
        let size = square.x1 - square.x0;
        let factor = self.factor(id).expect("a leaf") as i64;
        (size, size / factor)
    }

    /// Method I: the spacing shared along side `side` of leaf `k`, computed from that side: the
    /// coarsest interior spacing of the leaf and every leaf across it, but no coarser than the
    /// smallest of them.
    fn pow2_side_spacing(&self, k: usize, side: usize, neighbours: &mut Vec<u32>) -> i64 {
        self.neighbours_across(k, side, neighbours);
        let (size, spacing) = self.pow2_size_and_spacing(k);
        let (mut coarsest, mut smallest) = (spacing, size);
        for &n in neighbours.iter() {
            let (size, spacing) = self.pow2_size_and_spacing(n as usize);
            coarsest = coarsest.max(spacing);
            smallest = smallest.min(size);
        }
        coarsest.min(smallest)
    }

    /// The outer spacings of leaf `k`'s four sides (south, east, north, west).
    pub(super) fn outer_spacings(&self, k: usize) -> [EdgeSpacing; 4] {
        let id = self.leaves[k];
        let own = self.factor(id).expect("a leaf");
        match self.config.method {
            StitchingMethod::Strips => [EdgeSpacing::FractionalEven(own); 4],
            StitchingMethod::Uniform => [SOUTH, EAST, NORTH, WEST].map(|side| {
                let (dx, dy) = match side {
                    SOUTH => (0, -1),
                    NORTH => (0, 1),
                    WEST => (-1, 0),
                    _ => (1, 0),
                };
                let (x, y) = (i64::from(id.ix) + dx, i64::from(id.iy) + dy);
                let per_side = 1i64 << id.depth;
                let f = if (0..per_side).contains(&x) && (0..per_side).contains(&y) {
                    let neighbour = NodeId {
                        depth: id.depth,
                        ix: x as u32,
                        iy: y as u32,
                    };
                    own.max(self.factor(neighbour).expect("uniform leaves"))
                } else {
                    own
                };
                EdgeSpacing::FractionalEven(f)
            }),
            StitchingMethod::PowerOfTwo => {
                let mut neighbours = Vec::new();
                let (size, _) = self.pow2_size_and_spacing(k);
                [SOUTH, EAST, NORTH, WEST].map(|side| {
                    self.neighbours_across(k, side, &mut neighbours);
                    let spacing = match neighbours[..] {
                        [n] if self.pow2_size_and_spacing(n as usize).0 > size => {
                            let opposite = (side + 2) % 4;
                            self.pow2_side_spacing(n as usize, opposite, &mut Vec::new())
                        }
                        _ => self.pow2_side_spacing(k, side, &mut neighbours),
                    };
                    EdgeSpacing::Equal((size / spacing) as u32)
                })
            }
        }
    }
}
