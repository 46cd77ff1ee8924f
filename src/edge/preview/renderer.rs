//! The wgpu drawing shared by the window and the offscreen target (README, "Seeing the meshes:
//! `preview` and `render`"). It is a way to look at meshes, not SPEC §12's frame a GPU draws:
//! nothing here is timed or counted, and it builds no algorithm's buffers.
//!
//! Three pipelines over one uniform block (`shader.wgsl`): the shaded mesh with its wireframe
//! coloured by refinement level (culled triangles optionally tinted, skirts and stitches
//! optionally coloured by role), the flat triangle-id pass
//! (triangle k written as k + 1 into an `R32Uint` target, 0 is background), and coloured lines
//! (the view frustum, drawn over everything). Depth is reversed (cleared to 0, nearer is
//! greater). The renderer owns no target: the caller passes the views to draw into, so the
//! window draws into its swap chain and [`super::headless`] into textures it reads back.
//!
//! Per draw it uploads each pane's triangle list into a fresh buffer (O(T) bytes; the preview
//! favours simplicity over reusing GPU buffers).

use super::geometry::{LineVertex, MeshGeometry, MeshVertex, Viewport};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

/// The depth format of every target.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The id pass's format: one triangle number per pixel.
pub const TRIANGLE_ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The background (linear RGB): a pale sky.
pub const SKY_COLOUR: wgpu::Color = wgpu::Color {
    r: 0.60,
    g: 0.72,
    b: 0.88,
    a: 1.0,
};

/// How a pane draws its mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawOptions {
    /// Overlay the triangle edges, coloured by refinement level.
    pub wireframe: bool,
    /// Darken the triangles outside the view volume (the culling view).
    pub tint_culled: bool,
    /// Tell roles apart: skirts in cyan, stitches in violet, degenerate triangles as magenta
    /// lines (the pane's lines must then hold them, see `MeshGeometry::degenerate_lines`).
    /// Off, every triangle is shaded as terrain, as a renderer would draw it.
    pub roles: bool,
}

/// One pane of a frame: a viewport, a camera and what to draw in it.
pub struct Pane<'a> {
    pub viewport: Viewport,
    pub view_projection: Mat4,
    pub mesh: &'a MeshGeometry,
    /// Lines drawn over the mesh (the frustum in the overview); may be empty.
    pub lines: &'a [LineVertex],
    pub options: DrawOptions,
}

/// The device, its queue and the three pipelines.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    uniform_layout: wgpu::BindGroupLayout,
    shaded: wgpu::RenderPipeline,
    triangle_ids: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
}

/// The uniform block, laid out as `Uniforms` in `shader.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Uniforms {
    view_projection: [[f32; 4]; 4],
    sun: [f32; 4],
    options: [f32; 4],
}

const SHADER: &str = include_str!("shader.wgsl");

impl Renderer {
    /// Compiles the shaders and builds the pipelines for colour targets of `colour_format`.
    pub fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        colour_format: wgpu::TextureFormat,
    ) -> Renderer {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("preview shaders"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let uniform_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("preview uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("preview layout"),
            bind_group_layouts: &[Some(&uniform_layout)],
            immediate_size: 0,
        });
        let mesh_attributes = wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32, 4 => Float32,
            5 => Float32
        ];
        let mesh_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as wgpu::BufferAddress,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attributes,
        })];
        let line_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as wgpu::BufferAddress,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &line_attributes,
        })];
        let pipeline = |spec: PipelineSpec| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(spec.label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(spec.vertex_entry),
                    compilation_options: Default::default(),
                    buffers: spec.buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: spec.topology,
                    // Triangles are seen from both sides: the overview looks down, the flight
                    // camera may skim under an overhang of the far terrain.
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(spec.depth_tested),
                    depth_compare: Some(if spec.depth_tested {
                        wgpu::CompareFunction::GreaterEqual
                    } else {
                        wgpu::CompareFunction::Always
                    }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(spec.fragment_entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: spec.format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let shaded = pipeline(PipelineSpec {
            label: "shaded mesh",
            vertex_entry: "mesh_vertex",
            fragment_entry: "shaded_fragment",
            buffers: &mesh_buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            format: colour_format,
            depth_tested: true,
        });
        let triangle_ids = pipeline(PipelineSpec {
            label: "triangle ids",
            vertex_entry: "mesh_vertex",
            fragment_entry: "id_fragment",
            buffers: &mesh_buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            format: TRIANGLE_ID_FORMAT,
            depth_tested: true,
        });
        let lines = pipeline(PipelineSpec {
            label: "lines",
            vertex_entry: "line_vertex",
            fragment_entry: "line_fragment",
            buffers: &line_buffers,
            topology: wgpu::PrimitiveTopology::LineList,
            format: colour_format,
            depth_tested: false,
        });
        Renderer {
            device,
            queue,
            uniform_layout,
            shaded,
            triangle_ids,
            lines,
        }
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Records the drawing of `panes` into `colour` (cleared to [`SKY_COLOUR`]) and `depth`.
    pub fn draw_panes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        colour: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        panes: &[Pane],
    ) {
        let uploads: Vec<PaneUpload> = panes.iter().map(|pane| self.upload(pane)).collect();
        let mut pass = begin_pass(encoder, colour, SKY_COLOUR, depth, "panes");
        for (pane, upload) in panes.iter().zip(&uploads) {
            set_viewport(&mut pass, pane.viewport);
            pass.set_bind_group(0, &upload.uniforms, &[]);
            if let Some(mesh) = &upload.mesh {
                pass.set_pipeline(&self.shaded);
                pass.set_vertex_buffer(0, mesh.slice(..));
                pass.draw(0..pane.mesh.vertices().len() as u32, 0..1);
            }
            if let Some(lines) = &upload.lines {
                pass.set_pipeline(&self.lines);
                pass.set_vertex_buffer(0, lines.slice(..));
                pass.draw(0..pane.lines.len() as u32, 0..1);
            }
        }
    }

    /// Records the id pass of one pane's mesh into `ids` (an [`TRIANGLE_ID_FORMAT`] view, cleared
    /// to 0) and `depth`. The pane's lines are not drawn.
    pub fn draw_triangle_ids(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        ids: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        pane: &Pane,
    ) {
        let upload = self.upload(pane);
        let mut pass = begin_pass(encoder, ids, wgpu::Color::TRANSPARENT, depth, "ids");
        set_viewport(&mut pass, pane.viewport);
        pass.set_bind_group(0, &upload.uniforms, &[]);
        if let Some(mesh) = &upload.mesh {
            pass.set_pipeline(&self.triangle_ids);
            pass.set_vertex_buffer(0, mesh.slice(..));
            pass.draw(0..pane.mesh.vertices().len() as u32, 0..1);
        }
    }

    fn upload(&self, pane: &Pane) -> PaneUpload {
        let sun = Vec3::new(-0.4, -0.5, 0.77).normalize();
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let uniforms = Uniforms {
            view_projection: pane.view_projection.to_cols_array_2d(),
            sun: sun.extend(0.0).to_array(),
            options: [
                flag(pane.options.wireframe),
                flag(pane.options.tint_culled),
                pane.mesh.max_level() as f32,
                flag(pane.options.roles),
            ],
        };
        let uniform_buffer = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("pane uniforms"),
                contents: bytemuck::bytes_of(&uniforms),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("pane uniforms"),
            layout: &self.uniform_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform_buffer.as_entire_binding(),
            }],
        });
        let vertex_buffer = |label: &str, bytes: &[u8]| {
            (!bytes.is_empty()).then(|| {
                self.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(label),
                        contents: bytes,
                        usage: wgpu::BufferUsages::VERTEX,
                    })
            })
        };
        PaneUpload {
            uniforms: bind_group,
            mesh: vertex_buffer("mesh", bytemuck::cast_slice(pane.mesh.vertices())),
            lines: vertex_buffer("lines", bytemuck::cast_slice(pane.lines)),
        }
    }
}

/// What one pipeline differs in.
struct PipelineSpec<'a> {
    label: &'a str,
    vertex_entry: &'a str,
    fragment_entry: &'a str,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    topology: wgpu::PrimitiveTopology,
    format: wgpu::TextureFormat,
    /// Tested against and written to depth; otherwise drawn over everything.
    depth_tested: bool,
}

/// A pane's buffers on the GPU, alive for one draw.
struct PaneUpload {
    uniforms: wgpu::BindGroup,
    mesh: Option<wgpu::Buffer>,
    lines: Option<wgpu::Buffer>,
}

fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    clear: wgpu::Color,
    depth: &wgpu::TextureView,
    label: &str,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            // Reversed depth: 0 is the far plane.
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(0.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

fn set_viewport(pass: &mut wgpu::RenderPass, viewport: Viewport) {
    pass.set_viewport(
        viewport.x as f32,
        viewport.y as f32,
        viewport.width as f32,
        viewport.height as f32,
        0.0,
        1.0,
    );
    pass.set_scissor_rect(viewport.x, viewport.y, viewport.width, viewport.height);
}
