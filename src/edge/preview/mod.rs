//! The preview: one experiment's flight replayed and drawn, in a window (`roamsim preview`) or
//! offscreen into PNG files (`roamsim render`). Built only with the `preview` cargo feature,
//! which enables the optional dependencies wgpu, winit, bytemuck and pollster; the default build
//! compiles none of this. It is a way to look at meshes, not the GPU buffers SPEC §12 times: it
//! draws every frame's mesh afresh through the mesh visitor.
//!
//! - [`replay`] steps the experiment's algorithms through the flight with the simulation's own
//!   runner ([`crate::sim::run::FrameRunner`]), so the mesh and statistics shown are exactly
//!   those of `roamsim run`; it knows nothing of drawing.
//! - [`geometry`] turns one frame's mesh into vertex data (terrain-local positions, face normals,
//!   each triangle's refinement level and whether it meets the view volume) and the view
//!   frustum into lines, and builds the camera matrices. Pure: testable without a GPU.
//! - [`renderer`] is the wgpu drawing shared by the window and the offscreen target: the shaded
//!   mesh with its wireframe coloured by level, the frustum, and a flat triangle-id pass.
//! - [`headless`] renders to textures and reads them back (PNG files, test images);
//!   [`window`] is the winit window with its keys.
//!
//! The preview never changes what a run computes: it reads meshes and statistics, nothing else.

pub mod geometry;
pub mod headless;
pub mod renderer;
pub mod replay;
pub mod window;
