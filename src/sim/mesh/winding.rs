//! The winding rule every drawn triangle keeps, as a GPU would cull it: **counter-clockwise seen
//! from above** (z up, x east along columns, y north along rows), the front face of OpenGL's and
//! Vulkan's default pipelines. Whatever an algorithm draws, its triangles' corners are listed in
//! that order, so a renderer with back-face culling on draws the terrain seen from above, and a
//! mesh export (`meshes/*.ply`, which writes faces in the corner order) has its normals up.
//!
//! The rule is the sign of the triangle's signed area in the x–y plane, computed exactly: the
//! corners are fixed-point [`SubgridPoint`]s, differences fit 34 bits, and their products are
//! taken in `i128`, so no rounding can flip a sign. Positive is counter-clockwise.
//!
//! **Excepted: triangles with zero plane area**, which have no winding seen from above: the
//! joins of a triangle strip (a repeated corner), triangles collapsed onto a line (Vaněk–Ježek's
//! collapsed borders, two vertices of a fractional tessellation rounded onto one point) and
//! vertical skirts. Their roles (degenerate, skirt) say so, and the triangle-list validator
//! checks that they have no area.
//!
//! Both validators hold every algorithm to it: the 4-8 validator (`validate`) on the bintree's
//! triangles in the visitor's corner order, the triangle-list validator (`list_validate`) on
//! every listed triangle. What it is not: a check that the surface faces up in 3-D (a triangle
//! on a steep slope still faces up; none can overhang, heights being a function of x and y).

use super::position::{SubgridPoint, SurfacePoint};

/// Which way a triangle's corners run, seen from above.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Winding {
    /// Positive signed area: the order every drawn triangle must have.
    CounterClockwise,
    /// Negative signed area: back-facing seen from above, refused by the validators.
    Clockwise,
    /// Zero plane area (a strip join, a collapsed triangle, a skirt): no winding, excepted.
    Flat,
}

impl Winding {
    /// The winding of the triangle with plane corners `points`, exactly.
    pub fn of_points(points: [SubgridPoint; 3]) -> Winding {
        match signed_area2(points).signum() {
            1 => Winding::CounterClockwise,
            -1 => Winding::Clockwise,
            _ => Winding::Flat,
        }
    }

    /// The winding of a drawn triangle, its heights ignored.
    pub fn of(corners: &[SurfacePoint; 3]) -> Winding {
        Winding::of_points(corners.map(|c| c.position))
    }
}

/// Twice the signed area of the triangle `points` in the x–y plane, in fixed-point units²
/// (1/65 536² of a cell²): positive counter-clockwise, exact.
pub fn signed_area2(points: [SubgridPoint; 3]) -> i128 {
    let [a, b, c] = points.map(|p| {
        let (x, y) = p.raw();
        (i128::from(x), i128::from(y))
    });
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// [`signed_area2`] of a drawn triangle's plane corners.
pub fn plane_area2(corners: &[SurfacePoint; 3]) -> i128 {
    signed_area2(corners.map(|c| c.position))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(points: [(u32, u32); 3]) -> [SubgridPoint; 3] {
        points.map(|(i, j)| SubgridPoint::grid(i, j))
    }

    #[test]
    fn east_then_north_is_counter_clockwise_and_the_reverse_is_clockwise() {
        let ccw = grid([(0, 0), (1, 0), (0, 1)]);
        assert_eq!(Winding::of_points(ccw), Winding::CounterClockwise);
        assert_eq!(signed_area2(ccw), 1 << 32);
        let cw = grid([(0, 0), (0, 1), (1, 0)]);
        assert_eq!(Winding::of_points(cw), Winding::Clockwise);
        assert_eq!(signed_area2(cw), -(1 << 32));
    }

    #[test]
    fn a_repeated_corner_or_three_points_on_a_line_are_flat() {
        assert_eq!(
            Winding::of_points(grid([(0, 0), (1, 0), (1, 0)])),
            Winding::Flat
        );
        assert_eq!(
            Winding::of_points(grid([(0, 0), (1, 1), (3, 3)])),
            Winding::Flat
        );
    }

    #[test]
    fn the_sign_is_exact_for_the_thinnest_triangle_on_the_largest_lattice() {
        // One fixed-point unit off the diagonal of a 2^15-cell square: a float area would round
        // the products (2^62) and could lose the sign; the i128 products do not.
        let far = (1i64 << 15) * crate::sim::mesh::SUBGRID_UNITS_PER_CELL;
        let p = |x, y| SubgridPoint::from_raw(x, y).unwrap();
        let thin = [p(0, 0), p(far, far), p(far - 1, far)];
        assert_eq!(signed_area2(thin), i128::from(far));
        assert_eq!(Winding::of_points(thin), Winding::CounterClockwise);
        let surface = thin.map(|position| SurfacePoint { position, z: 5.0 });
        assert_eq!(Winding::of(&surface), Winding::CounterClockwise);
        assert_eq!(plane_area2(&surface), i128::from(far));
    }
}
