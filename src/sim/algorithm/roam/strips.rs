//! Triangle strips over the leaves (ROAM §7.2), kept incrementally and reported as triangles per
//! strip.
//!
//! **What a strip is here.** The leaves are taken in the bintree's Sierpinski (curve) order: the
//! two roots in turn, each triangle's children in the order that keeps the curve continuous
//! (child 0 first at even depths, child 1 first at odd depths, as in
//! [`Bintree::leaves_in_curve_order`]). In a conforming bintree mesh consecutive leaves in that
//! order always share an edge (a test checks it), so with swaps allowed the whole mesh would be a
//! single generalised strip and the figure would say nothing. We therefore model ROAM's strips
//! *without* swaps, cut along the curve: a swap-free strip (v0 v1 v2)(v1 v2 v3)… holds each
//! vertex in at most three consecutive triangles, so three consecutive junctions that turn
//! around one vertex (the four leaves they join share a corner) cannot all be kept; the last of
//! such three is a *fan junction*. The *junction* between consecutive leaves is *joined* when
//! they share an edge and it is
//! not the 1st, 4th, 7th, … of a run of consecutive fan junctions (such a run turns around a
//! single vertex, so it is at most as long as that vertex's fan, ≤ 8 triangles). Every maximal
//! run of joined junctions is then a valid swap-free strip (its first triangle can be oriented
//! freely), within a run of fan junctions the cuts are as few as possible, and
//! `strips = leaves − joined junctions`. The rule is local: a junction's status depends only on
//! the leaves from the start of its fan to the leaf after it. That is what makes the count
//! incremental, and it is the structure §7.2 maintains (strips along the bintree's recursive
//! order, repaired around each split and merge), so `triangles_per_strip` is the §7.2 figure for
//! these strips. It never reorders leaves to lengthen strips and does not count swap vertices.
//!
//! **Incremental.** With strips on, the [`Bintree`] keeps its leaves in a doubly linked list in
//! curve order (`prev`/`next`) and the number of joined junctions. A split replaces a leaf by its
//! two children in curve order and a merge replaces the two children by their parent; each
//! re-evaluates only the junctions whose status the change can affect (from the leaf before the
//! change to the end of the fan that runs past it), a bounded number, in O(1). Per frame the
//! strip count therefore costs O(splits + merges), not O(leaves). The previous implementation
//! recounted a greedy rule (no swaps, first triangle's orientation fixed by the vertex order)
//! over all leaves on every changed frame; its figure (2.58 triangles per strip on
//! `experiments/roam-pop.json`) is not the same rule.
//!
//! [`count_strips`] recounts from scratch in O(triangles) with the same rule: the validator and
//! the tests compare it with the incremental count.

use super::bintree::{BinTriangle, Bintree, TriangleKey};
use crate::sim::hierarchy::GridPoint;

/// Leaves per strip, from the incremental count in O(1). With strips off in the bintree, 0.
pub fn triangles_per_strip(bintree: &Bintree) -> f64 {
    if !bintree.tracks_strips() {
        return 0.0;
    }
    let strips = bintree
        .n_leaves()
        .saturating_sub(bintree.joined_junctions());
    bintree.n_leaves() as f64 / strips.max(1) as f64
}

/// The number of strips, recounted from scratch over the leaves in curve order with the rule of
/// the module comment: leaves minus joined junctions. O(triangles); reuses `stack` and `leaves`.
pub fn count_strips(
    bintree: &Bintree,
    stack: &mut Vec<(TriangleKey, bool)>,
    leaves: &mut Vec<TriangleKey>,
) -> u64 {
    bintree.leaves_in_curve_order(stack, leaves);
    let corners = |k: usize| corners(bintree.get(leaves[k]));
    let mut joined = 0;
    // Consecutive fan junctions ending at the current one.
    let mut run = 0u32;
    for k in 0..leaves.len().saturating_sub(1) {
        let fan =
            k >= 2 && shares_corner(&[corners(k - 2), corners(k - 1), corners(k), corners(k + 1)]);
        run = if fan { run + 1 } else { 0 };
        if shares_edge(corners(k), corners(k + 1)) && !(fan && run % 3 == 1) {
            joined += 1;
        }
    }
    leaves.len() as u64 - joined
}

type Corners = [GridPoint; 3];

fn corners(triangle: &BinTriangle) -> Corners {
    [
        triangle.shape.apex,
        triangle.shape.left,
        triangle.shape.right,
    ]
}

/// Whether two triangles share an edge: two of their corners coincide.
fn shares_edge(a: Corners, b: Corners) -> bool {
    a.iter().filter(|v| b.contains(v)).count() >= 2
}

/// Whether the triangles have a corner in common.
fn shares_corner(triangles: &[Corners]) -> bool {
    triangles[0]
        .iter()
        .any(|v| triangles[1..].iter().all(|t| t.contains(v)))
}

fn prev(bintree: &Bintree, key: TriangleKey) -> Option<TriangleKey> {
    bintree.get(key).prev
}

fn next(bintree: &Bintree, key: TriangleKey) -> Option<TriangleKey> {
    bintree.get(key).next
}

/// Whether the junction after the leaf `key` is a fan junction: it, the two before it and the
/// four leaves they join turn around one vertex.
fn is_fan(bintree: &Bintree, key: TriangleKey) -> bool {
    let window = || {
        let after = next(bintree, key)?;
        let before = prev(bintree, key)?;
        let first = prev(bintree, before)?;
        Some([first, before, key, after].map(|k| corners(bintree.get(k))))
    };
    window().is_some_and(|w| shares_corner(&w))
}

/// The junction after the leaf `key`: `Some((joined, fan))`, or `None` for the last leaf.
/// Walks back over the fan junctions before it (at most the triangles around one vertex).
fn junction(bintree: &Bintree, key: TriangleKey) -> Option<(bool, bool)> {
    let after = next(bintree, key)?;
    let edge = shares_edge(corners(bintree.get(key)), corners(bintree.get(after)));
    let fan = is_fan(bintree, key);
    let mut run = u32::from(fan);
    let mut back = prev(bintree, key);
    while fan && let Some(k) = back.filter(|&k| is_fan(bintree, k)) {
        run += 1;
        back = prev(bintree, k);
    }
    Some((edge && !(fan && run % 3 == 1), fan))
}

/// The joined junctions whose status a change of the leaves up to `last_changed` can affect:
/// those from the leaf `start` on, up to the first non-fan junction whose four leaves all lie
/// after `last_changed` (the junctions after it depend only on unchanged leaves).
fn stretch_joined(bintree: &Bintree, start: TriangleKey, last_changed: TriangleKey) -> u64 {
    let mut joined = 0;
    let mut key = Some(start);
    let mut steps_after: Option<u32> = None;
    while let Some(k) = key {
        let Some((is_joined, fan)) = junction(bintree, k) else {
            break;
        };
        joined += u64::from(is_joined);
        steps_after = if k == last_changed {
            Some(0)
        } else {
            steps_after.map(|s| s + 1)
        };
        if steps_after.is_some_and(|s| s >= 3) && !fan {
            break;
        }
        key = next(bintree, k);
    }
    joined
}

/// The children of a triangle at `depth`, in curve order.
fn in_curve_order(depth: u32, [c0, c1]: [TriangleKey; 2]) -> [TriangleKey; 2] {
    if depth.is_multiple_of(2) {
        [c0, c1]
    } else {
        [c1, c0]
    }
}

/// Points `prev`'s `next` and `next`'s `prev` at `first` and `last`, the new ends of the run
/// between them.
fn splice(
    bintree: &mut Bintree,
    prev: Option<TriangleKey>,
    first: TriangleKey,
    last: TriangleKey,
    next: Option<TriangleKey>,
) {
    bintree.triangles[first].prev = prev;
    bintree.triangles[last].next = next;
    if let Some(prev) = prev {
        bintree.triangles[prev].next = Some(first);
    }
    if let Some(next) = next {
        bintree.triangles[next].prev = Some(last);
    }
}

/// The base mesh's list: `roots[0]` then `roots[1]`.
pub(super) fn link_roots(bintree: &mut Bintree) {
    let [a, b] = bintree.roots;
    splice(bintree, None, a, a, Some(b));
    splice(bintree, Some(a), b, b, None);
    bintree.joined_junctions = stretch_joined(bintree, a, b);
}

/// After the leaf `parent` got its children: puts them in its place in the list and re-evaluates
/// the junctions around them. O(1): a few junctions, each walking back over at most one fan.
pub(super) fn replace_by_children(bintree: &mut Bintree, parent: TriangleKey) {
    let triangle = bintree.get(parent);
    let (prev, next) = (triangle.prev, triangle.next);
    let Some(children) = triangle.children else {
        return;
    };
    let [first, second] = in_curve_order(triangle.depth, children);
    let before = stretch_joined(bintree, prev.unwrap_or(parent), parent);
    splice(bintree, prev, first, first, Some(second));
    splice(bintree, Some(first), second, second, next);
    let triangle = &mut bintree.triangles[parent];
    triangle.prev = None;
    triangle.next = None;
    let after = stretch_joined(bintree, prev.unwrap_or(first), second);
    bintree.joined_junctions = bintree.joined_junctions + after - before;
}

/// Before the leaf children of `parent` are freed: puts `parent` back in their place in the list
/// and re-evaluates the junctions around it. O(1), as for a split.
pub(super) fn replace_children_by_parent(bintree: &mut Bintree, parent: TriangleKey) {
    let triangle = bintree.get(parent);
    let Some(children) = triangle.children else {
        return;
    };
    let [first, second] = in_curve_order(triangle.depth, children);
    let (prev, next) = (bintree.get(first).prev, bintree.get(second).next);
    let before = stretch_joined(bintree, prev.unwrap_or(first), second);
    splice(bintree, prev, parent, parent, next);
    for child in [first, second] {
        bintree.triangles[child].prev = None;
        bintree.triangles[child].next = None;
    }
    let after = stretch_joined(bintree, prev.unwrap_or(parent), parent);
    bintree.joined_junctions = bintree.joined_junctions + after - before;
}

#[cfg(test)]
mod tests {
    use super::super::merge::{is_mergeable, merge, primary_parent};
    use super::super::split::{SplitLog, split};
    use super::*;
    use crate::sim::hierarchy::Lattice;

    /// The bintree under test and the reference's buffers.
    struct Strips {
        bintree: Bintree,
        stack: Vec<(TriangleKey, bool)>,
        leaves: Vec<TriangleKey>,
    }

    impl Strips {
        fn new(level: u32) -> Strips {
            Strips {
                bintree: Bintree::new(&Lattice::new(level), true),
                stack: Vec::new(),
                leaves: Vec::new(),
            }
        }

        /// The strips the incremental count gives.
        fn incremental(&self) -> u64 {
            self.bintree.n_leaves() - self.bintree.joined_junctions()
        }

        /// Checks the incremental count and the linked list against a recount.
        fn check(&mut self, what: &str) {
            let expected = count_strips(&self.bintree, &mut self.stack, &mut self.leaves);
            assert_eq!(self.incremental(), expected, "{what}");
            let mut walked = Vec::new();
            let mut key = Some(self.leaves[0]);
            while let Some(k) = key {
                walked.push(k);
                key = self.bintree.get(k).next;
                assert!(walked.len() <= self.leaves.len(), "{what}: the list loops");
            }
            assert_eq!(walked, self.leaves, "{what}: list order");
            assert_eq!(self.bintree.get(self.leaves[0]).prev, None, "{what}");
        }

        fn leaves(&self) -> Vec<TriangleKey> {
            let mut leaves: Vec<_> = self
                .bintree
                .iter()
                .filter(|(_, t)| t.is_leaf())
                .map(|(k, t)| (self.bintree.lattice().id(t.shape.apex), t.depth, k))
                .collect();
            leaves.sort();
            leaves.into_iter().map(|(_, _, k)| k).collect()
        }

        fn mergeable(&self) -> Vec<TriangleKey> {
            let mut diamonds: Vec<_> = self
                .bintree
                .iter()
                .filter(|(k, t)| !t.is_leaf() && is_mergeable(&self.bintree, *k))
                .map(|(k, _)| primary_parent(&self.bintree, k))
                .map(|k| (self.bintree.get(k).split_vertex(), k))
                .collect();
            diamonds.sort_by_key(|(v, _)| v.map(|v| self.bintree.lattice().id(v)));
            diamonds.dedup();
            diamonds.into_iter().map(|(_, k)| k).collect()
        }
    }

    fn next_random(state: &mut u64) -> u64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *state >> 33
    }

    #[test]
    fn the_base_mesh_is_one_strip_of_two() {
        let mut strips = Strips::new(3);
        strips.check("base mesh");
        assert_eq!(strips.incremental(), 1);
        assert_eq!(triangles_per_strip(&strips.bintree), 2.0);
    }

    /// Whether every pair of consecutive leaves in curve order shares an edge.
    fn edge_connected(strips: &mut Strips) -> bool {
        count_strips(&strips.bintree, &mut strips.stack, &mut strips.leaves);
        strips.leaves.windows(2).all(|pair| {
            shares_edge(
                corners(strips.bintree.get(pair[0])),
                corners(strips.bintree.get(pair[1])),
            )
        })
    }

    #[test]
    fn a_uniform_mesh_is_cut_only_in_its_fans() {
        let mut strips = Strips::new(4);
        let mut log = SplitLog::default();
        for level in 1..=4 {
            for leaf in strips.leaves() {
                split(&mut strips.bintree, leaf, &mut log);
            }
            strips.check(&format!("uniform level {level}"));
            assert!(edge_connected(&mut strips), "level {level}");
        }
        assert_eq!(strips.bintree.n_leaves(), 32);
        let per_strip = triangles_per_strip(&strips.bintree);
        assert!((2.0..=3.0).contains(&per_strip), "{per_strip}");
    }

    #[test]
    fn the_incremental_count_equals_a_recount_after_every_split_and_merge() {
        let mut cut_meshes = 0;
        for seed in 1..=6u64 {
            let mut strips = Strips::new(5);
            let mut log = SplitLog::default();
            let mut state = seed;
            let (mut splits, mut merges) = (0, 0);
            for step in 0..600 {
                // Grow for a while, then mix, so that deep and shallow meshes both occur.
                let split_share = if step < 200 { 8 } else { 5 };
                if next_random(&mut state) % 10 < split_share {
                    let leaves = strips.leaves();
                    let leaf = leaves[next_random(&mut state) as usize % leaves.len()];
                    if split(&mut strips.bintree, leaf, &mut log) {
                        splits += 1;
                    }
                } else {
                    let diamonds = strips.mergeable();
                    if let Some(&primary) =
                        diamonds.get(next_random(&mut state) as usize % diamonds.len().max(1))
                        && merge(&mut strips.bintree, primary).is_some()
                    {
                        merges += 1;
                    }
                }
                strips.check(&format!("seed {seed}, step {step}"));
                assert!(edge_connected(&mut strips), "seed {seed}, step {step}");
                cut_meshes += u64::from(strips.incremental() > 1);
            }
            assert!(
                splits > 200 && merges > 100,
                "{splits} splits, {merges} merges"
            );
        }
        // Fans cut strips: the rule is not trivially "one strip".
        assert!(cut_meshes > 1000, "{cut_meshes}");
    }
}
