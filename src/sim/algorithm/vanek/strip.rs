//! The paper's height-map index buffers (Vaněk–Ježek 2004, §2, Table 1): a grid of m rows and
//! n columns of vertices (vertex index row·n + column) described as a triangle list, as
//! triangle fans, as one triangle strip per row, and as the single strip with degenerate
//! triangles that `vanek` draws every patch with.
//!
//! The single strip is built exactly as the paper's code fragment builds it: even rows run
//! west to east, odd rows east to west, each row followed by its last vertex index twice. Its
//! triangles are every three consecutive indices (every other one reversed, as a GPU reads a
//! strip); each cell is split along its north-west–south-east diagonal, and the two repeated
//! indices at the end of a row make four triangles with a repeated corner (the joins), except
//! after the last row, where they make two. So a strip of (2n + 2)(m − 1) indices holds
//! (2n + 2)(m − 1) − 2 triangles: 2(n − 1)(m − 1) cells' worth and 4(m − 1) − 2 joins.
//!
//! **Winding** ([`strip_triangle`]). A GPU reads triangle t of a strip as (v_t, v_t+1, v_t+2)
//! when t is even and (v_t+1, v_t, v_t+2) when t is odd, so every triangle of a strip has its
//! first one's winding (the joins keep the parity: four of them between two rows). The paper's
//! first triangle is row 0's south-west, north-west and south-east corners: clockwise seen from
//! above in roamsim's frame, whose rows run north (in a frame whose rows run south, as an image's
//! do, the same indices run counter-clockwise). roamsim draws every triangle counter-clockwise
//! (`sim::mesh::winding`), so it keeps the paper's indices (their count, their diagonals, the
//! joins) and reads the strip with the opposite parity, even triangles (v_t+1, v_t, v_t+2) and
//! odd ones (v_t, v_t+1, v_t+2), as a renderer does that draws the paper's buffer with its front
//! face set to clockwise (`glFrontFace(GL_CW)`).
//!
//! Cost: O(indices); the algorithm builds one strip per patch level once and reuses it.

/// Indices of the single strip with degenerate triangles over `m` rows and `n` columns
/// (m, n ≥ 2), in the paper's order.
pub fn degenerate_strip(m: u32, n: u32) -> Vec<u32> {
    let mut indices = Vec::with_capacity(degenerate_strip_len(m, n) as usize);
    degenerate_strip_into(m, n, &mut indices);
    indices
}

/// [`degenerate_strip`] into `indices` (emptied first, its capacity kept).
pub fn degenerate_strip_into(m: u32, n: u32, indices: &mut Vec<u32>) {
    indices.clear();
    for i in 0..m - 1 {
        if i % 2 == 1 {
            for j in (0..n).rev() {
                indices.push((i + 1) * n + j);
                indices.push(i * n + j);
            }
            indices.push((i + 1) * n);
            indices.push((i + 1) * n);
        } else {
            for j in 0..n {
                indices.push(i * n + j);
                indices.push((i + 1) * n + j);
            }
            indices.push((i + 2) * n - 1);
            indices.push((i + 2) * n - 1);
        }
    }
}

/// Triangle `t` of a strip whose indices from position t are `window`, its corners in the order
/// roamsim draws them: the GPU's order for a strip read with the opposite parity (see the
/// module docs), counter-clockwise seen from above for [`degenerate_strip`].
pub fn strip_triangle(t: usize, window: [u32; 3]) -> [u32; 3] {
    let [a, b, c] = window;
    if t.is_multiple_of(2) {
        [b, a, c]
    } else {
        [a, b, c]
    }
}

/// (2n + 2)(m − 1): the length of [`degenerate_strip`] (Table 1, last row).
pub fn degenerate_strip_len(m: u32, n: u32) -> u64 {
    (2 * u64::from(n) + 2) * (u64::from(m) - 1)
}

/// Triangles of [`degenerate_strip`]: its indices less 2.
pub fn degenerate_strip_triangles(m: u32, n: u32) -> u64 {
    degenerate_strip_len(m, n) - 2
}

/// The triangle list over the same grid (the same diagonals), 3 indices per triangle.
pub fn triangle_list(m: u32, n: u32) -> Vec<u32> {
    let mut indices = Vec::with_capacity(6 * (m as usize - 1) * (n as usize - 1));
    for i in 0..m - 1 {
        for j in 0..n - 1 {
            let (sw, se, nw, ne) = (
                i * n + j,
                i * n + j + 1,
                (i + 1) * n + j,
                (i + 1) * n + j + 1,
            );
            indices.extend_from_slice(&[sw, nw, se, nw, ne, se]);
        }
    }
    indices
}

/// Triangle fans over 2 × 2 cells each (m and n odd): per fan its centre, then its 8 border
/// vertices around and the first again. Returns the index buffer and the number of fans (the
/// parts drawn one call each).
pub fn triangle_fans(m: u32, n: u32) -> (Vec<u32>, u64) {
    assert!(
        m % 2 == 1 && n % 2 == 1,
        "fans need odd m and n, not {m} × {n}"
    );
    let mut indices = Vec::new();
    let mut fans = 0;
    for i in (1..m - 1).step_by(2) {
        for j in (1..n - 1).step_by(2) {
            let at = |di: i32, dj: i32| (i as i32 + di) as u32 * n + (j as i32 + dj) as u32;
            indices.push(at(0, 0));
            for (di, dj) in [
                (-1, -1),
                (-1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
                (1, 0),
                (1, -1),
                (0, -1),
            ] {
                indices.push(at(di, dj));
            }
            indices.push(at(-1, -1));
            fans += 1;
        }
    }
    (indices, fans)
}

/// One strip per row (the parts drawn one call each): the row's 2n indices.
pub fn row_strips(m: u32, n: u32) -> Vec<Vec<u32>> {
    (0..m - 1)
        .map(|i| (0..n).flat_map(|j| [i * n + j, (i + 1) * n + j]).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    const MIB: f64 = 1024.0 * 1024.0;

    /// The cells a list of triangles covers, as unordered vertex triples, degenerate ones left
    /// out.
    fn proper(triangles: impl Iterator<Item = [u32; 3]>) -> HashSet<[u32; 3]> {
        triangles
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .map(|mut t| {
                t.sort_unstable();
                t
            })
            .collect()
    }

    #[test]
    fn table_1_index_counts_for_a_1025_square_height_map() {
        let (m, n) = (1025u32, 1025u32);
        let cells = u64::from(m - 1) * u64::from(n - 1);
        let list = triangle_list(m, n);
        assert_eq!(list.len() as u64, 6 * cells);
        let (fans, parts) = triangle_fans(m, n);
        assert_eq!(fans.len() as u64 * 2, 5 * cells);
        assert_eq!(parts, cells / 4);
        assert_eq!(parts, 262_144);
        let strips = row_strips(m, n);
        assert_eq!(strips.len(), 1024);
        let strip_indices: u64 = strips.iter().map(|s| s.len() as u64).sum();
        assert_eq!(strip_indices, 2 * u64::from(n) * u64::from(m - 1));
        let one = degenerate_strip(m, n);
        assert_eq!(one.len() as u64, (2 * u64::from(n) + 2) * u64::from(m - 1));
        assert_eq!(one.len() as u64, degenerate_strip_len(m, n));
        // The table's buffer sizes, 32-bit indices, in MiB: 24, 10, 8.008, 8.016.
        let mib = |indices: u64| indices as f64 * 4.0 / MIB;
        assert_eq!(mib(list.len() as u64), 24.0);
        assert_eq!(mib(fans.len() as u64), 10.0);
        assert_eq!((mib(strip_indices) * 1000.0).round(), 8008.0);
        assert_eq!((mib(one.len() as u64) * 1000.0).round(), 8016.0);
    }

    #[test]
    fn the_single_strip_draws_every_cell_once_plus_its_joins() {
        for (m, n) in [(2, 2), (2, 5), (3, 3), (5, 3), (4, 6), (9, 9)] {
            let strip = degenerate_strip(m, n);
            let triangles: Vec<[u32; 3]> = strip.windows(3).map(|w| [w[0], w[1], w[2]]).collect();
            assert_eq!(triangles.len() as u64, degenerate_strip_triangles(m, n));
            let joins = triangles
                .iter()
                .filter(|t| t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
                .count() as u64;
            assert_eq!(joins, 4 * u64::from(m - 1) - 2, "{m} × {n}");
            let cells = u64::from(m - 1) * u64::from(n - 1);
            let from_strip = proper(triangles.into_iter());
            assert_eq!(from_strip.len() as u64, 2 * cells, "{m} × {n}");
            let from_list = proper(triangle_list(m, n).chunks(3).map(|c| [c[0], c[1], c[2]]));
            assert_eq!(from_strip, from_list, "{m} × {n}");
        }
    }

    #[test]
    fn every_triangle_of_the_single_strip_with_area_is_drawn_counter_clockwise() {
        for (m, n) in [(2, 2), (2, 5), (3, 3), (5, 3), (4, 6), (9, 9)] {
            let strip = degenerate_strip(m, n);
            // Vertex row·n + column sits at (column, row): x east, y north.
            let at = |v: u32| (i64::from(v % n), i64::from(v / n));
            let (mut ccw, mut flat) = (0, 0);
            for (t, w) in strip.windows(3).enumerate() {
                let [a, b, c] = strip_triangle(t, [w[0], w[1], w[2]]).map(at);
                let area2 = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
                assert!(area2 >= 0, "{m} × {n}, triangle {t}: clockwise");
                if area2 > 0 {
                    ccw += 1;
                } else {
                    flat += 1;
                }
            }
            assert_eq!(ccw, 2 * (m - 1) * (n - 1), "{m} × {n}");
            assert_eq!(flat, 4 * (m - 1) - 2, "{m} × {n}");
        }
    }

    #[test]
    fn fans_and_row_strips_cover_the_same_cells() {
        let (m, n) = (5, 7);
        let (fans, parts) = triangle_fans(m, n);
        assert_eq!(parts, 6);
        let mut fan_cells = 0;
        for fan in fans.chunks(10) {
            for k in 1..9 {
                fan_cells += usize::from(fan[k] != fan[k + 1]);
            }
        }
        assert_eq!(fan_cells, 2 * 4 * 6);
        let strips = row_strips(m, n);
        let strip_triangles: usize = strips.iter().map(|s| s.len() - 2).sum();
        assert_eq!(strip_triangles, 2 * 4 * 6);
    }
}
