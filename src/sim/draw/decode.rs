//! Primitive assembly: how a GPU turns a draw call's indices into triangles (lists, strips,
//! fans, primitive restart). Pure index arithmetic; what the triangles are drawn at is the
//! caller's.

use super::{DrawCall, RESTART, Topology};

/// Calls `visit` with the three vertex indices of every triangle `indices` make under
/// `topology`, in drawing order: a strip's odd triangles have their first two corners swapped
/// (so that the strip keeps one winding), a fan's triangles are (first, previous, current).
/// [`RESTART`] starts a new strip or fan; in a list it is not allowed (debug-checked).
/// Patches are not indices: their tessellator makes their triangles (`super::patches`), and
/// this visits none.
pub(super) fn for_each_triangle(
    topology: Topology,
    indices: &[u32],
    mut visit: impl FnMut([u32; 3]),
) {
    match topology {
        Topology::TriangleList => {
            debug_assert!(
                !indices.contains(&RESTART),
                "primitive restart in a triangle list"
            );
            for corners in indices.chunks_exact(3) {
                visit([corners[0], corners[1], corners[2]]);
            }
        }
        Topology::TriangleStrip => {
            for strip in indices.split(|&k| k == RESTART) {
                for (n, window) in strip.windows(3).enumerate() {
                    visit(if n % 2 == 0 {
                        [window[0], window[1], window[2]]
                    } else {
                        [window[1], window[0], window[2]]
                    });
                }
            }
        }
        Topology::TriangleFan => {
            for fan in indices.split(|&k| k == RESTART) {
                for window in fan.windows(2).skip(1) {
                    visit([fan[0], window[0], window[1]]);
                }
            }
        }
        Topology::Patches => {}
    }
}

/// The triangles a draw call submits (degenerate ones included). O(1) for a list (three
/// indices a triangle, no restart), so that an incremental algorithm's frame does not pay a walk
/// over its whole index buffer; strips and fans are walked for their restarts.
pub(super) fn triangles_submitted(call: &DrawCall, indices: &[u32]) -> u64 {
    if call.topology == Topology::TriangleList {
        return u64::from(call.index_count / 3);
    }
    let range = call.first_index as usize..(call.first_index + call.index_count) as usize;
    let mut count = 0;
    for_each_triangle(call.topology, &indices[range], |_| count += 1);
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangles(topology: Topology, indices: &[u32]) -> Vec<[u32; 3]> {
        let mut seen = Vec::new();
        for_each_triangle(topology, indices, |t| seen.push(t));
        seen
    }

    #[test]
    fn a_strip_keeps_its_winding_and_restarts() {
        assert_eq!(
            triangles(Topology::TriangleStrip, &[0, 1, 2, 3, RESTART, 4, 5, 6]),
            vec![[0, 1, 2], [2, 1, 3], [4, 5, 6]]
        );
    }

    #[test]
    fn a_fan_turns_around_its_first_vertex() {
        assert_eq!(
            triangles(Topology::TriangleFan, &[0, 1, 2, 3, RESTART, 5, 6]),
            vec![[0, 1, 2], [0, 2, 3]]
        );
    }

    #[test]
    fn a_list_takes_three_at_a_time() {
        assert_eq!(
            triangles(Topology::TriangleList, &[0, 1, 2, 2, 1, 3]),
            vec![[0, 1, 2], [2, 1, 3]]
        );
    }
}
