//! The general path of the rasteriser (see `mod.rs`): [`SampleRaster`], corners anywhere in
//! fixed point, every sample of a tiling given to exactly one triangle by the tie rule, heights
//! on an edge from its two ends only; and the vertical spans a wall triangle covers. Not here:
//! the 4-8 fast path the audit has used since its first release (`lattice.rs`).

use crate::sim::mesh::position::SurfacePoint;

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
    use crate::sim::mesh::position::{SUBGRID_BITS, SubgridPoint};

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
