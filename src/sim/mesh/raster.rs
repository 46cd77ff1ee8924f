//! Rasterising drawn triangles over a lattice of samples: which samples a triangle covers, and
//! the height it draws there. Shared by the audit (SPEC §7: mesh heights at audited samples) and
//! the triangle-list validator (every sample covered exactly once). It measures no error and
//! decides no sample set: which samples are audited is the audit's (`sim::audit::tiles`).
//!
//! Two rasterisers, both with exact integer inside tests:
//!
//! - [`rasterise_lattice_triangle`], the 4-8 fast path: corners on grid samples, a sample on an
//!   edge counts as inside (a closed 4-8 mesh has no T-junction, so both triangles of a shared
//!   edge give it the same height up to rounding, and the last one drawn writes it). This is
//!   the audit's arithmetic since the first release, kept bit for bit.
//! - [`SampleRaster`], the general path: corners anywhere (fixed-point [`super::SubgridPoint`]s), with a
//!   **tie rule** that gives every sample of a tiling to exactly one triangle: a sample on an edge
//!   or a vertex belongs to the triangle it would fall in if nudged by an infinitesimal step east
//!   (west on the domain's east border) and an infinitely smaller step north (south on the
//!   north border). This is the top-left rule of GPU rasterisers, written as the perturbation it
//!   is: every point of a tiling then has exactly one triangle, with shared vertices or not, so
//!   T-junctions, collapsed borders and stitches need no special case; positions are fixed-point
//!   integers (1/65 536 of a cell), so the inside tests are exact. Heights are
//!   interpolated inside the triangle; on an edge, from the edge's two ends only, in a canonical
//!   order of the ends, so two triangles with the same edge give a sample on it bit-identical
//!   heights and a crack gap is exactly zero where there is no crack; on a vertex, the vertex's
//!   own height.
//!
//! Samples are the points (i·step, j·step) in fixed-point units, i and j below the lattice's
//! side: the audit's every `stride`-th grid sample has step = stride cells; a finer lattice
//! (a truth surface with more detail than the source samples) would have a step below one cell.

use super::position::{SUBGRID_BITS, SurfacePoint};

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

/// A square lattice of samples in the terrain's plane, for the general rasteriser.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleRaster {
    /// Fixed-point units between neighbouring samples (positive).
    step: i64,
    /// Samples per side.
    side: usize,
    /// The domain's largest coordinate, fixed-point: samples on it are nudged back inside.
    domain_max: i64,
}

/// One sample a triangle covers (edges and vertices included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoveredSample {
    /// Row-major index into the lattice.
    pub index: usize,
    /// The triangle's height there, metres.
    pub height: f64,
    /// Whether the tie rule gives the sample to this triangle (always, for a sample strictly
    /// inside).
    pub owned: bool,
}

impl SampleRaster {
    /// Samples every `step` fixed-point units, `side` per side, over a domain whose largest
    /// coordinate is `domain_max`.
    ///
    /// # Panics
    /// When `step` is not positive.
    pub fn new(step: i64, side: usize, domain_max: i64) -> SampleRaster {
        assert!(step > 0, "sample step {step}");
        SampleRaster {
            step,
            side,
            domain_max,
        }
    }

    pub fn side(&self) -> usize {
        self.side
    }

    /// Calls `visit` for every sample of the lattice inside the closed triangle, in row-major
    /// order. Zero-area triangles cover nothing. O(samples in the bounding box).
    pub fn for_each_covered_sample(
        &self,
        corners: &[SurfacePoint; 3],
        mut visit: impl FnMut(CoveredSample),
    ) {
        let point = |k: usize| {
            let (x, y) = corners[k].position.raw();
            (i128::from(x), i128::from(y))
        };
        let (a, mut b, mut c) = (point(0), point(1), point(2));
        let (za, mut zb, mut zc) = (corners[0].z, corners[1].z, corners[2].z);
        let area2 = cross(sub(b, a), sub(c, a));
        if area2 == 0 {
            return;
        }
        if area2 < 0 {
            std::mem::swap(&mut b, &mut c);
            std::mem::swap(&mut zb, &mut zc);
        }
        let area2 = area2.abs() as f64;
        let step = i128::from(self.step);
        let last = self.side as i128 - 1;
        let range = |low: i128, high: i128| {
            let first = ((low + step - 1).div_euclid(step)).max(0);
            let last = high.div_euclid(step).min(last);
            (first, last)
        };
        let (i_first, i_last) = range(a.0.min(b.0).min(c.0), a.0.max(b.0).max(c.0));
        let (j_first, j_last) = range(a.1.min(b.1).min(c.1), a.1.max(b.1).max(c.1));
        let domain_max = i128::from(self.domain_max);
        // Counter-clockwise: the interior is on the left of a→b, b→c, c→a.
        let edges = [(b, c), (c, a), (a, b)];
        for j in j_first..=j_last {
            let y = j * step;
            for i in i_first..=i_last {
                let s = (i * step, y);
                let w = edges.map(|(p, q)| cross(sub(q, p), sub(s, p)));
                if w.iter().any(|&w| w < 0) {
                    continue;
                }
                let nudge = (
                    if s.0 >= domain_max { -1 } else { 1 },
                    if s.1 >= domain_max { -1 } else { 1 },
                );
                let owned = edges
                    .iter()
                    .zip(&w)
                    .all(|(&(p, q), &w)| w > 0 || owns_edge(sub(q, p), nudge));
                let zeros = w.iter().filter(|&&w| w == 0).count();
                let height = match zeros {
                    0 => {
                        (w[0] as f64 * f64::from(za)
                            + w[1] as f64 * f64::from(zb)
                            + w[2] as f64 * f64::from(zc))
                            / area2
                    }
                    1 => {
                        let k = w.iter().position(|&w| w == 0).unwrap_or(0);
                        let ends = [(b, zb), (c, zc), (a, za)];
                        let (p, q) = (ends[k], ends[(k + 1) % 3]);
                        along_edge(p, q, s)
                    }
                    // On two edges: the vertex they share (the edge opposite to the one
                    // that is not zero).
                    _ => {
                        let k = w.iter().position(|&w| w != 0).unwrap_or(0);
                        f64::from([za, zb, zc][k])
                    }
                };
                visit(CoveredSample {
                    index: j as usize * self.side + i as usize,
                    height,
                    owned,
                });
            }
        }
    }
}

impl SampleRaster {
    /// For a triangle of zero area in the plane (a vertical one, such as a skirt), calls
    /// `visit(index, low, high)` for every sample of the lattice on its projection (a segment,
    /// or a point), with the lowest and highest height the triangle reaches above that sample.
    /// Heights along an edge are interpolated from the edge's two ends in the canonical order
    /// [`SampleRaster::for_each_covered_sample`] uses, so a skirt's top edge gives a sample on it
    /// exactly the height a surface triangle with the same edge gives it. Triangles with area
    /// visit nothing. O(samples along the segment).
    pub fn for_each_vertical_span(
        &self,
        corners: &[SurfacePoint; 3],
        mut visit: impl FnMut(usize, f64, f64),
    ) {
        let ends: [((i128, i128), f32); 3] = corners.map(|c| {
            let (x, y) = c.position.raw();
            ((i128::from(x), i128::from(y)), c.z)
        });
        let (a, b, c) = (ends[0].0, ends[1].0, ends[2].0);
        if cross(sub(b, a), sub(c, a)) != 0 {
            return;
        }
        // The segment's ends: the two corners farthest apart.
        let pairs = [(0, 1), (1, 2), (0, 2)];
        let (p, q) = pairs
            .iter()
            .map(|&(u, v)| (ends[u].0, ends[v].0))
            .max_by_key(|&(u, v)| dot(sub(v, u), sub(v, u)))
            .unwrap_or((a, a));
        let step = i128::from(self.step);
        let last = self.side as i128 - 1;
        let mut span_at = |s: (i128, i128)| {
            let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..3 {
                let (u, v) = (ends[k], ends[(k + 1) % 3]);
                let heights = if u.0 == v.0 {
                    if u.0 != s {
                        continue;
                    }
                    [f64::from(u.1), f64::from(v.1)]
                } else {
                    // Collinear with the segment: on the edge when between its ends.
                    let between = |m: i128, n: i128, w: i128| m.min(n) <= w && w <= m.max(n);
                    if !(between(u.0.0, v.0.0, s.0) && between(u.0.1, v.0.1, s.1)) {
                        continue;
                    }
                    let z = along_edge(u, v, s);
                    [z, z]
                };
                low = low.min(heights[0].min(heights[1]));
                high = high.max(heights[0].max(heights[1]));
            }
            if low <= high {
                let (i, j) = (s.0 / step, s.1 / step);
                visit(j as usize * self.side + i as usize, low, high);
            }
        };
        let on_lattice = |v: i128| v % step == 0 && (0..=last).contains(&(v / step));
        let d = sub(q, p);
        if d == (0, 0) {
            if on_lattice(p.0) && on_lattice(p.1) {
                span_at(p);
            }
            return;
        }
        // Walk the axis the segment runs along most; keep the points whose other coordinate
        // is exactly on the lattice.
        let (along, across) = if d.0.abs() >= d.1.abs() {
            (0, 1)
        } else {
            (1, 0)
        };
        let get = |point: (i128, i128), w: usize| if w == 0 { point.0 } else { point.1 };
        let (from, to) = (
            get(p, along).min(get(q, along)),
            get(p, along).max(get(q, along)),
        );
        let first = ((from + step - 1).div_euclid(step)).max(0);
        let final_index = to.div_euclid(step).min(last);
        for k in first..=final_index {
            let t = k * step;
            let offset = (t - get(p, along)) * get(d, across);
            if offset % get(d, along) != 0 {
                continue;
            }
            let other = get(p, across) + offset / get(d, along);
            if !on_lattice(other) {
                continue;
            }
            let s = if along == 0 { (t, other) } else { (other, t) };
            span_at(s);
        }
    }
}

/// The height at `s` on the segment between `p` and `q` (their heights interpolated), computed
/// from the ends in a fixed order whatever order they come in.
fn along_edge(p: ((i128, i128), f32), q: ((i128, i128), f32), s: (i128, i128)) -> f64 {
    let (from, to) = if p.0 <= q.0 { (p, q) } else { (q, p) };
    let d = sub(to.0, from.0);
    let t = dot(sub(s, from.0), d) as f64 / dot(d, d) as f64;
    let (z0, z1) = (f64::from(from.1), f64::from(to.1));
    z0 + (z1 - z0) * t
}

/// Whether a counter-clockwise triangle's edge of direction `d` owns the samples on it, for a
/// sample nudged by (nudge.0 · ε, nudge.1 · ε²): the nudged sample is inside exactly when
/// cross(d, nudge) > 0.
fn owns_edge(d: (i128, i128), nudge: (i128, i128)) -> bool {
    if d.1 != 0 {
        -d.1 * nudge.0 > 0
    } else {
        d.0 * nudge.1 > 0
    }
}

fn sub(a: (i128, i128), b: (i128, i128)) -> (i128, i128) {
    (a.0 - b.0, a.1 - b.1)
}

fn cross(a: (i128, i128), b: (i128, i128)) -> i128 {
    a.0 * b.1 - a.1 * b.0
}

fn dot(a: (i128, i128), b: (i128, i128)) -> i128 {
    a.0 * b.0 + a.1 * b.1
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

    fn corner(x: f64, y: f64, z: f32) -> SurfacePoint {
        SurfacePoint {
            position: SubgridPoint::from_grid_units(x, y).unwrap(),
            z,
        }
    }

    /// Owners per sample of a 5×5 lattice (unit step) over the triangles.
    fn owners(raster: &SampleRaster, triangles: &[[SurfacePoint; 3]]) -> Vec<u32> {
        let mut owners = vec![0; raster.side() * raster.side()];
        for t in triangles {
            raster.for_each_covered_sample(t, |s| owners[s.index] += u32::from(s.owned));
        }
        owners
    }

    fn unit_raster() -> SampleRaster {
        SampleRaster::new(1 << SUBGRID_BITS, 5, 4 << SUBGRID_BITS)
    }

    #[test]
    fn two_triangles_of_a_square_own_every_sample_once_whatever_their_orientation() {
        let (sw, se, nw, ne) = (
            corner(0.0, 0.0, 0.0),
            corner(4.0, 0.0, 0.0),
            corner(0.0, 4.0, 0.0),
            corner(4.0, 4.0, 0.0),
        );
        for triangles in [[[sw, se, ne], [sw, ne, nw]], [[se, sw, ne], [nw, ne, sw]]] {
            assert_eq!(owners(&unit_raster(), &triangles), vec![1; 25]);
        }
    }

    #[test]
    fn a_t_junction_gives_each_sample_on_the_long_edge_to_one_side() {
        // Left: one triangle pair over [0,2]×[0,4]; right: four triangles over [2,4]×[0,4]
        // with a vertex at (2, 2) in the middle of the left side's edge.
        let c = |x: f64, y: f64| corner(x, y, 0.0);
        let triangles = [
            [c(0.0, 0.0), c(2.0, 0.0), c(2.0, 4.0)],
            [c(0.0, 0.0), c(2.0, 4.0), c(0.0, 4.0)],
            [c(2.0, 0.0), c(4.0, 0.0), c(2.0, 2.0)],
            [c(4.0, 0.0), c(4.0, 2.0), c(2.0, 2.0)],
            [c(2.0, 2.0), c(4.0, 2.0), c(2.0, 4.0)],
            [c(4.0, 2.0), c(4.0, 4.0), c(2.0, 4.0)],
        ];
        assert_eq!(owners(&unit_raster(), &triangles), vec![1; 25]);
    }

    #[test]
    fn fractional_corners_tile_too() {
        // A fan around (1.3, 2.7) over the square [0,4]².
        let centre = corner(1.3, 2.7, 0.0);
        let ring = [
            corner(0.0, 0.0, 0.0),
            corner(4.0, 0.0, 0.0),
            corner(4.0, 4.0, 0.0),
            corner(0.0, 4.0, 0.0),
        ];
        let triangles: Vec<[SurfacePoint; 3]> = (0..4)
            .map(|k| [centre, ring[k], ring[(k + 1) % 4]])
            .collect();
        // A finer lattice: quarter-cell steps.
        let raster = SampleRaster::new(1 << (SUBGRID_BITS - 2), 17, 4 << SUBGRID_BITS);
        let mut owners = vec![0; 17 * 17];
        for t in &triangles {
            raster.for_each_covered_sample(t, |s| owners[s.index] += u32::from(s.owned));
        }
        assert_eq!(owners, vec![1; 17 * 17]);
    }

    #[test]
    fn a_sample_on_an_edge_gets_the_same_height_from_both_sides_and_a_vertex_its_own() {
        let (a, b) = (corner(0.0, 0.0, 1.0), corner(3.0, 3.0, 10.0));
        let left = [a, b, corner(0.0, 3.0, 7.0)];
        let right = [b, a, corner(3.0, 0.0, -4.0)];
        let raster = SampleRaster::new(1 << SUBGRID_BITS, 4, 3 << SUBGRID_BITS);
        let mut heights = vec![Vec::new(); 16];
        for t in [&left, &right] {
            raster.for_each_covered_sample(t, |s| heights[s.index].push(s.height.to_bits()));
        }
        // (1, 1) and (2, 2) lie on the shared diagonal.
        for index in [5, 10] {
            assert_eq!(heights[index].len(), 2);
            assert_eq!(heights[index][0], heights[index][1]);
        }
        assert!((f64::from_bits(heights[5][0]) - 4.0).abs() < 1e-12);
        assert_eq!(heights[15], vec![10f64.to_bits(), 10f64.to_bits()]);
    }

    #[test]
    fn a_vertical_triangle_spans_from_its_bottom_to_its_top_edge_above_each_sample() {
        // A skirt below the edge (0, 1)–(4, 1) at heights 2 → 10, hanging 4 m below (4, 1).
        let skirt = [
            corner(0.0, 1.0, 2.0),
            corner(4.0, 1.0, 10.0),
            corner(4.0, 1.0, 6.0),
        ];
        let mut spans = Vec::new();
        unit_raster().for_each_vertical_span(&skirt, |index, low, high| {
            spans.push((index, low, high));
        });
        // Samples (0..=4, 1): the top edge rises 2 m a cell, the slanted bottom edge 1 m.
        let expected: Vec<(usize, f64, f64)> = (0..=4)
            .map(|i| {
                (
                    5 + i,
                    2.0 + f64::from(i as u32),
                    2.0 + 2.0 * f64::from(i as u32),
                )
            })
            .collect();
        assert_eq!(spans, expected);
        // The same top edge through a surface triangle gives the same heights, bit for bit.
        let surface = [
            corner(0.0, 1.0, 2.0),
            corner(4.0, 1.0, 10.0),
            corner(2.0, 3.0, 0.0),
        ];
        unit_raster().for_each_covered_sample(&surface, |sample| {
            if let Some(&(_, _, top)) = spans.iter().find(|s| s.0 == sample.index) {
                assert_eq!(top.to_bits(), sample.height.to_bits());
            }
        });
        // A diagonal segment only visits the samples exactly on it; a triangle with area none.
        let diagonal = [
            corner(0.0, 0.0, 1.0),
            corner(3.0, 1.5, 1.0),
            corner(3.0, 1.5, 0.0),
        ];
        let mut visited = Vec::new();
        unit_raster().for_each_vertical_span(&diagonal, |index, _, _| visited.push(index));
        assert_eq!(visited, [0, 5 + 2]);
        let mut none = 0;
        unit_raster().for_each_vertical_span(&surface, |_, _, _| none += 1);
        assert_eq!(none, 0);
    }

    #[test]
    fn zero_area_triangles_cover_nothing() {
        let degenerate = [
            corner(0.0, 0.0, 0.0),
            corner(2.0, 2.0, 0.0),
            corner(4.0, 4.0, 0.0),
        ];
        assert_eq!(owners(&unit_raster(), &[degenerate]), vec![0; 25]);
    }
}
