//! View-frustum culling flags as ROAM'97 §7.1 describes them, kept incrementally: what ROAM's
//! priorities (an `Out` triangle gets 0) and strips (only drawn leaves) read. It is not the
//! runner's `triangles_rendered` test (`Camera::may_see_triangle`, the same for every family),
//! and it removes no triangle from the mesh.
//!
//! The frustum is the intersection of six half-spaces. Every triangle of the bintree carries an
//! IN flag per half-space (its wedgie lies entirely inside it) and a label: `Out` when the wedgie
//! lies entirely outside at least one half-space, `AllIn` when every IN flag is set, `DontKnow`
//! otherwise. Wedgies are nested (the culling thickness of `thickness.rs`), so a label of `Out` or
//! `AllIn` holds for the whole subtree.
//!
//! **Per frame** ([`update_flags`]): a recursive traversal from the two roots. A triangle inherits
//! its parent's IN flags and tests its wedgie only against the half-spaces not marked IN. If it
//! was `Out` (or `AllIn`) in the previous frame and still is, its subtree is unchanged and the
//! recursion stops there; if it just became `Out` (or `AllIn`), its whole subtree is relabelled
//! (work proportional to the triangles whose label changes); if it is `DontKnow`, the recursion
//! continues into its children. So a frame costs O(triangles straddling the frustum's boundary +
//! triangles whose label changed), not O(tree). Leaves and split triangles whose `Out`-ness
//! changed are reported: their priorities (and strips) depend on it. Triangles created by a split
//! are classified once, from their parent's flags ([`classify_child`]). The wedgie is read from
//! the triangle's own copy of its corners and culling thickness.
//!
//! **Wedgie against a plane.** With the plane n·p + d ≥ 0 in world space (|n| = 1), the six
//! points corner ± e·ẑ of a wedgie lie inside when min over the corners of (n·p + d) − e·|n_z| ≥ 0
//! and outside when the max + e·|n_z| < 0. The planes are the camera's frustum, built once per
//! frame in eye-relative world coordinates ([`Frustum`]).

use super::bintree::{Bintree, TriangleKey};
use crate::sim::view::Camera;
use glam::DVec3;

/// Every half-space's IN flag set.
pub const ALL_IN: u8 = 0b11_1111;

/// ROAM §7.1's label of a triangle's wedgie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullLabel {
    /// Entirely outside at least one half-space: descendants are outside too.
    Out,
    /// Entirely inside all six half-spaces: descendants are inside too.
    AllIn,
    /// Neither is known.
    DontKnow,
}

/// A triangle's flags: its label and its per-half-space IN flags (bit k for plane k).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CullFlags {
    pub label: CullLabel,
    pub in_mask: u8,
}

impl CullFlags {
    /// What a triangle is before anything is known (and what every triangle is with culling
    /// flags off).
    pub const UNKNOWN: CullFlags = CullFlags {
        label: CullLabel::DontKnow,
        in_mask: 0,
    };

    pub fn is_out(&self) -> bool {
        self.label == CullLabel::Out
    }
}

/// A frustum plane in world space, eye-relative: inside when n·(p − eye) + offset ≥ 0, |n| = 1.
#[derive(Clone, Copy, Debug)]
struct Plane {
    normal: DVec3,
    offset: f64,
}

/// The six half-spaces of one frame's view volume.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    eye: DVec3,
    planes: [Plane; 6],
}

impl Frustum {
    /// The camera's frustum: four side planes through the eye, the near and the far plane.
    pub fn new(camera: &Camera) -> Frustum {
        let settings = camera.settings;
        let ty = (0.5 * settings.fovy).tan();
        let tx = ty * settings.aspect();
        // Camera-space normals (right, up, forward) turned into world space.
        let world = |x: f64, y: f64, z: f64| camera.right * x + camera.up * y + camera.forward * z;
        let side = |x: f64, y: f64, t: f64| Plane {
            normal: world(x, y, t).normalize(),
            offset: 0.0,
        };
        Frustum {
            eye: camera.eye,
            planes: [
                side(-1.0, 0.0, tx),
                side(1.0, 0.0, tx),
                side(0.0, -1.0, ty),
                side(0.0, 1.0, ty),
                Plane {
                    normal: camera.forward,
                    offset: -settings.near,
                },
                Plane {
                    normal: -camera.forward,
                    offset: settings.far,
                },
            ],
        }
    }

    /// Tests a wedgie (three corners, thickness `e`) against the half-spaces not already set in
    /// `flags.in_mask`, starting from the parent's flags.
    pub fn classify(&self, corners: [DVec3; 3], e: f64, inherited: u8) -> CullFlags {
        let mut in_mask = inherited;
        // Eye-relative corners once, then three dot products per plane.
        let [p0, p1, p2] = corners.map(|p| p - self.eye);
        for (k, plane) in self.planes.iter().enumerate() {
            if in_mask & (1 << k) != 0 {
                continue;
            }
            let (a, b, c) = (
                plane.normal.dot(p0) + plane.offset,
                plane.normal.dot(p1) + plane.offset,
                plane.normal.dot(p2) + plane.offset,
            );
            let reach = e * plane.normal.z.abs();
            let (low, high) = (a.min(b).min(c), a.max(b).max(c));
            if high + reach < 0.0 {
                return CullFlags {
                    label: CullLabel::Out,
                    in_mask,
                };
            }
            if low - reach >= 0.0 {
                in_mask |= 1 << k;
            }
        }
        CullFlags {
            label: if in_mask == ALL_IN {
                CullLabel::AllIn
            } else {
                CullLabel::DontKnow
            },
            in_mask,
        }
    }
}

/// The flags of a new child of `parent` (whose flags are current): inherited when the parent is
/// `Out` or `AllIn`, tested against the parent's remaining half-spaces otherwise.
pub fn classify_child(
    frustum: &Frustum,
    bintree: &Bintree,
    child: TriangleKey,
    parent: CullFlags,
) -> CullFlags {
    match parent.label {
        CullLabel::Out | CullLabel::AllIn => parent,
        CullLabel::DontKnow => {
            let (corners, e) = wedgie(bintree, child);
            frustum.classify(corners, e, parent.in_mask)
        }
    }
}

/// A triangle's corners and culling thickness.
pub fn wedgie(bintree: &Bintree, key: TriangleKey) -> ([DVec3; 3], f64) {
    let geometry = &bintree.get(key).geometry;
    (geometry.corners, f64::from(geometry.culling_thickness))
}

/// What one frame's flag update did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlagCounts {
    /// Wedgie classifications (one per triangle visited by the traversal).
    pub tests: u64,
}

/// §7.1's per-frame traversal. Appends to `changed` every triangle whose `Out`-ness changed
/// (leaves and split triangles alike); `stack` is a reused buffer.
pub fn update_flags(
    bintree: &mut Bintree,
    frustum: &Frustum,
    stack: &mut Vec<(TriangleKey, u8)>,
    changed: &mut Vec<TriangleKey>,
) -> FlagCounts {
    let mut counts = FlagCounts::default();
    stack.clear();
    for root in bintree.roots() {
        stack.push((root, 0));
    }
    while let Some((key, inherited)) = stack.pop() {
        let old = bintree.get(key).flags;
        let (corners, e) = wedgie(bintree, key);
        let new = frustum.classify(corners, e, inherited);
        counts.tests += 1;
        bintree.triangles[key].flags = new;
        if new.is_out() != old.is_out() {
            changed.push(key);
        }
        let children = bintree.get(key).children;
        match new.label {
            CullLabel::DontKnow => {
                if let Some(children) = children {
                    stack.extend(children.map(|c| (c, new.in_mask)));
                }
            }
            label if label == old.label => {}
            _ => {
                if let Some(children) = children {
                    relabel_subtree(bintree, children, new, changed);
                }
            }
        }
    }
    counts
}

/// Gives every triangle below `children` the flags `flags` (an `Out` or `AllIn` ancestor's),
/// reporting those whose `Out`-ness changed.
fn relabel_subtree(
    bintree: &mut Bintree,
    children: [TriangleKey; 2],
    flags: CullFlags,
    changed: &mut Vec<TriangleKey>,
) {
    let mut pending = children.to_vec();
    while let Some(key) = pending.pop() {
        let triangle = &mut bintree.triangles[key];
        if triangle.flags.label == flags.label {
            // An `Out` (`AllIn`) triangle's whole subtree is `Out` (`AllIn`) already.
            continue;
        }
        if triangle.flags.is_out() != flags.is_out() {
            changed.push(key);
        }
        triangle.flags = flags;
        if let Some(grandchildren) = triangle.children {
            pending.extend(grandchildren);
        }
    }
}
