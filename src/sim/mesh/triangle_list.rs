//! The general mesh form: an indexed triangle list as a block-based algorithm draws it (SPEC §3:
//! the families beyond the 4-8 hierarchy, taken as they are drawn).
//!
//! For the families outside the 4-8 hierarchy (geomipmapping, chunked LOD, Vaněk–Ježek patches,
//! tessellated blocks with stitching strips, anything geomorphed): vertices with positions of
//! their own (fractional ones included, see [`SubgridPoint`]) and heights of their own (sample,
//! morphed or resampled), and triangles over them, each with a **role** (what it is drawn for),
//! a **group** (its patch, chunk or draw batch) and a **level** (its refinement level, for
//! drawing and statistics). The mesh also declares its **crack policy**: how the algorithm
//! means its borders to be closed, which the validator (`list_validate`) holds it to.
//!
//! Built frame after frame: [`TriangleList::clear`] keeps every buffer's capacity, adding a
//! vertex or a triangle is O(1) amortised. Role counts, draw batches and morphing vertices are
//! counted as the list is built, so reading them is O(1).
//!
//! An algorithm that culls (leaves out what lies outside the view volume, as chunked LOD's box
//! culling does) declares each square it left undrawn with [`TriangleList::add_culled_region`]:
//! the validator then lets the surface leave exactly those squares uncovered, and the audit,
//! which only measures samples in view, counts any sample of them it does see as a hole.
//!
//! What it is not: a mesh structure with adjacency (algorithms keep their own), nor a GPU
//! buffer (the preview builds its own from the triangle visitor).

use super::position::{SubgridPoint, SurfacePoint};
use crate::sim::hierarchy::Lattice;

/// What a triangle is drawn for. Only [`TriangleRole::is_surface`] roles are the terrain's
/// surface: the audit measures them, the validator tiles the domain with them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TriangleRole {
    /// Part of the terrain's surface.
    Surface,
    /// A vertical curtain hung below a border to hide a crack (chunked LOD). Never surface.
    Skirt,
    /// A triangle of zero area: a collapsed border triangle, or one that joins two triangle
    /// strips. Never surface; the validator checks that its area is zero.
    Degenerate,
    /// A triangle that fills the gap between two blocks tessellated differently (stitching
    /// strips). Surface: it is drawn with area and the eye sees it.
    Stitch,
}

impl TriangleRole {
    /// Every role, in the order of [`TriangleRole::index`].
    pub const ALL: [TriangleRole; 4] = [
        TriangleRole::Surface,
        TriangleRole::Skirt,
        TriangleRole::Degenerate,
        TriangleRole::Stitch,
    ];

    /// Whether triangles of this role are the terrain's surface (surface and stitch).
    pub fn is_surface(self) -> bool {
        matches!(self, TriangleRole::Surface | TriangleRole::Stitch)
    }

    /// 0, 1, 2, 3 in the order of [`TriangleRole::ALL`] (also the role's number in mesh files).
    pub fn index(self) -> usize {
        match self {
            TriangleRole::Surface => 0,
            TriangleRole::Skirt => 1,
            TriangleRole::Degenerate => 2,
            TriangleRole::Stitch => 3,
        }
    }

    /// The role's name as outputs spell it.
    pub fn name(self) -> &'static str {
        match self {
            TriangleRole::Surface => "surface",
            TriangleRole::Skirt => "skirt",
            TriangleRole::Degenerate => "degenerate",
            TriangleRole::Stitch => "stitch",
        }
    }
}

/// How an algorithm closes the borders between its patches, as the validator checks it. In
/// every policy the surface triangles (surface and stitch) tile the terrain's domain exactly
/// once; the policies differ in what may sit on the borders between them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrackPolicy {
    /// The surface is watertight: every surface edge inside the domain is shared, end points and
    /// heights alike, by exactly two surface triangles. No skirts, no stitches.
    Closed,
    /// Borders may leave cracks (T-junctions, or heights that differ across a border); every
    /// surface edge that is not shared must have a skirt hanging below it. No stitches.
    Skirted,
    /// Gaps between blocks are filled by stitch triangles, after which the surface is
    /// watertight as under `Closed`. No skirts.
    Stitched,
    /// Border vertices are moved onto the coarser neighbour's, leaving zero-area triangles
    /// (role degenerate); the rest is watertight as under `Closed`. No skirts, no stitches.
    Collapsed,
}

impl CrackPolicy {
    /// Whether triangles of `role` may appear in a mesh of this policy. Surface triangles always
    /// may; degenerate triangles may under every policy (strip joins are degenerate too).
    pub fn allows(self, role: TriangleRole) -> bool {
        match role {
            TriangleRole::Surface | TriangleRole::Degenerate => true,
            TriangleRole::Skirt => self == CrackPolicy::Skirted,
            TriangleRole::Stitch => self == CrackPolicy::Stitched,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            CrackPolicy::Closed => "closed",
            CrackPolicy::Skirted => "skirted",
            CrackPolicy::Stitched => "stitched",
            CrackPolicy::Collapsed => "collapsed",
        }
    }
}

/// What a triangle is drawn for, in which batch, at which level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TriangleInfo {
    pub role: TriangleRole,
    /// The patch, chunk or draw batch the triangle belongs to (the algorithm's numbering).
    pub group: u32,
    /// The triangle's refinement level (the algorithm's numbering; the preview colours by it).
    pub level: u32,
}

/// An indexed triangle list over one terrain's domain, with roles, groups, levels and a crack
/// policy. Invariants (checked as the list is built): every vertex lies inside the terrain's
/// domain and has a finite height; every triangle's corners are vertices of the list.
#[derive(Clone, Debug)]
pub struct TriangleList {
    /// The domain's largest coordinate (2^n cells), in fixed-point units.
    domain_max: i64,
    crack_policy: CrackPolicy,
    vertices: Vec<SurfacePoint>,
    triangles: Vec<[u32; 3]>,
    info: Vec<TriangleInfo>,
    role_counts: [u64; 4],
    draw_batches: u64,
    morphing_vertices: u64,
    /// Axis-aligned rectangles (low, high corners) the algorithm culled: left undrawn because
    /// they lie outside the view volume.
    culled: Vec<(SubgridPoint, SubgridPoint)>,
}

impl TriangleList {
    /// An empty list over `lattice`'s domain, whose borders are closed by `crack_policy`.
    pub fn new(lattice: &Lattice, crack_policy: CrackPolicy) -> TriangleList {
        TriangleList {
            domain_max: SubgridPoint::grid(lattice.cells(), 0).raw().0,
            crack_policy,
            vertices: Vec::new(),
            triangles: Vec::new(),
            info: Vec::new(),
            role_counts: [0; 4],
            draw_batches: 0,
            morphing_vertices: 0,
            culled: Vec::new(),
        }
    }

    /// Empties the list for the next frame, keeping every buffer's capacity.
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.triangles.clear();
        self.info.clear();
        self.role_counts = [0; 4];
        self.draw_batches = 0;
        self.morphing_vertices = 0;
        self.culled.clear();
    }

    /// Adds a vertex at `position` with height `z` (terrain-local metres); returns its index.
    ///
    /// # Panics
    /// When the position lies outside the terrain's domain or `z` is not finite (an algorithm
    /// bug, not a property of the data).
    pub fn add_vertex(&mut self, position: SubgridPoint, z: f32) -> u32 {
        let (x, y) = position.raw();
        assert!(
            x <= self.domain_max && y <= self.domain_max,
            "vertex {:?} outside the terrain's domain",
            position.grid_units()
        );
        assert!(z.is_finite(), "vertex height {z} is not finite");
        let index = u32::try_from(self.vertices.len()).expect("fewer than 2^32 vertices");
        self.vertices.push(SurfacePoint { position, z });
        index
    }

    /// [`TriangleList::add_vertex`] for a vertex drawn at a morphed height (counted in
    /// [`TriangleList::morphing_vertices`]).
    pub fn add_morphing_vertex(&mut self, position: SubgridPoint, z: f32) -> u32 {
        self.morphing_vertices += 1;
        self.add_vertex(position, z)
    }

    /// Adds the triangle over vertices `corners`, in drawing order: counter-clockwise seen from
    /// above when it has area in the plane (`super::winding`; the validator refuses the other
    /// order, the list itself takes any).
    ///
    /// # Panics
    /// When a corner is not a vertex of the list.
    pub fn add_triangle(&mut self, corners: [u32; 3], info: TriangleInfo) {
        let n = self.vertices.len();
        assert!(
            corners.iter().all(|&c| (c as usize) < n),
            "triangle {corners:?} refers past the {n} vertices"
        );
        if self.info.last().is_none_or(|last| last.group != info.group) {
            self.draw_batches += 1;
        }
        self.role_counts[info.role.index()] += 1;
        self.triangles.push(corners);
        self.info.push(info);
    }

    /// Declares the rectangle from `low` to `high` (a non-empty, axis-aligned part of the
    /// domain) left undrawn because it lies outside the view volume: the surface need not cover
    /// it. Regions must not overlap each other or the surface (the validator checks the areas).
    ///
    /// # Panics
    /// When the rectangle is empty or inverted, or lies outside the terrain's domain.
    pub fn add_culled_region(&mut self, low: SubgridPoint, high: SubgridPoint) {
        let ((x0, y0), (x1, y1)) = (low.raw(), high.raw());
        assert!(
            x0 < x1 && y0 < y1 && x1 <= self.domain_max && y1 <= self.domain_max,
            "culled region {:?}–{:?} is empty or outside the terrain's domain",
            low.grid_units(),
            high.grid_units()
        );
        self.culled.push((low, high));
    }

    /// The rectangles declared culled this frame (low and high corners), in the order added.
    pub fn culled_regions(&self) -> &[(SubgridPoint, SubgridPoint)] {
        &self.culled
    }

    pub fn crack_policy(&self) -> CrackPolicy {
        self.crack_policy
    }

    pub fn n_triangles(&self) -> u64 {
        self.triangles.len() as u64
    }

    pub fn vertices(&self) -> &[SurfacePoint] {
        &self.vertices
    }

    /// Corner indices of every triangle, in the order added.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Role, group and level of every triangle, aligned with [`TriangleList::triangles`].
    pub fn info(&self) -> &[TriangleInfo] {
        &self.info
    }

    /// Triangles of `role`.
    pub fn role_count(&self, role: TriangleRole) -> u64 {
        self.role_counts[role.index()]
    }

    /// Draw batches: maximal runs of consecutive triangles of one group (what drawing the list
    /// in its order, one call per group change, costs).
    pub fn draw_batches(&self) -> u64 {
        self.draw_batches
    }

    /// Vertices added with [`TriangleList::add_morphing_vertex`].
    pub fn morphing_vertices(&self) -> u64 {
        self.morphing_vertices
    }

    /// The domain's largest coordinate in fixed-point units (2^n cells).
    pub fn domain_max(&self) -> i64 {
        self.domain_max
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.vertices.capacity() * std::mem::size_of::<SurfacePoint>()
            + self.triangles.capacity() * std::mem::size_of::<[u32; 3]>()
            + self.info.capacity() * std::mem::size_of::<TriangleInfo>()
            + self.culled.capacity() * std::mem::size_of::<(SubgridPoint, SubgridPoint)>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(role: TriangleRole, group: u32) -> TriangleInfo {
        TriangleInfo {
            role,
            group,
            level: 0,
        }
    }

    #[test]
    fn roles_batches_and_morphing_vertices_are_counted_as_the_list_is_built() {
        let lattice = Lattice::new(2);
        let mut list = TriangleList::new(&lattice, CrackPolicy::Skirted);
        let a = list.add_vertex(SubgridPoint::grid(0, 0), 1.0);
        let b = list.add_vertex(SubgridPoint::grid(4, 0), 1.0);
        let c = list.add_morphing_vertex(SubgridPoint::grid(4, 4), 2.0);
        list.add_triangle([a, b, c], info(TriangleRole::Surface, 0));
        list.add_triangle([a, b, b], info(TriangleRole::Degenerate, 0));
        list.add_triangle([a, b, c], info(TriangleRole::Skirt, 1));
        list.add_triangle([a, b, c], info(TriangleRole::Surface, 0));
        assert_eq!(list.n_triangles(), 4);
        assert_eq!(list.role_count(TriangleRole::Surface), 2);
        assert_eq!(list.role_count(TriangleRole::Stitch), 0);
        assert_eq!(list.draw_batches(), 3);
        assert_eq!(list.morphing_vertices(), 1);
        list.clear();
        assert_eq!(
            (
                list.n_triangles(),
                list.draw_batches(),
                list.morphing_vertices()
            ),
            (0, 0, 0)
        );
    }

    #[test]
    fn only_surface_and_stitch_triangles_are_surface() {
        let surface: Vec<bool> = TriangleRole::ALL.iter().map(|r| r.is_surface()).collect();
        assert_eq!(surface, [true, false, false, true]);
        assert!(CrackPolicy::Skirted.allows(TriangleRole::Skirt));
        assert!(!CrackPolicy::Closed.allows(TriangleRole::Skirt));
        assert!(!CrackPolicy::Collapsed.allows(TriangleRole::Stitch));
        assert!(CrackPolicy::Collapsed.allows(TriangleRole::Degenerate));
    }
}
