//! The 4-8 fast path of the rasteriser (see `mod.rs`): corners on grid samples, a sample on an
//! edge inside, the samples of each row found by solving the three edge inequalities for a span;
//! and the bounding-box rasteriser it replaced, kept as its differential reference. Not here:
//! corners off the grid and the tie rule (`sample.rs`).

use crate::sim::mesh::position::{SUBGRID_BITS, SurfacePoint};

/// The 4-8 fast path: writes into `heights` (row-major, `lattice_side` per row) the height the
/// triangle draws at every `stride`-th grid sample inside it or on its edges. The corners must
/// be grid samples. Zero-area triangles write nothing.
///
/// Per row of samples, the span inside the triangle is solved from the three edge functions in
/// exact integer arithmetic (the same inside test as evaluating them at every sample of the
/// bounding box, which [`rasterise_lattice_triangle_by_box`] does), and the edge functions are
/// stepped along it: the same samples get the same heights, bit for bit.
pub fn rasterise_lattice_triangle(
    corners: &[SurfacePoint; 3],
    stride: i64,
    lattice_side: usize,
    heights: &mut [f32],
) {
    let xy = corners.map(|c| {
        let (x, y) = c.position.raw();
        (x >> SUBGRID_BITS, y >> SUBGRID_BITS)
    });
    let z = corners.map(|c| f64::from(c.z));
    let area2 = edge(xy[0], xy[1], xy[2]);
    if area2 == 0 {
        return;
    }
    let i_min = xy[0].0.min(xy[1].0).min(xy[2].0);
    let i_max = xy[0].0.max(xy[1].0).max(xy[2].0);
    let j_min = xy[0].1.min(xy[1].1).min(xy[2].1);
    let j_max = xy[0].1.max(xy[1].1).max(xy[2].1);
    // `a / stride` (truncating), a shift for a power-of-two stride and a ≥ 0.
    let over_stride = |a: i64| {
        if a >= 0 {
            floor_div(a, stride)
        } else {
            a / stride
        }
    };
    let first = |low: i64| over_stride(low + stride - 1) * stride;
    let (i0, j0) = (first(i_min), first(j_min));
    if i0 > i_max || j0 > j_max {
        return;
    }
    if over_stride(i_max - i0) + over_stride(j_max - j0) <= 2 {
        // At most four samples in the box (a small triangle at a coarse stride): testing
        // them costs less than solving the rows' spans, with the same result.
        rasterise_lattice_triangle_by_box(corners, stride, lattice_side, heights);
        return;
    }
    // The edge functions, negated for a clockwise triangle so that inside is "all ≥ 0"; the
    // height's sum and quotient are then negated in both terms, which IEEE rounding leaves
    // bit-identical.
    let sign = area2.signum();
    let edges = [(xy[1], xy[2]), (xy[2], xy[0]), (xy[0], xy[1])];
    let step_i = edges.map(|(a, b)| -sign * (b.1 - a.1) * stride);
    let step_j = edges.map(|(a, b)| sign * (b.0 - a.0) * stride);
    let mut row_start = edges.map(|(a, b)| sign * edge(a, b, (i0, j0)));
    let area = (sign * area2) as f64;
    let denominator = sign as f64 * area;
    // Dividing by a power of two is multiplying by its reciprocal, exactly (both round the
    // same real number once): every 4-8 triangle's doubled area is one, and a product is
    // cheaper than a quotient.
    let reciprocal = (area2.unsigned_abs().is_power_of_two() && (1.0 / denominator).is_normal())
        .then(|| 1.0 / denominator);
    let n_columns = over_stride(i_max - i0); // the last step along a row
    let mut j = j0;
    let mut row_index = over_stride(j0) as usize * lattice_side + over_stride(i0) as usize;
    while j <= j_max {
        // Steps n in 0..=n_columns with row_start[k] + n·step_i[k] ≥ 0 for every edge k.
        let (mut low, mut high) = (0i64, n_columns);
        for k in 0..3 {
            let (w, s) = (row_start[k], step_i[k]);
            if s > 0 {
                low = low.max(ceil_div(-w, s));
            } else if s < 0 {
                high = high.min(floor_div(w, -s));
            } else if w < 0 {
                high = -1;
            }
        }
        if low <= high {
            // The signed edge functions at the span's n-th sample, `(sign · w_k) as f64`, as
            // `first_k + n · step_k` in f64: integers far below 2^53, so every product and sum
            // is exact and the value is the integer's, bit for bit; with an `i32` count the
            // loop runs as vector instructions.
            let first = [0, 1, 2].map(|k| (sign * (row_start[k] + low * step_i[k])) as f64);
            let step = step_i.map(|s| (sign * s) as f64);
            let span = &mut heights[row_index + low as usize..=row_index + high as usize];
            let height_at = |n: i32| {
                let n = f64::from(n);
                (first[0] + n * step[0]) * z[0]
                    + (first[1] + n * step[1]) * z[1]
                    + (first[2] + n * step[2]) * z[2]
            };
            if let Some(reciprocal) = reciprocal {
                for (n, height) in (0i32..).zip(span) {
                    *height = (height_at(n) * reciprocal) as f32;
                }
            } else {
                for (n, height) in (0i32..).zip(span) {
                    *height = (height_at(n) / denominator) as f32;
                }
            }
        }
        for k in 0..3 {
            row_start[k] += step_j[k];
        }
        j += stride;
        row_index += lattice_side;
    }
}

/// ⌈a / b⌉ for b > 0.
fn ceil_div(a: i64, b: i64) -> i64 {
    -floor_div(-a, b)
}

/// ⌊a / b⌋ for b > 0: a shift when b is a power of two (a 4-8 triangle's edge steps are), a
/// division otherwise.
pub(crate) fn floor_div(a: i64, b: i64) -> i64 {
    if b & (b - 1) == 0 {
        a >> b.trailing_zeros()
    } else {
        a.div_euclid(b)
    }
}

/// [`rasterise_lattice_triangle`] as it was first written: every sample of the bounding box
/// tested. The differential reference of the span solver (and of the audit's figures).
pub fn rasterise_lattice_triangle_by_box(
    corners: &[SurfacePoint; 3],
    stride: i64,
    lattice_side: usize,
    heights: &mut [f32],
) {
    let xy = corners.map(|c| {
        let (x, y) = c.position.raw();
        (x >> SUBGRID_BITS, y >> SUBGRID_BITS)
    });
    let z = corners.map(|c| f64::from(c.z));
    let area2 = edge(xy[0], xy[1], xy[2]);
    if area2 == 0 {
        return;
    }
    let (i_min, i_max) = (xy.iter().map(|c| c.0).min(), xy.iter().map(|c| c.0).max());
    let (j_min, j_max) = (xy.iter().map(|c| c.1).min(), xy.iter().map(|c| c.1).max());
    let (i_min, i_max, j_min, j_max) = (
        i_min.unwrap_or(0),
        i_max.unwrap_or(0),
        j_min.unwrap_or(0),
        j_max.unwrap_or(0),
    );
    let first = |low: i64| (low + stride - 1) / stride * stride;
    let mut j = first(j_min);
    while j <= j_max {
        let mut i = first(i_min);
        while i <= i_max {
            let w0 = edge(xy[1], xy[2], (i, j));
            let w1 = edge(xy[2], xy[0], (i, j));
            let w2 = edge(xy[0], xy[1], (i, j));
            let inside = if area2 > 0 {
                w0 >= 0 && w1 >= 0 && w2 >= 0
            } else {
                w0 <= 0 && w1 <= 0 && w2 <= 0
            };
            if inside {
                let height =
                    (w0 as f64 * z[0] + w1 as f64 * z[1] + w2 as f64 * z[2]) / area2 as f64;
                let index = (j / stride) as usize * lattice_side + (i / stride) as usize;
                heights[index] = height as f32;
            }
            i += stride;
        }
        j += stride;
    }
}

/// Twice the signed area of (a, b, c), grid units.
fn edge(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mesh::position::SubgridPoint;

    #[test]
    fn floor_division_shifts_by_powers_of_two_and_divides_otherwise_with_the_same_results() {
        for a in -40i64..=40 {
            for b in 1i64..=17 {
                assert_eq!(floor_div(a, b), a.div_euclid(b), "{a} / {b}");
                assert_eq!(ceil_div(a, b), -(-a).div_euclid(b), "⌈{a} / {b}⌉");
            }
        }
    }

    #[test]
    fn the_span_rasteriser_writes_what_the_bounding_box_rasteriser_writes_bit_for_bit() {
        // Triangles on a 33² grid of any shape (areas that are not powers of two included:
        // the span's quotient, not its product by a reciprocal), both orientations, at
        // strides that divide the grid and one that does not.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u32| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % u64::from(n)) as u32
        };
        let mut reciprocal_areas = 0;
        for stride in [1usize, 2, 3] {
            let side = 32 / stride + 1;
            for _ in 0..300 {
                let corners: [SurfacePoint; 3] = std::array::from_fn(|_| SurfacePoint {
                    position: SubgridPoint::grid(next(33), next(33)),
                    z: next(2000) as f32 * 0.37 - 100.0,
                });
                let raw = corners.map(|c| c.position.raw());
                let area2 = (raw[1].0 - raw[0].0) * (raw[2].1 - raw[0].1)
                    - (raw[2].0 - raw[0].0) * (raw[1].1 - raw[0].1);
                if (area2 >> 32).unsigned_abs().is_power_of_two() {
                    reciprocal_areas += 1;
                }
                let mut by_span = vec![f32::NAN; side * side];
                let mut by_box = by_span.clone();
                rasterise_lattice_triangle(&corners, stride as i64, side, &mut by_span);
                rasterise_lattice_triangle_by_box(&corners, stride as i64, side, &mut by_box);
                let bits =
                    |heights: &[f32]| heights.iter().map(|h| h.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&by_span),
                    bits(&by_box),
                    "{corners:?} at stride {stride}"
                );
            }
        }
        assert!(reciprocal_areas > 0, "no power-of-two area was drawn");
    }
}
