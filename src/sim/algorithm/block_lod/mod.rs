//! What the block-based algorithms `geomipmap` and `chunked` share: their goal (a tolerance or a
//! triangle target), how a block's distance is measured (the paper's horizontal-view assumption
//! or the exact vertical projection), the detail test d < δ·C and the morph factor of eq. 3.5
//! (`threshold.rs`), box culling (`cull.rs`), the regular grid both triangulate their blocks
//! with and geomorphing on it (`grid.rs`), and the per-frame τ search that holds a triangle
//! target (`budget.rs`). `vanek` also uses the box culling and the τ search, `stitching-strips`
//! the box culling; `geomipmap` and `vanek` cull their patch grids through one quadtree
//! (`quadtree.rs`).
//!
//! Both schemes' blocks (de Boer's geomipmaps, Lauritsen–Nielsen's chunks) are regular grids of
//! (2^k + 1)² samples taken every 2^ℓ-th sample, each cell split along its south-west–north-east
//! diagonal; a grid at stride s with its odd vertices moved onto the lines between their even
//! neighbours is exactly the grid at stride 2s, which is what makes geomorphing pop-free.
//!
//! What it is not: an algorithm. No state is kept here from frame to frame.

pub(super) mod budget;
pub(super) mod cull;
pub(super) mod grid;
pub(super) mod quadtree;
pub(super) mod threshold;

/// What a block-based algorithm holds fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlockGoal {
    /// The screen-space tolerance τ in pixels (finite, ≥ 0): C = S/(2τ·tan(fov/2)) (eq. 3.3).
    TolerancePx(f64),
    /// A triangle count held every frame by choosing τ: the finest mesh (smallest τ, to 1/64
    /// of an octave) whose triangles, skirts and stitches included, do not exceed the target
    /// (see `budget.rs`).
    TargetTriangles(u64),
}

/// How a block's distance d, compared with δ·C, is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// The papers' choice (de Boer, Lauritsen–Nielsen eq. 3.2): the error is projected as if
    /// the view direction were horizontal, ε = δ·S/(2d·tan(fov/2)) with d the Euclidean
    /// distance from the eye to the block's box. Conservative for an eye above the block (a
    /// vertical segment seen from above looks shorter), accurate near the ground.
    HorizontalView,
    /// The exact projection the paper refers to (Lindstrom et al. 1996, its \[13\]): the
    /// vertical-projection error λ·δ·r/(r² + h²), its largest value over the block's box, used
    /// as the equivalent distance d = 1/max(r/(r² + h²)). Never refines more than
    /// `HorizontalView`; still independent of the view direction (the audit measures the real
    /// camera).
    Exact,
}
