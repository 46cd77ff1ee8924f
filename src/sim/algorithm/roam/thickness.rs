//! ROAM's nested wedgie thicknesses e_T, built once before the first frame: per bintree triangle
//! as eq. (1) of ROAM'97 says (the default), or per split vertex as roamsim did before (an
//! option); SPEC §3 asks for each paper's own nesting. Tables only: the priorities that read them
//! are `priority.rs`'s.
//!
//! **Per triangle (eq. 1).** A bintree triangle T with apex a and hypotenuse (l, r) splits at the
//! midpoint v of its hypotenuse into T0 (split vertex m0 = mid(a, l), apex v) and T1 (split vertex
//! m1 = mid(a, r), apex v). Bottom-up from e = 0 for triangles that cannot split:
//! e_T = max(e_T0, e_T1) + |ε(v)| (the `max_plus_own` rule; the `max` rule takes
//! max(e_T0, e_T1, |ε(v)|) instead, to measure what the bound costs). A triangle is identified by
//! its split vertex and its apex, one of the split vertex's one or two parents, so the table holds
//! two `f32` per vertex (8 bytes per sample): slot 0 or 1 by the side of the split vertex the apex
//! lies on ([`apex_slot`]).
//!
//! **Per vertex (the former rule).** e(v) = |ε(v)| + the largest e of v's four children (or the
//! `max` rule), the same for both triangles split at v ([`Hierarchy::nested_vertex_errors`]; 4
//! bytes per sample). It nests over the whole diamond's descendants, so it is never smaller than
//! the per-triangle value and often larger: still a monotone bound, but looser.
//!
//! **Culling thickness.** Frustum flags (§7.1) need wedgies that really contain the surface and
//! are nested (a child's wedgie inside its parent's), whatever the priority rule: they always use
//! the per-triangle `max_plus_own` table, shared with the priority when that is the rule in use.
//! Every value is rounded up to `f32`.

use crate::sim::hierarchy::{
    GridPoint, Hierarchy, Lattice, NestingRule, round_up, vertices_finest_first,
};

/// Where the nested thickness of a triangle comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ThicknessScope {
    /// ROAM'97 eq. (1): one value per bintree triangle, nested over the triangle's own two
    /// children (the default).
    PerTriangle,
    /// One value per split vertex, nested over all four children of its diamond (looser).
    PerVertex,
}

/// One table of thicknesses.
#[derive(Clone, Debug)]
enum Table {
    PerTriangle(Vec<[f32; 2]>),
    PerVertex(Vec<f32>),
}

impl Table {
    fn get(&self, lattice: &Lattice, split: GridPoint, apex: GridPoint) -> f32 {
        let id = lattice.id(split) as usize;
        match self {
            Table::PerTriangle(values) => values[id][apex_slot(split, apex)],
            Table::PerVertex(values) => values[id],
        }
    }

    fn memory_bytes(&self) -> usize {
        match self {
            Table::PerTriangle(values) => values.capacity() * std::mem::size_of::<[f32; 2]>(),
            Table::PerVertex(values) => values.capacity() * std::mem::size_of::<f32>(),
        }
    }
}

/// The thicknesses the priorities use, and those the culling flags use.
#[derive(Clone, Debug)]
pub struct Thicknesses {
    lattice: Lattice,
    priority: Table,
    /// `None` when the priority table is the per-triangle `max_plus_own` one (then shared).
    culling: Option<Table>,
}

impl Thicknesses {
    /// Builds the priority table for `scope` and `rule`, and the culling table when
    /// `culling_flags` needs one of its own. O(samples).
    pub fn new(
        hierarchy: &Hierarchy,
        scope: ThicknessScope,
        rule: NestingRule,
        culling_flags: bool,
    ) -> Thicknesses {
        let paper = scope == ThicknessScope::PerTriangle && rule == NestingRule::MaxPlusOwn;
        let priority = match scope {
            ThicknessScope::PerTriangle => Table::PerTriangle(per_triangle(hierarchy, rule)),
            ThicknessScope::PerVertex => Table::PerVertex(hierarchy.nested_vertex_errors(rule)),
        };
        let culling = (culling_flags && !paper)
            .then(|| Table::PerTriangle(per_triangle(hierarchy, NestingRule::MaxPlusOwn)));
        Thicknesses {
            lattice: *hierarchy.lattice(),
            priority,
            culling,
        }
    }

    /// e_T of the triangle split at `split` with apex `apex`, for its priority.
    pub fn priority(&self, split: GridPoint, apex: GridPoint) -> f32 {
        self.priority.get(&self.lattice, split, apex)
    }

    /// e_T of the triangle for its frustum flag: a nested bound of the surface.
    pub fn culling(&self, split: GridPoint, apex: GridPoint) -> f32 {
        self.culling
            .as_ref()
            .unwrap_or(&self.priority)
            .get(&self.lattice, split, apex)
    }

    pub fn memory_bytes(&self) -> usize {
        self.priority.memory_bytes() + self.culling.as_ref().map_or(0, Table::memory_bytes)
    }
}

/// The slot (0 or 1) of the triangle split at `split` whose apex is `apex`: the two triangles of a
/// diamond have their apexes on opposite sides of the split vertex, along x (or along y when the
/// apexes share its x).
pub fn apex_slot(split: GridPoint, apex: GridPoint) -> usize {
    if apex.i != split.i {
        usize::from(apex.i > split.i)
    } else {
        usize::from(apex.j > split.j)
    }
}

/// Eq. (1) for every triangle, finest level first ([`vertices_finest_first`], generated as
/// read). O(samples); holds nothing but the table it returns (8 bytes per sample).
fn per_triangle(hierarchy: &Hierarchy, rule: NestingRule) -> Vec<[f32; 2]> {
    let lattice = hierarchy.lattice();
    let mut table = vec![[0.0f32; 2]; lattice.n_vertices()];
    // A triangle's children split at vertices one level finer: done before it.
    for split in vertices_finest_first(lattice) {
        let id = lattice.id(split);
        let Some([left, right]) = lattice.bisected_edge(split) else {
            continue;
        };
        let own = hierarchy.vertex_error(split).abs();
        for &apex in lattice.parents(split).as_slice() {
            let child = |end: GridPoint| -> f64 {
                let (si, sj) = (apex.i + end.i, apex.j + end.j);
                if si % 2 != 0 || sj % 2 != 0 {
                    return 0.0; // the child's hypotenuse has no grid midpoint
                }
                let mid = GridPoint::new(si / 2, sj / 2);
                f64::from(table[lattice.id(mid) as usize][apex_slot(mid, split)])
            };
            let children = child(left).max(child(right));
            let value = match rule {
                NestingRule::Max => own.max(children),
                NestingRule::MaxPlusOwn => own + children,
            };
            table[id as usize][apex_slot(split, apex)] = round_up(value);
        }
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mesh::triangles::{Triangle, base_triangles};
    use crate::sim::terrain::{Heightfield, Spacing};

    fn rough(level: u32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| ((k * 2654435761) % 101) as f32 * 0.37 - 9.0)
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 5.0, dy: 5.0 }).unwrap())
    }

    /// e_T by the definition, recursively over the triangle's own descendants.
    fn by_definition(hierarchy: &Hierarchy, triangle: Triangle, rule: NestingRule) -> f64 {
        let Some(mid) = triangle.split_vertex() else {
            return 0.0;
        };
        let [a, b] = triangle.children(mid);
        let children = by_definition(hierarchy, a, rule).max(by_definition(hierarchy, b, rule));
        let own = hierarchy.vertex_error(mid).abs();
        match rule {
            NestingRule::Max => own.max(children),
            NestingRule::MaxPlusOwn => own + children,
        }
    }

    /// The greatest vertical distance between the triangle's plane and the samples it covers:
    /// what a wedgie must contain.
    fn surface_deviation(hierarchy: &Hierarchy, triangle: Triangle) -> f64 {
        let z = |p: GridPoint| f64::from(hierarchy.height(p));
        let [a, l, r] = [triangle.apex, triangle.left, triangle.right];
        let (ax, ay, lx, ly, rx, ry) = (
            f64::from(a.i),
            f64::from(a.j),
            f64::from(l.i),
            f64::from(l.j),
            f64::from(r.i),
            f64::from(r.j),
        );
        let det = (lx - ax) * (ry - ay) - (rx - ax) * (ly - ay);
        let (i_min, i_max) = (a.i.min(l.i).min(r.i), a.i.max(l.i).max(r.i));
        let (j_min, j_max) = (a.j.min(l.j).min(r.j), a.j.max(l.j).max(r.j));
        let mut deviation: f64 = 0.0;
        for j in j_min..=j_max {
            for i in i_min..=i_max {
                let (x, y) = (f64::from(i), f64::from(j));
                let u = ((x - ax) * (ry - ay) - (rx - ax) * (y - ay)) / det;
                let v = ((lx - ax) * (y - ay) - (x - ax) * (ly - ay)) / det;
                if u < -1e-12 || v < -1e-12 || u + v > 1.0 + 1e-12 {
                    continue;
                }
                let plane = z(a) + u * (z(l) - z(a)) + v * (z(r) - z(a));
                deviation = deviation.max((z(GridPoint::new(i, j)) - plane).abs());
            }
        }
        deviation
    }

    /// Every triangle of the bintree, top-down.
    fn every_triangle(lattice: &Lattice) -> Vec<Triangle> {
        let mut out = Vec::new();
        let mut stack: Vec<Triangle> = base_triangles(lattice).to_vec();
        while let Some(t) = stack.pop() {
            out.push(t);
            if let Some(mid) = t.split_vertex() {
                stack.extend(t.children(mid));
            }
        }
        out
    }

    #[test]
    fn per_triangle_values_follow_eq_1_bound_the_surface_and_never_exceed_per_vertex_ones() {
        let hierarchy = rough(4);
        let lattice = hierarchy.lattice();
        let per_vertex = hierarchy.nested_vertex_errors(NestingRule::MaxPlusOwn);
        let mut tighter = 0;
        for rule in [NestingRule::MaxPlusOwn, NestingRule::Max] {
            let table = Thicknesses::new(&hierarchy, ThicknessScope::PerTriangle, rule, false);
            for triangle in every_triangle(lattice) {
                let Some(mid) = triangle.split_vertex() else {
                    continue;
                };
                let stored = f64::from(table.priority(mid, triangle.apex));
                let exact = by_definition(&hierarchy, triangle, rule);
                assert!(
                    stored >= exact && stored <= exact * (1.0 + 1e-6) + 1e-30,
                    "{triangle:?}"
                );
                if rule == NestingRule::MaxPlusOwn {
                    assert!(stored >= surface_deviation(&hierarchy, triangle) - 1e-4);
                    let vertex = per_vertex[lattice.id(mid) as usize];
                    assert!(stored <= f64::from(vertex), "{triangle:?}");
                    tighter += usize::from(stored < f64::from(vertex));
                }
            }
        }
        assert!(
            tighter > 50,
            "only {tighter} triangles are tighter per triangle"
        );
    }

    #[test]
    fn the_two_triangles_of_a_diamond_take_different_slots() {
        let lattice = Lattice::new(3);
        for id in 0..lattice.n_vertices() as u32 {
            let p = lattice.point(id);
            let parents = lattice.parents(p);
            if let [a, b] = parents.as_slice() {
                assert_ne!(apex_slot(p, *a), apex_slot(p, *b), "{p:?}");
            }
        }
    }

    #[test]
    fn culling_uses_the_nested_paper_bound_whatever_the_priority_rule() {
        let hierarchy = rough(3);
        let paper = Thicknesses::new(
            &hierarchy,
            ThicknessScope::PerTriangle,
            NestingRule::MaxPlusOwn,
            true,
        );
        assert!(paper.culling.is_none(), "shared");
        let loose = Thicknesses::new(
            &hierarchy,
            ThicknessScope::PerVertex,
            NestingRule::Max,
            true,
        );
        for triangle in every_triangle(hierarchy.lattice()) {
            if let Some(mid) = triangle.split_vertex() {
                assert_eq!(
                    loose.culling(mid, triangle.apex),
                    paper.priority(mid, triangle.apex)
                );
            }
        }
    }
}
