//! What the GPU draws, built on the CPU: one frame's mesh as a triangle list, the view frustum
//! as lines, and the two cameras' matrices (the flight's, and an overview from above).
//!
//! Pure: no GPU, no IO, so it is tested without an adapter. The triangles are the ones the
//! algorithm's own GPU buffers draw ([`GpuBuffers::for_each_triangle`]: the buffers the run
//! timed, so what a user watches is what was timed), corners at their drawn heights (morphed
//! ones included); each triangle's role and level are looked up in the frame's mesh
//! ([`MeshOutput::for_each_triangle`], which `--check` holds equal to the buffers; a triangle
//! with two equal corners, such as a strip's join, is drawn as degenerate), and whether it meets
//! the view volume by the run's own culling test (`Camera::may_see_triangle`, the test behind
//! `triangles_rendered`), so the culling view shows what the run counted. Positions are
//! terrain-local metres in `f32`, which is what the screen needs; the simulation keeps its own
//! `f64` arithmetic. The triangle list is not indexed: vertex `3k..3k+3` is triangle `k`, the
//! order the visitor visits, so a shader recovers a triangle's number from its vertex index and
//! the id pass can count what was drawn. Degenerate triangles have no area to draw: their edges
//! are kept as lines, shown when roles are shown.

use crate::sim::draw::GpuBuffers;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{MeshOutput, SurfacePoint, TriangleInfo, TriangleRole};
use crate::sim::view::Camera;
use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, Mat4};
use std::collections::HashMap;

/// One corner of one triangle, as the vertex shader reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    /// Terrain-local metres.
    pub position: [f32; 3],
    /// The triangle's unit face normal (flat shading), pointing up.
    pub normal: [f32; 3],
    /// (1,0,0), (0,1,0), (0,0,1) at the three corners: the fragment shader draws the wireframe
    /// where one coordinate nears zero.
    pub barycentric: [f32; 3],
    /// The triangle's refinement level: a 4-8 triangle's depth in the bintree (0 for the two
    /// base triangles), a triangle list's level as its algorithm numbers it.
    pub level: f32,
    /// 1 when the triangle may meet the view volume (`Camera::may_see_triangle`), 0 when culled.
    pub in_view: f32,
    /// The triangle's role, [`TriangleRole::index`]: 0 surface, 1 skirt, 2 degenerate, 3 stitch.
    pub role: f32,
}

/// The colour degenerate triangles' edges are drawn in when roles are shown: magenta.
pub const DEGENERATE_COLOUR: [f32; 3] = [0.9, 0.1, 0.8];

/// A frame's mesh as a triangle list. The vertex buffer is kept and refilled frame after frame
/// ([`MeshGeometry::rebuild`] allocates only when the mesh outgrows it); building is O(T).
#[derive(Clone, Debug, Default)]
pub struct MeshGeometry {
    vertices: Vec<MeshVertex>,
    max_level: u32,
    /// The edges of the degenerate triangles, as a line list.
    degenerate_lines: Vec<LineVertex>,
}

impl MeshGeometry {
    /// Refills the triangle list from the triangles `buffers` draw, with the role and level
    /// `mesh` gives each; `camera` decides which triangles are in view.
    pub fn rebuild(
        &mut self,
        hierarchy: &Hierarchy,
        buffers: &GpuBuffers,
        mesh: MeshOutput,
        camera: &Camera,
    ) {
        let spacing = hierarchy.field().spacing();
        self.vertices.clear();
        self.degenerate_lines.clear();
        self.max_level = 0;
        let mut infos: HashMap<[(i64, i64, u32); 3], TriangleInfo> = HashMap::new();
        mesh.for_each_triangle(hierarchy, |triangle| {
            infos.insert(corner_key(triangle.corners), triangle.info);
        });
        let degenerate = TriangleInfo {
            role: TriangleRole::Degenerate,
            group: 0,
            level: 0,
        };
        buffers.for_each_triangle(|drawn| {
            let key = corner_key(drawn);
            let repeated = key[0] == key[1] || key[1] == key[2] || key[0] == key[2];
            let info = match infos.get(&key) {
                Some(info) => *info,
                None if repeated => degenerate,
                None => TriangleInfo {
                    role: TriangleRole::Surface,
                    group: 0,
                    level: 0,
                },
            };
            let corners = drawn.map(|c| c.local(spacing));
            let level = info.level;
            self.max_level = self.max_level.max(level);
            let in_view = f32::from(u8::from(camera.may_see_triangle(corners)));
            let normal = face_normal(corners).as_vec3().to_array();
            let role = info.role;
            if role == TriangleRole::Degenerate {
                for k in 0..3 {
                    for corner in [corners[k], corners[(k + 1) % 3]] {
                        self.degenerate_lines.push(LineVertex {
                            position: corner.as_vec3().to_array(),
                            colour: DEGENERATE_COLOUR,
                        });
                    }
                }
            }
            for (k, corner) in corners.iter().enumerate() {
                let mut barycentric = [0.0; 3];
                barycentric[k] = 1.0;
                self.vertices.push(MeshVertex {
                    position: corner.as_vec3().to_array(),
                    normal,
                    barycentric,
                    level: level as f32,
                    in_view,
                    role: role.index() as f32,
                });
            }
        });
    }

    pub fn vertices(&self) -> &[MeshVertex] {
        &self.vertices
    }

    /// The number of triangles in the list.
    pub fn n_triangles(&self) -> u64 {
        (self.vertices.len() / 3) as u64
    }

    /// The deepest level in the mesh (the wireframe's colour scale ends there).
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// The edges of the mesh's degenerate triangles, as a line list in [`DEGENERATE_COLOUR`].
    pub fn degenerate_lines(&self) -> &[LineVertex] {
        &self.degenerate_lines
    }
}

/// A triangle's corners as a lookup key, rotated to start at the smallest corner (so that the
/// mesh's and the buffers' triangles meet whichever corner they start at).
fn corner_key(corners: [SurfacePoint; 3]) -> [(i64, i64, u32); 3] {
    let points = corners.map(|c| {
        let (x, y) = c.position.raw();
        (x, y, c.z.to_bits())
    });
    let start = (0..3).min_by_key(|&k| points[k]).unwrap_or(0);
    [0, 1, 2].map(|k| points[(start + k) % 3])
}

/// The unit normal of a triangle, oriented up (+z); a degenerate triangle gets +z.
fn face_normal(corners: [DVec3; 3]) -> DVec3 {
    let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    let oriented = if normal.z < 0.0 { -normal } else { normal };
    oriented.try_normalize().unwrap_or(DVec3::Z)
}

/// One end of a line segment, as the line shader reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LineVertex {
    pub position: [f32; 3],
    pub colour: [f32; 3],
}

/// The frustum's colour: a saturated orange that stands out on the grey terrain.
pub const FRUSTUM_COLOUR: [f32; 3] = [1.0, 0.45, 0.05];

/// The view volume's 12 edges plus 4 lines from the eye, as a line list. The far plane is
/// drawn at `min(far, draw_distance)` so that a 100 km far plane does not dwarf the terrain.
pub fn frustum_lines(camera: &Camera, draw_distance: f64) -> Vec<LineVertex> {
    let settings = camera.settings;
    let tan_y = (0.5 * settings.fovy).tan();
    let tan_x = tan_y * settings.aspect();
    let rectangle = |depth: f64| {
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(sx, sy)| {
            camera.eye
                + camera.forward * depth
                + camera.right * (sx * depth * tan_x)
                + camera.up * (sy * depth * tan_y)
        })
    };
    let near = rectangle(settings.near);
    let far = rectangle(settings.far.min(draw_distance).max(settings.near));
    let mut segments = Vec::with_capacity(16);
    for k in 0..4 {
        let next = (k + 1) % 4;
        segments.push((near[k], near[next]));
        segments.push((far[k], far[next]));
        segments.push((near[k], far[k]));
        segments.push((camera.eye, near[k]));
    }
    segments
        .into_iter()
        .flat_map(|(a, b)| [a, b])
        .map(|p| LineVertex {
            position: p.as_vec3().to_array(),
            colour: FRUSTUM_COLOUR,
        })
        .collect()
}

/// A rectangle of the target in pixels, origin at the top left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Viewport {
    pub fn aspect(&self) -> f64 {
        f64::from(self.width) / f64::from(self.height.max(1))
    }

    /// The largest centred sub-rectangle of aspect `aspect` (width / height).
    pub fn fitted(&self, aspect: f64) -> Viewport {
        let (width, height) = if self.aspect() > aspect {
            (
                (f64::from(self.height) * aspect).round() as u32,
                self.height,
            )
        } else {
            (self.width, (f64::from(self.width) / aspect).round() as u32)
        };
        let (width, height) = (width.clamp(1, self.width), height.clamp(1, self.height));
        Viewport {
            x: self.x + (self.width - width) / 2,
            y: self.y + (self.height - height) / 2,
            width,
            height,
        }
    }

    /// `n` equal panes side by side.
    pub fn split_horizontally(&self, n: u32) -> Vec<Viewport> {
        let n = n.max(1);
        let width = (self.width / n).max(1);
        (0..n)
            .map(|k| Viewport {
                x: self.x + k * width,
                y: self.y,
                width,
                height: self.height,
            })
            .collect()
    }
}

/// Which camera a pane shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewChoice {
    /// The flight's camera, as the algorithm saw the frame.
    Flight,
    /// Straight down on the whole terrain (orthographic): the refined region, the culled
    /// triangles and the frustum, from above.
    Overview,
}

/// Clip-space matrix (wgpu conventions, reversed depth: 1 at the near plane, 0 at the far one,
/// which keeps precision over a 10^5 depth range) of the flight camera, for a viewport of
/// `aspect` (the panes are fitted to the experiment's aspect, so this is normally its own).
/// Built from the camera's own axes: clip x, y are `Camera::to_camera`'s right and up scaled by
/// the lens, clip w is its depth, so pixels land where `Camera::project_camera` puts them.
pub fn flight_view_projection(camera: &Camera, aspect: f64) -> Mat4 {
    let settings = camera.settings;
    let focal_y = 1.0 / (0.5 * settings.fovy).tan();
    let focal_x = focal_y / aspect;
    let (near, far) = (settings.near, settings.far);
    // depth_ndc = a + b / depth: 1 at the near plane, 0 at the far plane.
    let b = near * far / (far - near);
    let a = -near / (far - near);
    let row = |axis: DVec3, scale: f64| {
        let axis = axis * scale;
        [axis.x, axis.y, axis.z, -axis.dot(camera.eye)]
    };
    let depth = row(camera.forward, 1.0);
    let rows = [
        row(camera.right, focal_x),
        row(camera.up, focal_y),
        [a * depth[0], a * depth[1], a * depth[2], a * depth[3] + b],
        depth,
    ];
    DMat4::from_cols_array_2d(&rows).transpose().as_mat4()
}

/// Clip-space matrix looking straight down (+y up on screen, +x right) on the rectangle
/// `[0, extent.0] × [0, extent.1]` grown by `margin` (a fraction of the larger side) and widened
/// to `aspect`. Seen from straight above a height field hides nothing of itself, so depth only
/// has to keep everything inside the clip volume: heights within ±[`OVERVIEW_DEPTH_M`] map into
/// it, higher nearer (reversed, as in the flight view).
pub fn overview_view_projection(extent: (f64, f64), margin: f64, aspect: f64) -> Mat4 {
    let pad = margin * extent.0.max(extent.1);
    let (mut half_x, mut half_y) = (0.5 * extent.0 + pad, 0.5 * extent.1 + pad);
    if half_x / half_y < aspect {
        half_x = half_y * aspect;
    } else {
        half_y = half_x / aspect;
    }
    let (centre_x, centre_y) = (0.5 * extent.0, 0.5 * extent.1);
    let rows = [
        [1.0 / half_x, 0.0, 0.0, -centre_x / half_x],
        [0.0, 1.0 / half_y, 0.0, -centre_y / half_y],
        [0.0, 0.0, 0.5 / OVERVIEW_DEPTH_M, 0.5],
        [0.0, 0.0, 0.0, 1.0],
    ];
    DMat4::from_cols_array_2d(&rows).transpose().as_mat4()
}

/// Heights (and frustum points) within this many metres of z = 0 fit in the overview's depth.
pub const OVERVIEW_DEPTH_M: f64 = 1.0e7;
