//! Regressions that only show in optimised builds: each test here failed under `cargo test
//! --release` (opt-level 3) while passing in the test profile (opt-level 1). CI runs this file on
//! the release profile too.

use roamsim::sim::hierarchy::{GridPoint, Lattice};
use roamsim::sim::mesh::VertexSet;

/// rustc 1.95 at opt-level >= 2 miscompiled `len += usize::from(absent)` in `VertexSet::insert`
/// inside a closure loop like the brute-force meshes' (push a vertex, insert it, push its
/// parents): `len` stayed at the corners' 4 while thousands of bits were set. The count must
/// equal the set's members after such a loop.
#[test]
fn vertex_set_len_matches_its_bits_in_an_insertion_loop() {
    let lattice = Lattice::new(7);
    let mut mesh = VertexSet::base_mesh(&lattice);
    let mut stack: Vec<GridPoint> = Vec::new();
    for j in 0..lattice.side() {
        for i in 0..lattice.side() {
            if (i + 2 * j) % 5 != 0 {
                continue;
            }
            stack.push(GridPoint::new(i, j));
            while let Some(vertex) = stack.pop() {
                if mesh.insert(lattice.id(vertex)) {
                    stack.extend(lattice.parents(vertex).as_slice());
                }
            }
        }
    }
    let members = mesh.iter().count();
    assert!(members > 1000, "the loop inserted only {members} vertices");
    assert_eq!(mesh.len(), members);
    let mut removed = 0;
    for id in mesh.clone().iter().filter(|id| id % 3 == 0) {
        removed += usize::from(mesh.remove(id));
    }
    assert_eq!(mesh.len(), members - removed);
    assert_eq!(mesh.len(), mesh.iter().count());
}
