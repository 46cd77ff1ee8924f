//! The regular grid both block algorithms draw, and geomorphing on it: a cell's two triangles,
//! the even neighbours an odd vertex morphs between, and its morphed height (Lauritsen–Nielsen
//! §3.2.3's simplification, every other row and column removed, and §3.2.8's morphing, eq. 3.4;
//! de Boer's geomipmaps, not in `papers/`). It is not a level choice or a morph factor
//! (`threshold.rs`), nor stitching or skirts (`geomipmap/stitch.rs`, `chunked/mesh.rs`): only the
//! arithmetic every block shares, so that blocks compute a shared vertex alike, bit for bit.
//!
//! A block at stride s is a grid of vertices every s samples, each cell split along its
//! south-west–north-east diagonal into the triangles (SW, SE, NE) and (SW, NE, NW). The next
//! coarser grid (stride 2s) keeps the even vertices; each odd vertex lies on an edge or on the
//! diagonal of a coarser cell: between its two neighbours along x for (odd, even), along y for
//! (even, odd), along the south-west–north-east diagonal for (odd, odd). Because every finer
//! triangle lies inside one coarser triangle, a grid whose odd vertices sit on those lines is
//! the coarser grid exactly: moving them there (geomorphing, factor 0) and back (factor 1)
//! changes the surface continuously, and the odd vertex's distance from that line is its
//! error in the paper's metric (Lauritsen–Nielsen fig. 3.4, de Boer's δ).

/// The two even neighbours (in grid steps, within the block) whose midpoint the odd vertex
/// (a, b) falls onto at the next coarser level; `None` for an even vertex.
pub(crate) fn coarser_neighbours(a: u32, b: u32) -> Option<[(u32, u32); 2]> {
    match (a % 2 == 1, b % 2 == 1) {
        (false, false) => None,
        (true, false) => Some([(a - 1, b), (a + 1, b)]),
        (false, true) => Some([(a, b - 1), (a, b + 1)]),
        (true, true) => Some([(a - 1, b - 1), (a + 1, b + 1)]),
    }
}

/// The height of a vertex of sample height `z` morphed by factor `f` (eq. 3.4): from the
/// coarser surface, the mean of `ends`, at f = 0 to `z` at f = 1. Computed in `f64` and rounded
/// once, the same way by every block that draws the vertex.
pub(crate) fn morphed_height(z: f32, ends: [f32; 2], f: f64) -> f32 {
    let coarse = 0.5 * (f64::from(ends[0]) + f64::from(ends[1]));
    (coarse + f * (f64::from(z) - coarse)) as f32
}

/// The two triangles of a cell with corners `sw`, `se`, `nw`, `ne` (vertex indices), split
/// along its south-west–north-east diagonal.
pub(crate) fn cell_triangles(sw: u32, se: u32, nw: u32, ne: u32) -> [[u32; 3]; 2] {
    [[sw, se, ne], [sw, ne, nw]]
}

/// f32 of `value` rounded towards +∞, so that a stored error never understates the one
/// computed.
pub(crate) fn round_up_f32(value: f64) -> f32 {
    let rounded = value as f32;
    if f64::from(rounded) < value {
        rounded.next_up()
    } else {
        rounded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn odd_vertices_fall_between_their_even_neighbours_and_even_ones_stay() {
        assert_eq!(coarser_neighbours(2, 4), None);
        assert_eq!(coarser_neighbours(3, 4), Some([(2, 4), (4, 4)]));
        assert_eq!(coarser_neighbours(2, 5), Some([(2, 4), (2, 6)]));
        assert_eq!(coarser_neighbours(1, 1), Some([(0, 0), (2, 2)]));
    }

    #[test]
    fn morphing_runs_from_the_coarser_surface_to_the_sample() {
        assert_eq!(morphed_height(10.0, [2.0, 4.0], 0.0), 3.0);
        assert_eq!(morphed_height(10.0, [2.0, 4.0], 1.0), 10.0);
        assert_eq!(morphed_height(10.0, [2.0, 4.0], 0.5), 6.5);
    }

    #[test]
    fn errors_are_rounded_up_when_stored() {
        let third = 1.0 / 3.0;
        assert!(f64::from(round_up_f32(third)) >= third);
        assert_eq!(round_up_f32(0.5), 0.5);
    }
}
