//! A Vaněk frame as triangles: every drawn patch's level's vertices, its border ones collapsed
//! onto a coarser drawn neighbour's (§3), and the paper's strip over them (§2) with its joins
//! and the triangles collapsing flattens as degenerate; culled squares declared as such; and
//! what changed since the last frame drawn (the `splits`, `merges` and vertex counters). It
//! chooses nothing: levels and culling are the frame's (`mod.rs`, `select.rs`); the GPU's
//! buffers are `buffers.rs`'s.

use super::{EAST, NORTH, SOUTH, Shape, Vanek, WEST, strip};
use crate::sim::hierarchy::GridPoint;
use crate::sim::mesh::{SubgridPoint, TriangleInfo, TriangleRole};

impl Vanek<'_> {
    /// The level each side of `patch` is drawn at: the coarser of the patch's and its drawn
    /// neighbour's (the patch's own on the domain's border and beside a culled patch, which
    /// draws nothing to meet).
    fn side_lods(&self, patch: usize) -> [u32; 4] {
        let own = self.lods[patch];
        [WEST, EAST, SOUTH, NORTH].map(|side| {
            self.neighbour(patch, side)
                .filter(|&q| self.is_drawn(q))
                .map_or(own, |q| own.min(self.lods[q]))
        })
    }

    /// Adds patch `patch` to the list: its level's vertices, collapsed towards coarser sides,
    /// and its strip's triangles. Returns its shape.
    fn add_patch(&mut self, patch: usize) -> Shape {
        let k = self.lods[patch];
        let sides = self.side_lods(patch);
        let m = (1u32 << k) + 1;
        let stride = 1u32 << (self.patch_level - k);
        let (x0, y0) = self.origin(patch);
        let steps = sides.map(|side| 1u32 << (k - side));
        self.moved.clear();
        let base = self.list.vertices().len() as u32;
        for r in 0..m {
            for c in 0..m {
                let (mut cc, mut rr) = (c, r);
                // South and west: back to the vertex at or before; north and east: on to the
                // one at or after (see the module docs).
                if r == 0 {
                    cc -= cc % steps[SOUTH];
                } else if r == m - 1 {
                    cc += (steps[NORTH] - cc % steps[NORTH]) % steps[NORTH];
                }
                if c == 0 {
                    rr -= rr % steps[WEST];
                } else if c == m - 1 {
                    rr += (steps[EAST] - rr % steps[EAST]) % steps[EAST];
                }
                let (i, j) = (x0 + cc * stride, y0 + rr * stride);
                let z = self.hierarchy.height(GridPoint::new(i, j));
                self.list.add_vertex(SubgridPoint::grid(i, j), z);
                self.moved.push((cc, rr));
            }
        }
        let shape = [k, sides[0], sides[1], sides[2], sides[3]];
        self.drawn.push((patch, base, shape));
        let mut indices = std::mem::take(&mut self.strip);
        strip::degenerate_strip_into(m, m, &mut indices);
        self.strip_indices += indices.len() as u64;
        for (t, w) in indices.windows(3).enumerate() {
            let [a, b, c] = strip::strip_triangle(t, [w[0], w[1], w[2]]);
            let role = if a == b || b == c || a == c {
                TriangleRole::Degenerate
            } else if area2(
                self.moved[a as usize],
                self.moved[b as usize],
                self.moved[c as usize],
            ) == 0
            {
                self.collapsed += 1;
                TriangleRole::Degenerate
            } else {
                TriangleRole::Surface
            };
            self.list.add_triangle(
                [base + a, base + b, base + c],
                TriangleInfo {
                    role,
                    group: patch as u32,
                    level: k,
                },
            );
        }
        self.strip = indices;
        shape
    }

    /// Draws every patch at the given levels (the paper's k, row by row; clamped to n), without
    /// culling: for exhaustive tests of the collapsing, which no eye position could reach.
    /// The next [`update`](crate::sim::algorithm::LodAlgorithm::update) chooses the levels
    /// again.
    pub fn draw_with_lods(&mut self, lods: &[u32]) {
        assert_eq!(lods.len(), self.lods.len(), "one level per patch");
        for (mine, &k) in self.lods.iter_mut().zip(lods) {
            *mine = k.min(self.patch_level);
        }
        self.visible.clear();
        self.visible.extend(0..self.lods.len() as u32);
        self.culled_squares.clear();
        self.begin_frame();
        self.draw();
    }

    /// Builds the list from this frame's levels and culling; returns the counters that
    /// compare it with the last frame drawn: patches drawn finer, coarser, vertices of the
    /// patches whose shape changed (the new and the old).
    pub(super) fn draw(&mut self) -> [u64; 4] {
        self.list.clear();
        self.drawn.clear();
        self.strip_indices = 0;
        self.collapsed = 0;
        for &((x0, y0), cells) in &self.culled_squares {
            self.list.add_culled_region(
                SubgridPoint::grid(x0, y0),
                SubgridPoint::grid(x0 + cells, y0 + cells),
            );
        }
        let (mut finer, mut coarser, mut inserted, mut deleted) = (0, 0, 0, 0);
        let frame = self.frame;
        for index in 0..self.visible.len() {
            let patch = self.visible[index] as usize;
            let now = self.add_patch(patch);
            let before = self.states[patch]
                .filter(|&(drawn_in, _)| drawn_in + 1 == frame)
                .map(|(_, shape)| shape);
            match before {
                None => inserted += patch_vertex_count(now[0]),
                Some(before) if before != now => {
                    inserted += patch_vertex_count(now[0]);
                    deleted += patch_vertex_count(before[0]);
                    finer += u64::from(now[0] > before[0]);
                    coarser += u64::from(now[0] < before[0]);
                }
                Some(_) => {}
            }
            self.states[patch] = Some((frame, now));
        }
        for &patch in &self.previous_drawn {
            if !self.is_drawn(patch as usize)
                && let Some((_, shape)) = self.states[patch as usize]
            {
                deleted += patch_vertex_count(shape[0]);
            }
        }
        self.previous_drawn.clone_from(&self.visible);
        [finer, coarser, inserted, deleted]
    }
}

/// The vertices a patch at level k holds, (2^k + 1)².
fn patch_vertex_count(k: u32) -> u64 {
    ((1u64 << k) + 1).pow(2)
}

/// Twice the signed area of the triangle over three (column, row) positions.
fn area2(a: (u32, u32), b: (u32, u32), c: (u32, u32)) -> i64 {
    let (ax, ay) = (i64::from(a.0), i64::from(a.1));
    let (bx, by) = (i64::from(b.0) - ax, i64::from(b.1) - ay);
    let (cx, cy) = (i64::from(c.0) - ax, i64::from(c.1) - ay);
    bx * cy - by * cx
}
