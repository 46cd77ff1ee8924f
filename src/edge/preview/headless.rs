//! Drawing without a window: `roamsim render` and the render test (README, "Seeing the meshes:
//! `preview` and `render`"). It computes nothing a run reports (the frames are the runner's,
//! through `replay.rs`) and draws through [`super::renderer`], as the window does.
//!
//! [`Offscreen`] owns a wgpu device on whatever adapter the machine has (a GPU, or Mesa's
//! software Vulkan/GL on CI), draws panes into textures and reads the pixels back: the colour
//! image (written as PNG) and the triangle-id image (one triangle number per pixel, which the
//! test counts). [`render_experiment`] replays an experiment and writes the chosen frames.
//! [`FramePanes`] (a frame's lanes laid out as panes, with their cameras) is shared with the
//! window.

use super::geometry::{
    MeshGeometry, ViewChoice, Viewport, flight_view_projection, frustum_lines,
    overview_view_projection,
};
use super::renderer::{DEPTH_FORMAT, DrawOptions, Pane, Renderer, TRIANGLE_ID_FORMAT};
use super::replay::{LaneFrame, Replay, Scene, UnknownAlgorithm};
use crate::edge::experiment::ExperimentError;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::RunError;
use std::path::{Path, PathBuf};

/// The colour targets' format: 8-bit sRGB, what PNG files hold.
const COLOUR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Bytes per pixel of both read-back formats (RGBA8 and R32Uint).
const BYTES_PER_PIXEL: u32 = 4;
/// The overview's margin around the terrain, a fraction of its larger side.
const OVERVIEW_MARGIN: f64 = 0.05;

/// Why nothing could be drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum HeadlessError {
    #[error("no graphics adapter: {0}")]
    NoAdapter(String),
    #[error("cannot open the graphics device: {0}")]
    Device(String),
    #[error("cannot read the image back from the graphics device: {0}")]
    Readback(String),
    #[error("cannot draw the captions: {0}")]
    Caption(String),
    #[error("{path}: cannot write the image: {message}")]
    Write { path: PathBuf, message: String },
}

/// An RGBA8 (sRGB) image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

/// Triangle numbers per pixel, rows top to bottom: 0 is background, k + 1 is triangle k of the
/// drawn [`MeshGeometry`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TriangleIdImage {
    pub width: u32,
    pub height: u32,
    pub ids: Vec<u32>,
}

/// A device with colour, id and depth targets of one size.
pub struct Offscreen {
    renderer: Renderer,
    adapter_info: wgpu::AdapterInfo,
    width: u32,
    height: u32,
    colour: wgpu::Texture,
    triangle_ids: wgpu::Texture,
    depth: wgpu::Texture,
}

impl Offscreen {
    /// Opens the default adapter (`WGPU_BACKEND` and friends are honoured) and makes targets of
    /// `width` × `height` pixels.
    pub fn new(width: u32, height: u32) -> Result<Offscreen, HeadlessError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::default(),
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| HeadlessError::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("roamsim offscreen"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| HeadlessError::Device(e.to_string()))?;
        let target = |label: &str, format: wgpu::TextureFormat| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let colour = target("colour", COLOUR_FORMAT);
        let triangle_ids = target("triangle ids", TRIANGLE_ID_FORMAT);
        let depth = target("depth", DEPTH_FORMAT);
        Ok(Offscreen {
            renderer: Renderer::new(device, queue, COLOUR_FORMAT),
            adapter_info: adapter.get_info(),
            width,
            height,
            colour,
            triangle_ids,
            depth,
        })
    }

    /// The adapter's name and backend, e.g. `llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan)`.
    pub fn adapter_description(&self) -> String {
        format!(
            "{} ({:?})",
            self.adapter_info.name, self.adapter_info.backend
        )
    }

    /// The whole target.
    pub fn viewport(&self) -> Viewport {
        Viewport {
            x: 0,
            y: 0,
            width: self.width,
            height: self.height,
        }
    }

    /// Draws `panes` and reads the colour image back.
    pub fn render_colour(&self, panes: &[Pane]) -> Result<RgbaImage, HeadlessError> {
        let mut encoder = self.encoder();
        self.renderer.draw_panes(
            &mut encoder,
            &view_of(&self.colour),
            &view_of(&self.depth),
            panes,
        );
        let pixels = self.read_back(encoder, &self.colour)?;
        Ok(RgbaImage {
            width: self.width,
            height: self.height,
            pixels,
        })
    }

    /// Draws one pane's id pass and reads the triangle numbers back.
    pub fn render_triangle_ids(&self, pane: &Pane) -> Result<TriangleIdImage, HeadlessError> {
        let mut encoder = self.encoder();
        self.renderer.draw_triangle_ids(
            &mut encoder,
            &view_of(&self.triangle_ids),
            &view_of(&self.depth),
            pane,
        );
        let bytes = self.read_back(encoder, &self.triangle_ids)?;
        Ok(TriangleIdImage {
            width: self.width,
            height: self.height,
            ids: bytemuck::pod_collect_to_vec(&bytes),
        })
    }

    fn encoder(&self) -> wgpu::CommandEncoder {
        self.renderer
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("offscreen"),
            })
    }

    /// Submits `encoder` plus a copy of `texture` into a buffer, waits, and returns the
    /// texture's bytes without the rows' alignment padding.
    fn read_back(
        &self,
        mut encoder: wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) -> Result<Vec<u8>, HeadlessError> {
        let device = self.renderer.device();
        let row_bytes = self.width * BYTES_PER_PIXEL;
        let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read back"),
            size: u64::from(padded_row_bytes) * u64::from(self.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes),
                    rows_per_image: Some(self.height),
                },
            },
            texture.size(),
        );
        self.renderer.queue().submit([encoder.finish()]);
        let (sender, receiver) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |result| {
            // The receiver waits below; a send can only fail if it is gone, and then no one
            // is left to tell.
            let _ = sender.send(result);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| HeadlessError::Readback(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| HeadlessError::Readback(e.to_string()))?
            .map_err(|e| HeadlessError::Readback(e.to_string()))?;
        let mapped = buffer
            .get_mapped_range(..)
            .map_err(|e| HeadlessError::Readback(e.to_string()))?;
        let mut pixels = Vec::with_capacity((row_bytes * self.height) as usize);
        for row in mapped.chunks_exact(padded_row_bytes as usize) {
            pixels.extend_from_slice(&row[..row_bytes as usize]);
        }
        Ok(pixels)
    }
}

fn view_of(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// Writes an image as an 8-bit RGBA PNG.
pub fn write_png(path: &Path, image: &RgbaImage) -> Result<(), HeadlessError> {
    let error = |message: String| HeadlessError::Write {
        path: path.to_path_buf(),
        message,
    };
    let file = std::fs::File::create(path).map_err(|e| error(e.to_string()))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), image.width, image.height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| error(e.to_string()))?;
    writer
        .write_image_data(&image.pixels)
        .map_err(|e| error(e.to_string()))?;
    writer.finish().map_err(|e| error(e.to_string()))
}

/// Caption text size and line spacing, in pixels.
const CAPTION_FONT_SIZE: f64 = 14.0;
const CAPTION_LINE_HEIGHT: i32 = 18;
/// Gap between a pane's corner, its caption box and the text.
const CAPTION_PADDING: i32 = 6;

/// Writes each pane's caption lines in a translucent white box at the pane's top left, with the
/// embedded font of the plots (so the text does not depend on the machine's fonts).
pub fn draw_captions(
    image: &mut RgbaImage,
    captions: &[(Viewport, Vec<String>)],
) -> Result<(), HeadlessError> {
    use crate::edge::output::plots::{FONT_FAMILY, embedded_font_registered};
    use plotters::prelude::*;
    if !embedded_font_registered() {
        return Err(HeadlessError::Caption(
            "the embedded font is unreadable".into(),
        ));
    }
    let failed = |e: &dyn std::fmt::Display| HeadlessError::Caption(e.to_string());
    let mut rgb: Vec<u8> = image
        .pixels
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    {
        let root =
            BitMapBackend::with_buffer(&mut rgb, (image.width, image.height)).into_drawing_area();
        let style = TextStyle::from((FONT_FAMILY, CAPTION_FONT_SIZE).into_font()).color(&BLACK);
        for (viewport, lines) in captions {
            let mut widest = 0;
            for line in lines {
                let (width, _) = root
                    .estimate_text_size(line, &style)
                    .map_err(|e| failed(&e))?;
                widest = widest.max(width as i32);
            }
            let (x0, y0) = (
                viewport.x as i32 + CAPTION_PADDING,
                viewport.y as i32 + CAPTION_PADDING,
            );
            let box_corner = (
                x0 + widest + 2 * CAPTION_PADDING,
                y0 + lines.len() as i32 * CAPTION_LINE_HEIGHT + 2 * CAPTION_PADDING,
            );
            root.draw(&Rectangle::new(
                [(x0, y0), box_corner],
                RGBAColor(255, 255, 255, 0.75).filled(),
            ))
            .map_err(|e| failed(&e))?;
            for (k, line) in lines.iter().enumerate() {
                let at = (
                    x0 + CAPTION_PADDING,
                    y0 + CAPTION_PADDING + k as i32 * CAPTION_LINE_HEIGHT,
                );
                root.draw(&Text::new(line.as_str(), at, style.clone()))
                    .map_err(|e| failed(&e))?;
            }
        }
        root.present().map_err(|e| failed(&e))?;
    }
    for (pixel, rgb) in image.pixels.chunks_exact_mut(4).zip(rgb.chunks_exact(3)) {
        pixel[..3].copy_from_slice(rgb);
    }
    Ok(())
}

/// The panes of one frame: each lane side by side, seen from `view`. `geometries` and `lines`
/// hold one entry per lane and are refilled.
pub struct FramePanes {
    geometries: Vec<MeshGeometry>,
    lines: Vec<Vec<super::geometry::LineVertex>>,
}

impl FramePanes {
    pub fn new() -> FramePanes {
        FramePanes {
            geometries: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// Rebuilds the geometry of the lanes `lanes` of `replay` after its last step and returns
    /// the panes that split `area` among them, in that order. `None` before the first step.
    pub fn build(
        &mut self,
        replay: &Replay,
        lanes: &[usize],
        area: Viewport,
        view: ViewChoice,
        options: DrawOptions,
    ) -> Option<Vec<Pane<'_>>> {
        let hierarchy = &replay.scene().hierarchy;
        let n = lanes.len();
        self.geometries.resize_with(n, MeshGeometry::default);
        self.lines.resize_with(n, Vec::new);
        let mut specs = Vec::with_capacity(n);
        let areas = area.split_horizontally(n as u32);
        for (k, (&lane, pane_area)) in lanes.iter().zip(areas).enumerate() {
            let lane = replay.lane(lane)?;
            self.geometries[k].rebuild(hierarchy, lane.buffers, lane.mesh, lane.camera);
            let (viewport, view_projection) = pane_camera(hierarchy, &lane, pane_area, view);
            self.lines[k] = match view {
                ViewChoice::Flight => Vec::new(),
                ViewChoice::Overview => frustum_lines(lane.camera, terrain_diagonal(hierarchy)),
            };
            if options.roles {
                let degenerate = self.geometries[k].degenerate_lines();
                self.lines[k].extend_from_slice(degenerate);
            }
            specs.push((viewport, view_projection));
        }
        Some(
            specs
                .into_iter()
                .zip(self.geometries.iter().zip(&self.lines))
                .map(|((viewport, view_projection), (mesh, lines))| Pane {
                    viewport,
                    view_projection,
                    mesh,
                    lines,
                    options,
                })
                .collect(),
        )
    }
}

impl Default for FramePanes {
    fn default() -> FramePanes {
        FramePanes::new()
    }
}

/// The viewport (fitted to the camera's aspect) and matrix of a pane.
pub fn pane_camera(
    hierarchy: &Hierarchy,
    lane: &LaneFrame,
    area: Viewport,
    view: ViewChoice,
) -> (Viewport, glam::Mat4) {
    match view {
        ViewChoice::Flight => {
            let aspect = lane.camera.settings.aspect();
            (
                area.fitted(aspect),
                flight_view_projection(lane.camera, aspect),
            )
        }
        ViewChoice::Overview => (
            area,
            overview_view_projection(hierarchy.field().extent(), OVERVIEW_MARGIN, area.aspect()),
        ),
    }
}

fn terrain_diagonal(hierarchy: &Hierarchy) -> f64 {
    let (x, y) = hierarchy.field().extent();
    x.hypot(y)
}

/// What `roamsim render` was asked for.
#[derive(Clone, Debug)]
pub struct RenderRequest {
    pub experiment: PathBuf,
    /// Frames to write (any order; each is written once).
    pub frames: Vec<u64>,
    pub out_dir: PathBuf,
    /// Entry labels or algorithm names, drawn side by side; empty: the experiment's first entry.
    pub algorithms: Vec<String>,
    pub view: ViewChoice,
    pub wireframe: bool,
    /// Pixels; by default the experiment's window size times the number of panes across.
    pub size: Option<(u32, u32)>,
    /// Write each pane's statistics into its top left corner.
    pub captions: bool,
    /// Tell triangle roles apart (skirts, stitches, degenerate triangles); see
    /// [`DrawOptions::roles`].
    pub roles: bool,
}

/// Why `roamsim render` wrote nothing more.
#[derive(Debug, thiserror::Error)]
pub enum RenderFailure {
    #[error("{0}")]
    Experiment(#[from] ExperimentError),
    #[error("{0}")]
    UnknownAlgorithm(#[from] UnknownAlgorithm),
    #[error("frame {frame} is past the flight's last frame {last}")]
    FramePastEnd { frame: u64, last: u64 },
    #[error("{0}")]
    Mesh(#[from] RunError),
    #[error("{0}")]
    Graphics(#[from] HeadlessError),
    #[error("{path}: cannot create the output folder: {source}")]
    OutDir {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// One written frame.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    pub path: PathBuf,
    /// One caption per pane (see [`LaneFrame::caption`]).
    pub captions: Vec<String>,
}

/// Replays the experiment and writes `frame-NNNNNN.png` for every requested frame; returns the
/// files in frame order with each frame's statistics.
pub fn render_experiment(request: &RenderRequest) -> Result<Vec<RenderedFrame>, RenderFailure> {
    let scene = Scene::load(&request.experiment)?;
    let entries = if request.algorithms.is_empty() {
        vec![0]
    } else {
        request
            .algorithms
            .iter()
            .map(|wanted| scene.entry_index(wanted))
            .collect::<Result<Vec<_>, _>>()?
    };
    let mut frames = request.frames.clone();
    frames.sort_unstable();
    frames.dedup();
    let last = scene.n_frames().saturating_sub(1);
    if let Some(&frame) = frames.iter().find(|&&f| f > last) {
        return Err(RenderFailure::FramePastEnd { frame, last });
    }
    std::fs::create_dir_all(&request.out_dir).map_err(|source| RenderFailure::OutDir {
        path: request.out_dir.clone(),
        source,
    })?;
    let view_settings = scene.experiment.view;
    let (width, height) = request.size.unwrap_or((
        view_settings.width_px * entries.len() as u32,
        view_settings.height_px,
    ));
    let offscreen = Offscreen::new(width, height)?;
    let options = DrawOptions {
        wireframe: request.wireframe,
        tint_culled: request.view == ViewChoice::Overview,
        roles: request.roles,
    };
    let mut replay = Replay::new(&scene, &entries);
    let all_lanes: Vec<usize> = (0..entries.len()).collect();
    let mut panes = FramePanes::new();
    let mut written = Vec::with_capacity(frames.len());
    for frame in frames {
        replay.run_to(frame)?;
        let caption_lines: Vec<Vec<String>> = (0..replay.n_lanes())
            .filter_map(|k| replay.lane(k).map(|lane| lane.caption_lines()))
            .collect();
        let Some(frame_panes) = panes.build(
            &replay,
            &all_lanes,
            offscreen.viewport(),
            request.view,
            options,
        ) else {
            continue;
        };
        let mut image = offscreen.render_colour(&frame_panes)?;
        if request.captions {
            let boxes: Vec<(Viewport, Vec<String>)> = frame_panes
                .iter()
                .map(|pane| pane.viewport)
                .zip(caption_lines.iter().cloned())
                .collect();
            draw_captions(&mut image, &boxes)?;
        }
        let captions = caption_lines
            .iter()
            .map(|lines| lines.join(" · "))
            .collect();
        let path = request.out_dir.join(format!("frame-{frame:06}.png"));
        write_png(&path, &image)?;
        written.push(RenderedFrame { path, captions });
    }
    Ok(written)
}
