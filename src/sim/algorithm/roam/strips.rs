//! Incremental triangle strips as ROAM'97 §7.2 describes them, kept over the drawn leaves.
//! Counted, not drawn (`mod.rs` says why): they feed only `triangles_per_strip`; the mesh the
//! runner reads and the buffers a GPU draws (`draw.rs`) are the bintree's leaves, whatever the
//! strips.
//!
//! "We consider only non-generalized strips (no vertex swapping). We use a simple, sub-optimal,
//! incremental approach … As triangles are split, merged or change view-culling status, minimal
//! re-linking of strips is performed. Deleting a triangle from a strip causes the strip to be
//! deleted (for a singleton strip), shortened on the end, or split in two. New triangles are first
//! inserted as singleton strips, which we subsequently attempt to glue to each of the neighboring
//! strip ends." That is what this module does, over the *drawn* leaves only: every leaf with
//! culling flags off, every leaf not labelled `Out` with them on.
//!
//! **A strip** is a vertex sequence v0 v1 v2 … whose k-th triangle is (v_k, v_k+1, v_k+2): each
//! triangle shares with the next the edge opposite its oldest vertex. Each stripped leaf stores
//! its neighbours in the strip and the order of its three corners in that sequence
//! ([`StripLinks`]), so a strip's ends are known in O(1): a strip can grow at its head across
//! the head's edge (v0, v1), at its tail across the tail's edge (v_k+1, v_k+2), and a singleton
//! across any of its edges (its order is free). Gluing a new triangle t to a neighbour n across
//! their shared edge: to a singleton n (the two become a strip of two), to the tail of n's strip
//! if that edge is the tail's exit, or to its head if it is the head's entry. Once glued, t's
//! other free end is tried against its remaining neighbours, which may join two strips into one
//! (reversing the second when only its other orientation fits: O(its length)). Neighbours are
//! tried in a fixed order (base, left, right), so the strips are deterministic.
//!
//! `triangles_per_strip` = stripped triangles / strips; the paper reports about 4 to 5 for its
//! strips. Each operation is O(1) apart from the reversal, so strips cost O(splits + merges +
//! culling changes) per frame.

use super::bintree::{Bintree, Side, StripLinks, TriangleKey};
use crate::sim::hierarchy::GridPoint;

/// Triangles per strip from the counts (0 when nothing is stripped).
pub fn triangles_per_strip(bintree: &Bintree) -> f64 {
    let counts = bintree.strip_counts();
    if counts.strips == 0 {
        0.0
    } else {
        counts.triangles as f64 / counts.strips as f64
    }
}

/// The corners of a triangle as grid points, in the order apex, left, right.
fn corners(bintree: &Bintree, key: TriangleKey) -> [GridPoint; 3] {
    let shape = bintree.get(key).shape;
    [shape.apex, shape.left, shape.right]
}

/// A stripped triangle's vertices v_k, v_k+1, v_k+2.
fn sequence(bintree: &Bintree, key: TriangleKey) -> [GridPoint; 3] {
    let c = corners(bintree, key);
    let order = bintree.get(key).strip.map_or([0, 1, 2], |s| s.order);
    order.map(|k| c[k as usize])
}

fn links(bintree: &Bintree, key: TriangleKey) -> Option<StripLinks> {
    bintree.get(key).strip
}

fn set_links(bintree: &mut Bintree, key: TriangleKey, links: StripLinks) {
    bintree.get_mut(key).strip = Some(links);
}

/// The order (corner indices) that makes `key`'s sequence start with `first`, `second`.
fn order_starting(
    bintree: &Bintree,
    key: TriangleKey,
    first: GridPoint,
    second: GridPoint,
) -> [u8; 3] {
    let c = corners(bintree, key);
    let index = |p: GridPoint| c.iter().position(|&q| q == p).unwrap_or(0) as u8;
    let (a, b) = (index(first), index(second));
    [a, b, 3 - a - b]
}

/// The order that makes `key`'s sequence end with `second_last`, `last`.
fn order_ending(
    bintree: &Bintree,
    key: TriangleKey,
    second_last: GridPoint,
    last: GridPoint,
) -> [u8; 3] {
    let c = corners(bintree, key);
    let index = |p: GridPoint| c.iter().position(|&q| q == p).unwrap_or(0) as u8;
    let (b, c2) = (index(second_last), index(last));
    [3 - b - c2, b, c2]
}

/// Whether the unordered edges are the same.
fn same_edge(a: [GridPoint; 2], b: [GridPoint; 2]) -> bool {
    (a[0] == b[0] && a[1] == b[1]) || (a[0] == b[1] && a[1] == b[0])
}

/// Takes `key` out of its strip (if it is in one): the strip is deleted, shortened at an end or
/// split in two.
pub fn detach(bintree: &mut Bintree, key: TriangleKey) {
    let Some(own) = links(bintree, key) else {
        return;
    };
    bintree.get_mut(key).strip = None;
    bintree.strip_counts.triangles -= 1;
    match (own.prev, own.next) {
        (None, None) => bintree.strip_counts.strips -= 1,
        (Some(prev), None) => {
            if let Some(s) = bintree.get_mut(prev).strip.as_mut() {
                s.next = None;
            }
        }
        (None, Some(next)) => {
            if let Some(s) = bintree.get_mut(next).strip.as_mut() {
                s.prev = None;
            }
        }
        (Some(prev), Some(next)) => {
            if let Some(s) = bintree.get_mut(prev).strip.as_mut() {
                s.next = None;
            }
            if let Some(s) = bintree.get_mut(next).strip.as_mut() {
                s.prev = None;
            }
            bintree.strip_counts.strips += 1;
        }
    }
}

/// Inserts the leaf `key` as a singleton strip, then glues it to the neighbouring strip ends
/// it fits (see the module comment). The caller decides which leaves are drawn.
pub fn attach(bintree: &mut Bintree, key: TriangleKey) {
    if links(bintree, key).is_some() {
        return;
    }
    set_links(
        bintree,
        key,
        StripLinks {
            prev: None,
            next: None,
            order: [0, 1, 2],
        },
    );
    bintree.strip_counts.triangles += 1;
    bintree.strip_counts.strips += 1;
    for side in [Side::Base, Side::Left, Side::Right] {
        let Some(neighbour) = bintree.get(key).neighbour(side) else {
            continue;
        };
        if links(bintree, neighbour).is_none() {
            continue;
        }
        let edge = bintree.get(key).edge(side);
        if glue(bintree, key, neighbour, edge) {
            break;
        }
    }
    // Now try to grow the strip from t's other free end, if t is an end.
    let Some(own) = links(bintree, key) else {
        return;
    };
    if own.prev.is_none() == own.next.is_none() {
        return; // still a singleton (nothing fitted) or in the middle: nothing more to do
    }
    for side in [Side::Base, Side::Left, Side::Right] {
        let Some(neighbour) = bintree.get(key).neighbour(side) else {
            continue;
        };
        if links(bintree, neighbour).is_none() || same_strip(bintree, key, neighbour) {
            continue;
        }
        let edge = bintree.get(key).edge(side);
        if extend_end(bintree, key, neighbour, edge) {
            break;
        }
    }
}

/// Glues the singleton `t` to its stripped neighbour `n` across `edge`; returns whether it fitted.
fn glue(bintree: &mut Bintree, t: TriangleKey, n: TriangleKey, edge: [GridPoint; 2]) -> bool {
    let Some(theirs) = links(bintree, n) else {
        return false;
    };
    match (theirs.prev, theirs.next) {
        (None, None) => {
            // Both singletons: n then t, across the shared edge.
            let order = order_ending(bintree, n, edge[0], edge[1]);
            set_links(
                bintree,
                n,
                StripLinks {
                    prev: None,
                    next: Some(t),
                    order,
                },
            );
            let order = order_starting(bintree, t, edge[0], edge[1]);
            set_links(
                bintree,
                t,
                StripLinks {
                    prev: Some(n),
                    next: None,
                    order,
                },
            );
            bintree.strip_counts.strips -= 1;
            true
        }
        (_, None) => {
            let [_, exit0, exit1] = sequence(bintree, n);
            if !same_edge([exit0, exit1], edge) {
                return false;
            }
            append(bintree, n, t, exit0, exit1);
            bintree.strip_counts.strips -= 1;
            true
        }
        (None, _) => {
            let [entry0, entry1, _] = sequence(bintree, n);
            if !same_edge([entry0, entry1], edge) {
                return false;
            }
            prepend(bintree, n, t, entry0, entry1);
            bintree.strip_counts.strips -= 1;
            true
        }
        _ => false,
    }
}

/// Puts `t` after the tail `n` whose exit edge is (`exit0`, `exit1`).
fn append(
    bintree: &mut Bintree,
    n: TriangleKey,
    t: TriangleKey,
    exit0: GridPoint,
    exit1: GridPoint,
) {
    if let Some(s) = bintree.get_mut(n).strip.as_mut() {
        s.next = Some(t);
    }
    let order = order_starting(bintree, t, exit0, exit1);
    let next = links(bintree, t).and_then(|s| s.next);
    set_links(
        bintree,
        t,
        StripLinks {
            prev: Some(n),
            next,
            order,
        },
    );
}

/// Puts `t` before the head `n` whose entry edge is (`entry0`, `entry1`).
fn prepend(
    bintree: &mut Bintree,
    n: TriangleKey,
    t: TriangleKey,
    entry0: GridPoint,
    entry1: GridPoint,
) {
    if let Some(s) = bintree.get_mut(n).strip.as_mut() {
        s.prev = Some(t);
    }
    let order = order_ending(bintree, t, entry0, entry1);
    let prev = links(bintree, t).and_then(|s| s.prev);
    set_links(
        bintree,
        t,
        StripLinks {
            prev,
            next: Some(n),
            order,
        },
    );
}

/// Whether `a` and `b` are in the same strip (walks `a`'s strip: O(its length)).
fn same_strip(bintree: &Bintree, a: TriangleKey, b: TriangleKey) -> bool {
    let mut cursor = Some(a);
    while let Some(k) = cursor {
        if k == b {
            return true;
        }
        cursor = links(bintree, k).and_then(|s| s.prev);
    }
    let mut cursor = links(bintree, a).and_then(|s| s.next);
    while let Some(k) = cursor {
        if k == b {
            return true;
        }
        cursor = links(bintree, k).and_then(|s| s.next);
    }
    false
}

/// `t` is an end of its strip (not a singleton); tries to join the strip of its neighbour `n`
/// across `edge` at `t`'s free end. Returns whether it did.
fn extend_end(bintree: &mut Bintree, t: TriangleKey, n: TriangleKey, edge: [GridPoint; 2]) -> bool {
    let Some(own) = links(bintree, t) else {
        return false;
    };
    let [v0, v1, v2] = sequence(bintree, t);
    let Some(theirs) = links(bintree, n) else {
        return false;
    };
    let singleton = theirs.prev.is_none() && theirs.next.is_none();
    if own.next.is_none() {
        // t is a tail: its exit is (v1, v2); n must start with (v1, v2).
        if !same_edge([v1, v2], edge) {
            return false;
        }
        if singleton {
            append(bintree, t, n, v1, v2);
            bintree.strip_counts.strips -= 1;
            return true;
        }
        if theirs.prev.is_none() && sequence(bintree, n)[..2] == [v1, v2] {
            link(bintree, t, n);
            return true;
        }
        if theirs.next.is_none() && sequence(bintree, n)[1..] == [v2, v1] {
            reverse_strip_ending(bintree, n);
            link(bintree, t, n);
            return true;
        }
    } else {
        // t is a head: its entry is (v0, v1); n must end with (v0, v1).
        if !same_edge([v0, v1], edge) {
            return false;
        }
        if singleton {
            prepend(bintree, t, n, v0, v1);
            bintree.strip_counts.strips -= 1;
            return true;
        }
        if theirs.next.is_none() && sequence(bintree, n)[1..] == [v0, v1] {
            link(bintree, n, t);
            return true;
        }
        if theirs.prev.is_none() && sequence(bintree, n)[..2] == [v1, v0] {
            reverse_strip_starting(bintree, n);
            link(bintree, n, t);
            return true;
        }
    }
    false
}

/// Joins the strip ending at `tail` and the strip starting at `head` (orders already fit).
fn link(bintree: &mut Bintree, tail: TriangleKey, head: TriangleKey) {
    if let Some(s) = bintree.get_mut(tail).strip.as_mut() {
        s.next = Some(head);
    }
    if let Some(s) = bintree.get_mut(head).strip.as_mut() {
        s.prev = Some(tail);
    }
    bintree.strip_counts.strips -= 1;
}

/// Reverses the strip whose tail is `tail` (it becomes its head). O(strip length).
fn reverse_strip_ending(bintree: &mut Bintree, tail: TriangleKey) {
    reverse_strip(bintree, tail, |links| links.prev);
}

/// Reverses the strip whose head is `head` (it becomes its tail). O(strip length).
fn reverse_strip_starting(bintree: &mut Bintree, head: TriangleKey) {
    reverse_strip(bintree, head, |links| links.next);
}

/// Reverses the strip at one of its ends, walking towards the other with `onwards`: every
/// triangle's neighbours swap and its vertex order reverses.
fn reverse_strip(
    bintree: &mut Bintree,
    end: TriangleKey,
    onwards: impl Fn(&StripLinks) -> Option<TriangleKey>,
) {
    let mut cursor = Some(end);
    while let Some(k) = cursor {
        let Some(s) = bintree.get_mut(k).strip.as_mut() else {
            break;
        };
        let following = onwards(s);
        std::mem::swap(&mut s.prev, &mut s.next);
        s.order.reverse();
        cursor = following;
    }
}

/// Checks the strips: every stripped triangle is a leaf, consecutive triangles continue each
/// other's vertex sequence, links are symmetric, and the counts match. O(triangles).
pub fn check(bintree: &Bintree) -> Result<(), String> {
    let (mut strips, mut triangles) = (0, 0);
    for (key, triangle) in bintree.iter() {
        let Some(own) = triangle.strip else {
            continue;
        };
        triangles += 1;
        if !triangle.is_leaf() {
            return Err(format!("{:?}: split, yet in a strip", triangle.shape));
        }
        let mut order = own.order;
        order.sort_unstable();
        if order != [0, 1, 2] {
            return Err(format!("{:?}: order {:?}", triangle.shape, own.order));
        }
        if own.prev.is_none() {
            strips += 1;
        }
        if let Some(next) = own.next {
            let Some(theirs) = bintree.triangles.get(next).and_then(|t| t.strip) else {
                return Err(format!("{:?}: next is not stripped", triangle.shape));
            };
            if theirs.prev != Some(key) {
                return Err(format!("{:?}: next does not link back", triangle.shape));
            }
            let (mine, following) = (sequence(bintree, key), sequence(bintree, next));
            if mine[1..] != following[..2] {
                return Err(format!(
                    "{:?} then {:?}: sequences {mine:?} and {following:?} do not continue",
                    triangle.shape,
                    bintree.get(next).shape
                ));
            }
        }
    }
    let counts = bintree.strip_counts();
    if (strips, triangles) != (counts.strips, counts.triangles) {
        return Err(format!(
            "{strips} strips of {triangles} triangles, counted {} of {}",
            counts.strips, counts.triangles
        ));
    }
    Ok(())
}
