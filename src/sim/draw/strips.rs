//! Incremental non-generalised triangle strips over a changing set of leaf triangles, as ROAM'97
//! §7.2 describes them and Wu et al. 2001 §7 adopts them: the linking logic shared by ROAM
//! (`roam/strips.rs`, leaves of a bintree) and Wu (`wu/strips.rs`, leaves of the buffers' 4-8
//! mesh). Each supplies its triangles, their neighbours and where their links live through
//! [`StripMesh`]; this module decides nothing about which triangles are stripped (the caller
//! attaches and detaches them) and draws nothing: it keeps links and counts.
//!
//! "We consider only non-generalized strips (no vertex swapping). We use a simple, sub-optimal,
//! incremental approach … As triangles are split, merged or change view-culling status, minimal
//! re-linking of strips is performed. Deleting a triangle from a strip causes the strip to be
//! deleted (for a singleton strip), shortened on the end, or split in two. New triangles are first
//! inserted as singleton strips, which we subsequently attempt to glue to each of the neighboring
//! strip ends."
//!
//! **A strip** is a vertex sequence v0 v1 v2 … whose k-th triangle is (v_k, v_k+1, v_k+2): each
//! triangle shares with the next the edge opposite its oldest vertex. Each stripped triangle
//! stores its neighbours in the strip and the order of its three corners in that sequence
//! ([`StripLinks`]), so a strip's ends are known in O(1): a strip can grow at its head across
//! the head's edge (v0, v1), at its tail across the tail's edge (v_k+1, v_k+2), and a singleton
//! across any of its edges (its order is free). Gluing a new triangle t to a neighbour n across
//! their shared edge: to a singleton n (the two become a strip of two), to the tail of n's strip
//! if that edge is the tail's exit, or to its head if it is the head's entry. Once glued, t's
//! other free end is tried against its remaining neighbours, which may join two strips into one
//! (reversing the second when only its other orientation fits: O(its length)). Neighbours are
//! tried in the mesh's fixed order ([`StripMesh::neighbour`]), so the strips are deterministic.
//!
//! Each operation is O(1) apart from the reversal and the same-strip walk, so strips cost
//! O(triangles changed) per frame, times the length of the strips touched.

use crate::sim::hierarchy::GridPoint;
use std::fmt::Debug;

/// A stripped triangle's place in its strip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StripLinks<K> {
    pub prev: Option<K>,
    pub next: Option<K>,
    /// The triangle's corners (indices into [`StripMesh::corners`]) as v_k, v_k+1, v_k+2.
    pub order: [u8; 3],
}

/// How many strips there are and how many triangles they hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StripCounts {
    pub strips: u64,
    pub triangles: u64,
}

impl StripCounts {
    /// Triangles per strip (0 when nothing is stripped).
    pub fn triangles_per_strip(&self) -> f64 {
        if self.strips == 0 {
            0.0
        } else {
            self.triangles as f64 / self.strips as f64
        }
    }
}

/// A triangle's neighbour across one of its edges, with that edge (`None`: none there).
pub type Neighbour<K> = Option<(K, [GridPoint; 2])>;

/// A mesh whose triangles can be stripped: where their corners, neighbours and links are.
pub trait StripMesh {
    /// A triangle of the mesh.
    type Key: Copy + Eq + Debug;
    /// The triangle's corners in a fixed order (what [`StripLinks::order`] indexes).
    fn corners(&self, key: Self::Key) -> [GridPoint; 3];
    /// The neighbour across the triangle's `side`-th edge (0 to 2, the order glued in), with that
    /// edge; `None` at the mesh's boundary.
    fn neighbour(&self, key: Self::Key, side: usize) -> Neighbour<Self::Key>;
    fn links(&self, key: Self::Key) -> Option<StripLinks<Self::Key>>;
    fn links_mut(&mut self, key: Self::Key) -> Option<&mut StripLinks<Self::Key>>;
    fn set_links(&mut self, key: Self::Key, links: Option<StripLinks<Self::Key>>);
    fn counts_mut(&mut self) -> &mut StripCounts;
}

/// A stripped triangle's vertices v_k, v_k+1, v_k+2.
fn sequence<M: StripMesh>(mesh: &M, key: M::Key) -> [GridPoint; 3] {
    let c = mesh.corners(key);
    let order = mesh.links(key).map_or([0, 1, 2], |s| s.order);
    order.map(|k| c[k as usize])
}

/// The order (corner indices) that makes `key`'s sequence start with `first`, `second`.
fn order_starting<M: StripMesh>(
    mesh: &M,
    key: M::Key,
    first: GridPoint,
    second: GridPoint,
) -> [u8; 3] {
    let c = mesh.corners(key);
    let index = |p: GridPoint| c.iter().position(|&q| q == p).unwrap_or(0) as u8;
    let (a, b) = (index(first), index(second));
    [a, b, 3 - a - b]
}

/// The order that makes `key`'s sequence end with `second_last`, `last`.
fn order_ending<M: StripMesh>(
    mesh: &M,
    key: M::Key,
    second_last: GridPoint,
    last: GridPoint,
) -> [u8; 3] {
    let c = mesh.corners(key);
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
pub fn detach<M: StripMesh>(mesh: &mut M, key: M::Key) {
    let Some(own) = mesh.links(key) else {
        return;
    };
    mesh.set_links(key, None);
    mesh.counts_mut().triangles -= 1;
    if let Some(prev) = own.prev
        && let Some(s) = mesh.links_mut(prev)
    {
        s.next = None;
    }
    if let Some(next) = own.next
        && let Some(s) = mesh.links_mut(next)
    {
        s.prev = None;
    }
    match (own.prev, own.next) {
        (None, None) => mesh.counts_mut().strips -= 1,
        (Some(_), Some(_)) => mesh.counts_mut().strips += 1,
        _ => {}
    }
}

/// Inserts `key` as a singleton strip, then glues it to the neighbouring strip ends it fits
/// (see the module comment). The caller decides which triangles are stripped.
pub fn attach<M: StripMesh>(mesh: &mut M, key: M::Key) {
    if mesh.links(key).is_some() {
        return;
    }
    mesh.set_links(
        key,
        Some(StripLinks {
            prev: None,
            next: None,
            order: [0, 1, 2],
        }),
    );
    let counts = mesh.counts_mut();
    counts.triangles += 1;
    counts.strips += 1;
    // Each side's neighbour, looked up once (linking changes no neighbour).
    let mut neighbours: [Option<Neighbour<M::Key>>; 3] = [None; 3];
    let mut neighbour =
        |mesh: &M, side: usize| *neighbours[side].get_or_insert_with(|| mesh.neighbour(key, side));
    for side in 0..3 {
        let Some((neighbour, edge)) = neighbour(mesh, side) else {
            continue;
        };
        if mesh.links(neighbour).is_none() {
            continue;
        }
        if glue(mesh, key, neighbour, edge) {
            break;
        }
    }
    // Now try to grow the strip from t's other free end, if t is an end.
    let Some(own) = mesh.links(key) else {
        return;
    };
    if own.prev.is_none() == own.next.is_none() {
        return; // still a singleton (nothing fitted) or in the middle: nothing more to do
    }
    for side in 0..3 {
        let Some((neighbour, edge)) = neighbour(mesh, side) else {
            continue;
        };
        if mesh.links(neighbour).is_none() || same_strip(mesh, key, neighbour) {
            continue;
        }
        if extend_end(mesh, key, neighbour, edge) {
            break;
        }
    }
}

/// Glues the singleton `t` to its stripped neighbour `n` across `edge`; returns whether it fitted.
fn glue<M: StripMesh>(mesh: &mut M, t: M::Key, n: M::Key, edge: [GridPoint; 2]) -> bool {
    let Some(theirs) = mesh.links(n) else {
        return false;
    };
    match (theirs.prev, theirs.next) {
        (None, None) => {
            // Both singletons: n then t, across the shared edge.
            let order = order_ending(mesh, n, edge[0], edge[1]);
            mesh.set_links(
                n,
                Some(StripLinks {
                    prev: None,
                    next: Some(t),
                    order,
                }),
            );
            let order = order_starting(mesh, t, edge[0], edge[1]);
            mesh.set_links(
                t,
                Some(StripLinks {
                    prev: Some(n),
                    next: None,
                    order,
                }),
            );
        }
        (_, None) => {
            let [_, exit0, exit1] = sequence(mesh, n);
            if !same_edge([exit0, exit1], edge) {
                return false;
            }
            append(mesh, n, t, exit0, exit1);
        }
        (None, _) => {
            let [entry0, entry1, _] = sequence(mesh, n);
            if !same_edge([entry0, entry1], edge) {
                return false;
            }
            prepend(mesh, n, t, entry0, entry1);
        }
        _ => return false,
    }
    mesh.counts_mut().strips -= 1;
    true
}

/// Puts `t` after the tail `n` whose exit edge is (`exit0`, `exit1`).
fn append<M: StripMesh>(mesh: &mut M, n: M::Key, t: M::Key, exit0: GridPoint, exit1: GridPoint) {
    if let Some(s) = mesh.links_mut(n) {
        s.next = Some(t);
    }
    let order = order_starting(mesh, t, exit0, exit1);
    let next = mesh.links(t).and_then(|s| s.next);
    mesh.set_links(
        t,
        Some(StripLinks {
            prev: Some(n),
            next,
            order,
        }),
    );
}

/// Puts `t` before the head `n` whose entry edge is (`entry0`, `entry1`).
fn prepend<M: StripMesh>(mesh: &mut M, n: M::Key, t: M::Key, entry0: GridPoint, entry1: GridPoint) {
    if let Some(s) = mesh.links_mut(n) {
        s.prev = Some(t);
    }
    let order = order_ending(mesh, t, entry0, entry1);
    let prev = mesh.links(t).and_then(|s| s.prev);
    mesh.set_links(
        t,
        Some(StripLinks {
            prev,
            next: Some(n),
            order,
        }),
    );
}

/// Whether `a` and `b` are in the same strip (walks `a`'s strip: O(its length)).
fn same_strip<M: StripMesh>(mesh: &M, a: M::Key, b: M::Key) -> bool {
    let mut cursor = Some(a);
    while let Some(k) = cursor {
        if k == b {
            return true;
        }
        cursor = mesh.links(k).and_then(|s| s.prev);
    }
    let mut cursor = mesh.links(a).and_then(|s| s.next);
    while let Some(k) = cursor {
        if k == b {
            return true;
        }
        cursor = mesh.links(k).and_then(|s| s.next);
    }
    false
}

/// `t` is an end of its strip (not a singleton); tries to join the strip of its neighbour `n`
/// across `edge` at `t`'s free end. Returns whether it did.
fn extend_end<M: StripMesh>(mesh: &mut M, t: M::Key, n: M::Key, edge: [GridPoint; 2]) -> bool {
    let Some(own) = mesh.links(t) else {
        return false;
    };
    let [v0, v1, v2] = sequence(mesh, t);
    let Some(theirs) = mesh.links(n) else {
        return false;
    };
    let singleton = theirs.prev.is_none() && theirs.next.is_none();
    if own.next.is_none() {
        // t is a tail: its exit is (v1, v2); n must start with (v1, v2).
        if !same_edge([v1, v2], edge) {
            return false;
        }
        if singleton {
            append(mesh, t, n, v1, v2);
            mesh.counts_mut().strips -= 1;
            return true;
        }
        if theirs.prev.is_none() && sequence(mesh, n)[..2] == [v1, v2] {
            link(mesh, t, n);
            return true;
        }
        if theirs.next.is_none() && sequence(mesh, n)[1..] == [v2, v1] {
            reverse_strip(mesh, n, |links| links.prev);
            link(mesh, t, n);
            return true;
        }
    } else {
        // t is a head: its entry is (v0, v1); n must end with (v0, v1).
        if !same_edge([v0, v1], edge) {
            return false;
        }
        if singleton {
            prepend(mesh, t, n, v0, v1);
            mesh.counts_mut().strips -= 1;
            return true;
        }
        if theirs.next.is_none() && sequence(mesh, n)[1..] == [v0, v1] {
            link(mesh, n, t);
            return true;
        }
        if theirs.prev.is_none() && sequence(mesh, n)[..2] == [v1, v0] {
            reverse_strip(mesh, n, |links| links.next);
            link(mesh, n, t);
            return true;
        }
    }
    false
}

/// Joins the strip ending at `tail` and the strip starting at `head` (orders already fit).
fn link<M: StripMesh>(mesh: &mut M, tail: M::Key, head: M::Key) {
    if let Some(s) = mesh.links_mut(tail) {
        s.next = Some(head);
    }
    if let Some(s) = mesh.links_mut(head) {
        s.prev = Some(tail);
    }
    mesh.counts_mut().strips -= 1;
}

/// Reverses the strip at one of its ends, walking towards the other with `onwards`: every
/// triangle's neighbours swap and its vertex order reverses. O(strip length).
fn reverse_strip<M: StripMesh>(
    mesh: &mut M,
    end: M::Key,
    onwards: impl Fn(&StripLinks<M::Key>) -> Option<M::Key>,
) {
    let mut cursor = Some(end);
    while let Some(k) = cursor {
        let Some(s) = mesh.links_mut(k) else {
            break;
        };
        let following = onwards(s);
        std::mem::swap(&mut s.prev, &mut s.next);
        s.order.reverse();
        cursor = following;
    }
}

/// Checks the strips of `stripped` (every stripped triangle, each once): orders are
/// permutations, links are symmetric, consecutive triangles continue each other's vertex
/// sequence (so they share the edge the strip crosses), every strip walked from its head ends
/// (no cycle), and the counts match. O(triangles). `name` describes a triangle in errors.
pub fn check<M: StripMesh>(
    mesh: &M,
    stripped: impl IntoIterator<Item = M::Key>,
    counted: StripCounts,
    name: impl Fn(M::Key) -> String,
) -> Result<(), String> {
    let (mut strips, mut triangles, mut walked) = (0, 0, 0);
    for key in stripped {
        let Some(own) = mesh.links(key) else {
            return Err(format!("{}: listed as stripped, has no links", name(key)));
        };
        triangles += 1;
        let mut order = own.order;
        order.sort_unstable();
        if order != [0, 1, 2] {
            return Err(format!("{}: order {:?}", name(key), own.order));
        }
        if own.prev.is_none() {
            strips += 1;
            let mut cursor = Some(key);
            while let Some(k) = cursor {
                walked += 1;
                if walked > counted.triangles {
                    return Err(format!("the strip from {} does not end", name(key)));
                }
                cursor = mesh.links(k).and_then(|s| s.next);
            }
        }
        if let Some(next) = own.next {
            let Some(theirs) = mesh.links(next) else {
                return Err(format!("{}: next is not stripped", name(key)));
            };
            if theirs.prev != Some(key) {
                return Err(format!("{}: next does not link back", name(key)));
            }
            let (mine, following) = (sequence(mesh, key), sequence(mesh, next));
            if mine[1..] != following[..2] {
                return Err(format!(
                    "{} then {}: sequences {mine:?} and {following:?} do not continue",
                    name(key),
                    name(next)
                ));
            }
        }
    }
    let found = StripCounts { strips, triangles };
    if found != counted || walked != triangles {
        return Err(format!(
            "{strips} strips of {triangles} triangles ({walked} walked from their heads), \
             counted {} of {}",
            counted.strips, counted.triangles
        ));
    }
    Ok(())
}
