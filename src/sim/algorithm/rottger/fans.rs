//! The triangle fans of a frame (§2.1): what the paper draws, counted.
//!
//! Every subdivided block draws one fan around its centre over the quadrants whose child is not
//! subdivided (all four for the finest blocks, whose children are single cells): a full fan, or
//! a partial one. Its ring runs corner, edge midpoint, corner, …; an edge whose midpoint is not
//! drawn gives one triangle instead of two (the crosses of the paper's figure 2). A fan is what
//! one `GL_TRIANGLE_FAN` can draw: a contiguous run of triangles around the centre; a block whose
//! drawn quadrants are not contiguous draws two fans. A run of t triangles sends t + 2 vertices
//! (centre, then the ring; a closed ring repeats its first vertex), which is how the paper counts
//! "vertices" ("up to 10 vertices" a fan, §2.2; "approximately 1600 triangle fans, or a total of
//! roughly 15000 vertices per frame", §3). When the root is not subdivided, the mesh is the two
//! base triangles: one fan of 4 vertices.
//!
//! Every triangle of the mesh belongs to exactly one fan, so without clipping the fans' triangles
//! add up to the mesh's; with clipping, a fan is counted only when its block's box may be seen.

use super::clip::{ViewFrustum, fan_may_be_seen};
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice, VertexClass};
use crate::sim::mesh::VertexSet;

/// The fans of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FanCounts {
    pub fans: u64,
    pub triangles: u64,
    /// Vertices sent: triangles + 2 per fan.
    pub vertices: u64,
}

impl FanCounts {
    fn add(&mut self, other: FanCounts) {
        self.fans += other.fans;
        self.triangles += other.triangles;
        self.vertices += other.vertices;
    }
}

/// The fan(s) of the block centred at `centre` (half-size `half`, subdivided) in `mesh`.
pub fn block_fans(lattice: &Lattice, mesh: &VertexSet, centre: GridPoint, half: u32) -> FanCounts {
    let active = |di: i64, dj: i64| {
        let i = i64::from(centre.i) + di;
        let j = i64::from(centre.j) + dj;
        mesh.contains_point(lattice, GridPoint::new(i as u32, j as u32))
    };
    let t = i64::from(half);
    let q = t / 2;
    // Quadrants SW, SE, NE, NW: drawn when their child is not subdivided.
    let quadrant_drawn =
        [(-1, -1), (1, -1), (1, 1), (-1, 1)].map(|(a, b)| half == 1 || !active(a * q, b * q));
    // Edges S, E, N, W (between quadrants k and k + 1): midpoint drawn?
    let midpoint = [(0, -1), (1, 0), (0, 1), (-1, 0)].map(|(a, b)| active(a * t, b * t));
    // Ring slots 0..8, slot 2k and 2k + 1 on edge k: slot 2k in quadrant k, slot 2k + 1 in
    // quadrant k + 1 (mod 4).
    let slot_drawn: [bool; 8] = std::array::from_fn(|s| quadrant_drawn[(s / 2 + s % 2) % 4]);
    let mut triangles = 0;
    for edge in 0..4 {
        let (a, b) = (slot_drawn[2 * edge], slot_drawn[2 * edge + 1]);
        triangles += if midpoint[edge] {
            u64::from(a) + u64::from(b)
        } else {
            debug_assert!(
                a && b,
                "a skipped midpoint between a drawn and a subdivided quadrant"
            );
            u64::from(a && b)
        };
    }
    let drawn = slot_drawn.iter().filter(|&&d| d).count();
    let runs = if drawn == 8 {
        1
    } else {
        (0..8)
            .filter(|&s| slot_drawn[s] && !slot_drawn[(s + 7) % 8])
            .count() as u64
    };
    FanCounts {
        fans: runs,
        triangles,
        vertices: triangles + 2 * runs,
    }
}

/// Every fan of the frame: the fans of the subdivided blocks (`subdivided` lists their centres),
/// or the two base triangles when there are none. With a `clipping` frustum, only the fans whose
/// block's box may be seen.
pub fn count_fans(
    hierarchy: &Hierarchy,
    mesh: &VertexSet,
    subdivided: &[u32],
    clipping: Option<&ViewFrustum>,
) -> FanCounts {
    let lattice = hierarchy.lattice();
    let seen = |centre: GridPoint, half: u32| {
        clipping.is_none_or(|frustum| fan_may_be_seen(hierarchy, frustum, centre, half))
    };
    if subdivided.is_empty() {
        let root = lattice.root();
        return if seen(root, lattice.cells() / 2) {
            FanCounts {
                fans: 1,
                triangles: 2,
                vertices: 4,
            }
        } else {
            FanCounts::default()
        };
    }
    let mut counts = FanCounts::default();
    for &id in subdivided {
        let centre = lattice.point(id);
        let VertexClass::Square { half } = lattice.classify(centre) else {
            unreachable!("only block centres are subdivided");
        };
        if seen(centre, half) {
            counts.add(block_fans(lattice, mesh, centre, half));
        }
    }
    counts
}

/// One fan as drawn: the range of its vertices among the frame's fan vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FanRun {
    pub first: u32,
    pub count: u32,
}

/// Calls `visit` with the vertices of every fan of the frame in drawing order (the fans counted
/// by [`count_fans`] without clipping): the centre, then the ring counter-clockwise (the mesh's
/// winding), a closed ring ending on its first vertex again. The two base triangles, when
/// nothing is subdivided, are one fan of four vertices.
pub fn for_each_fan(
    lattice: &Lattice,
    mesh: &VertexSet,
    subdivided: &[u32],
    mut visit: impl FnMut(&[GridPoint]),
) {
    if subdivided.is_empty() {
        let [sw, se, nw, ne] = lattice.corners();
        visit(&[sw, se, ne, nw]);
        return;
    }
    for &id in subdivided {
        let centre = lattice.point(id);
        let VertexClass::Square { half } = lattice.classify(centre) else {
            unreachable!("only block centres are subdivided");
        };
        block_fan_vertices(lattice, mesh, centre, half, &mut visit);
    }
}

/// The fan(s) of one subdivided block as vertex sequences (see [`block_fans`] for which
/// triangles they hold).
fn block_fan_vertices(
    lattice: &Lattice,
    mesh: &VertexSet,
    centre: GridPoint,
    half: u32,
    visit: &mut impl FnMut(&[GridPoint]),
) {
    let t = i64::from(half);
    let q = t / 2;
    let at = |di: i64, dj: i64| {
        GridPoint::new(
            (i64::from(centre.i) + di) as u32,
            (i64::from(centre.j) + dj) as u32,
        )
    };
    let active = |di: i64, dj: i64| mesh.contains_point(lattice, at(di, dj));
    let quadrant_drawn =
        [(-1, -1), (1, -1), (1, 1), (-1, 1)].map(|(a, b)| half == 1 || !active(a * q, b * q));
    let midpoint = [(0, -1), (1, 0), (0, 1), (-1, 0)].map(|(a, b)| active(a * t, b * t));
    let slot_drawn: [bool; 8] = std::array::from_fn(|s| quadrant_drawn[(s / 2 + s % 2) % 4]);
    // The ring counter-clockwise from the south-west corner: corner, midpoint, corner, ….
    let ring = [
        (-t, -t),
        (0, -t),
        (t, -t),
        (t, 0),
        (t, t),
        (0, t),
        (-t, t),
        (-t, 0),
    ]
    .map(|(di, dj)| at(di, dj));
    // The triangles around the centre in ring order: (ring start, ring end, drawn).
    let mut units = [(0usize, 0usize, false); 8];
    let mut n_units = 0;
    for edge in 0..4 {
        let (a, b) = (slot_drawn[2 * edge], slot_drawn[2 * edge + 1]);
        if midpoint[edge] {
            units[n_units] = (2 * edge, 2 * edge + 1, a);
            units[n_units + 1] = (2 * edge + 1, (2 * edge + 2) % 8, b);
            n_units += 2;
        } else {
            units[n_units] = (2 * edge, (2 * edge + 2) % 8, a && b);
            n_units += 1;
        }
    }
    let units = &units[..n_units];
    let mut fan: [GridPoint; 10] = [centre; 10];
    let mut len = 0;
    // Start after an undrawn triangle so that no run wraps around; a full ring starts anywhere.
    let start = units.iter().position(|u| !u.2).map_or(0, |k| k + 1);
    for k in 0..units.len() {
        let (from, to, drawn) = units[(start + k) % units.len()];
        if drawn {
            if len == 0 {
                fan[1] = ring[from];
                len = 2;
            }
            fan[len] = ring[to];
            len += 1;
        } else if len > 0 {
            visit(&fan[..len]);
            len = 0;
        }
    }
    if len > 0 {
        visit(&fan[..len]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's figure 1: a 9 × 9 field whose quadtree matrix subdivides the root, three of
    /// its children and two finest blocks of the north-east child.
    fn figure_1() -> (Lattice, VertexSet, Vec<u32>) {
        let lattice = Lattice::new(3);
        let mut mesh = VertexSet::base_mesh(&lattice);
        let subdivided: Vec<u32> = [(4, 4), (6, 2), (2, 6), (6, 6), (7, 5), (7, 7)]
            .map(|(i, j)| lattice.id(GridPoint::new(i, j)))
            .to_vec();
        for &id in &subdivided {
            mesh.insert(id);
        }
        // Edge midpoints whose blocks on both sides (one on the border) are subdivided.
        for &id in &subdivided {
            let centre = lattice.point(id);
            let VertexClass::Square { half } = lattice.classify(centre) else {
                unreachable!()
            };
            for midpoint in lattice.boundary_vertices(centre, half) {
                if lattice
                    .parents(midpoint)
                    .as_slice()
                    .iter()
                    .all(|p| subdivided.contains(&lattice.id(*p)))
                {
                    mesh.insert(lattice.id(midpoint));
                }
            }
        }
        (lattice, mesh, subdivided)
    }

    #[test]
    fn the_papers_figure_1_draws_six_fans_of_33_triangles_and_45_vertices() {
        let (lattice, mesh, subdivided) = figure_1();
        crate::sim::mesh::validate::validate_reported(&lattice, &mesh, 33).unwrap();
        let fan = |i, j, half| block_fans(&lattice, &mesh, GridPoint::new(i, j), half);
        let counts = |fans, triangles| FanCounts {
            fans,
            triangles,
            vertices: triangles + 2 * fans,
        };
        // The root draws only its south-west quadrant (its child there is not subdivided).
        assert_eq!(fan(4, 4, 4), counts(1, 2));
        // (6, 2) and (2, 6): full rings, the midpoint towards the unrefined (2, 2) skipped.
        assert_eq!(fan(6, 2, 2), counts(1, 7));
        assert_eq!(fan(2, 6, 2), counts(1, 7));
        // (6, 6): its west quadrants only, one contiguous run of four triangles.
        assert_eq!(fan(6, 6, 2), counts(1, 4));
        // The finest blocks: full fans with the midpoints towards unrefined neighbours skipped.
        assert_eq!(fan(7, 5, 1), counts(1, 6));
        assert_eq!(fan(7, 7, 1), counts(1, 7));
        let hierarchy = Hierarchy::new(
            crate::sim::terrain::Heightfield::new(
                9,
                vec![0.0; 81],
                crate::sim::terrain::Spacing { dx: 1.0, dy: 1.0 },
            )
            .unwrap(),
        );
        assert_eq!(
            count_fans(&hierarchy, &mesh, &subdivided, None),
            counts(6, 33)
        );
    }

    #[test]
    fn the_fans_drawn_for_figure_1_are_the_fans_counted() {
        let (lattice, mesh, subdivided) = figure_1();
        let (mut fans, mut vertices) = (0, 0);
        for_each_fan(&lattice, &mesh, &subdivided, |points| {
            fans += 1;
            vertices += points.len();
        });
        assert_eq!((fans, vertices), (6, 33 + 2 * 6));
    }

    #[test]
    fn a_block_whose_drawn_quadrants_are_opposite_draws_two_fans() {
        // 9 × 9: the root and its south-west and north-east children subdivided, with the
        // edge midpoints closure needs.
        let lattice = Lattice::new(3);
        let mut mesh = VertexSet::base_mesh(&lattice);
        for (i, j) in [(4, 4), (4, 0), (8, 4), (4, 8), (0, 4), (2, 2), (6, 6)] {
            mesh.insert(lattice.id(GridPoint::new(i, j)));
        }
        let fans = block_fans(&lattice, &mesh, GridPoint::new(4, 4), 4);
        assert_eq!(
            fans,
            FanCounts {
                fans: 2,
                triangles: 4,
                vertices: 8
            }
        );
    }
}
