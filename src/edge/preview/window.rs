//! `roamsim preview`: the flight replayed in a winit window, one or two algorithms side by side
//! (README, "Seeing the meshes: `preview` and `render`", lists the same keys). It computes
//! nothing a run reports and draws nothing itself (see the last paragraph).
//!
//! Every algorithm entry of the experiment runs in lockstep (so switching a pane's algorithm
//! shows that algorithm at the same frame at once); the panes show one or two of them. The
//! statistics of the shown panes are in the window title (no text is drawn in the window).
//!
//! Keys: Space pause/play · → or N one frame (paused) · A / B next algorithm in the left /
//! right pane · S split screen on/off · W wireframe on/off · C culling view (the overview from
//! above with the frustum and the culled triangles darkened) on/off · R roles (skirts cyan,
//! stitches violet, degenerate triangles as magenta lines) on/off · Esc or Q quit.
//!
//! This file is only the event loop and the swap chain; the drawing is [`super::renderer`]'s.

use super::geometry::{ViewChoice, Viewport};
use super::headless::FramePanes;
use super::renderer::{DEPTH_FORMAT, DrawOptions, Renderer};
use super::replay::{Replay, Scene, UnknownAlgorithm};
use crate::edge::experiment::ExperimentError;
use crate::sim::run::RunError;
use std::path::PathBuf;
use std::sync::Arc;
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// What `roamsim preview` was asked for.
#[derive(Clone, Debug)]
pub struct PreviewRequest {
    pub experiment: PathBuf,
    /// Entry labels or algorithm names for the left and (if two) right pane; empty: the first
    /// entry, and the second (split screen) when the experiment has two or more.
    pub algorithms: Vec<String>,
    /// Close the window by itself after drawing this many frames (smoke tests, screenshots).
    pub quit_after_frames: Option<u64>,
}

/// Why the preview stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum PreviewFailure {
    #[error("{0}")]
    Experiment(#[from] ExperimentError),
    #[error("{0}")]
    UnknownAlgorithm(#[from] UnknownAlgorithm),
    #[error("{0}")]
    Mesh(#[from] RunError),
    #[error("window: {0}")]
    Window(String),
    #[error("graphics: {0}")]
    Graphics(String),
}

/// What a preview session did, for the command to report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PreviewSummary {
    /// Frames presented to the window.
    pub frames_drawn: u64,
    /// The last flight frame the replay ran.
    pub last_frame: u64,
    /// The adapter drawn on, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    pub adapter: String,
}

/// Opens the window and runs until it is closed.
pub fn run_preview(request: &PreviewRequest) -> Result<PreviewSummary, PreviewFailure> {
    let scene = Scene::load(&request.experiment)?;
    let n_entries = scene.experiment.algorithms.len();
    let shown = if request.algorithms.is_empty() {
        (0..n_entries.min(2)).collect()
    } else {
        request
            .algorithms
            .iter()
            .take(2)
            .map(|wanted| scene.entry_index(wanted))
            .collect::<Result<Vec<_>, _>>()?
    };
    let all_entries: Vec<usize> = (0..n_entries).collect();
    let event_loop = EventLoop::new().map_err(|e| PreviewFailure::Window(e.to_string()))?;
    let mut app = App {
        replay: Replay::new(&scene, &all_entries),
        shown,
        split: true,
        playing: true,
        view: ViewChoice::Flight,
        wireframe: true,
        roles: false,
        quit_after_frames: request.quit_after_frames,
        frames_drawn: 0,
        panes: FramePanes::new(),
        surface: None,
        adapter: String::new(),
        failure: None,
    };
    app.replay.step()?;
    event_loop
        .run_app(&mut app)
        .map_err(|e| PreviewFailure::Window(e.to_string()))?;
    match app.failure {
        Some(failure) => Err(failure),
        None => Ok(PreviewSummary {
            frames_drawn: app.frames_drawn,
            last_frame: app.replay.next_frame().saturating_sub(1),
            adapter: app.adapter,
        }),
    }
}

struct App<'s> {
    replay: Replay<'s>,
    /// Lanes shown, left to right (one or two).
    shown: Vec<usize>,
    split: bool,
    playing: bool,
    view: ViewChoice,
    wireframe: bool,
    roles: bool,
    quit_after_frames: Option<u64>,
    frames_drawn: u64,
    panes: FramePanes,
    surface: Option<SurfaceState>,
    /// The adapter's name and backend, once the window is open.
    adapter: String,
    failure: Option<PreviewFailure>,
}

/// The window and what draws into it.
struct SurfaceState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    depth: wgpu::TextureView,
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, failure: PreviewFailure) {
        self.failure = Some(failure);
        event_loop.exit();
    }

    /// The lanes the panes show now.
    fn visible_lanes(&self) -> Vec<usize> {
        if self.split {
            self.shown.clone()
        } else {
            self.shown[..1].to_vec()
        }
    }

    fn step(&mut self, event_loop: &ActiveEventLoop) {
        match self.replay.step() {
            Ok(true) => {}
            Ok(false) => self.playing = false,
            Err(error) => self.fail(event_loop, error.into()),
        }
    }

    fn on_key(&mut self, event_loop: &ActiveEventLoop, key: &Key) {
        let n_entries = self.replay.n_lanes();
        match key.as_ref() {
            Key::Named(NamedKey::Space) => self.playing = !self.playing,
            Key::Named(NamedKey::ArrowRight) | Key::Character("n") => {
                self.playing = false;
                self.step(event_loop);
            }
            Key::Character("a") => self.shown[0] = (self.shown[0] + 1) % n_entries,
            Key::Character("b") => {
                if self.shown.len() < 2 {
                    self.shown.push(self.shown[0]);
                }
                self.shown[1] = (self.shown[1] + 1) % n_entries;
                self.split = true;
            }
            Key::Character("s") => self.split = !self.split && self.shown.len() > 1,
            Key::Character("w") => self.wireframe = !self.wireframe,
            Key::Character("r") => self.roles = !self.roles,
            Key::Character("c") => {
                self.view = match self.view {
                    ViewChoice::Flight => ViewChoice::Overview,
                    ViewChoice::Overview => ViewChoice::Flight,
                }
            }
            Key::Named(NamedKey::Escape) | Key::Character("q") => event_loop.exit(),
            _ => return,
        }
        if let Some(state) = &self.surface {
            state.window.request_redraw();
        }
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<SurfaceState, PreviewFailure> {
        let graphics = |e: &dyn std::fmt::Display| PreviewFailure::Graphics(e.to_string());
        let window = event_loop
            .create_window(
                Window::default_attributes()
                    .with_title("roamsim preview")
                    .with_inner_size(LogicalSize::new(1200.0, 640.0)),
            )
            .map_err(|e| PreviewFailure::Window(e.to_string()))?;
        let window = Arc::new(window);
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| graphics(&e))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::default(),
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            apply_limit_buckets: false,
        }))
        .map_err(|e| graphics(&e))?;
        let info = adapter.get_info();
        self.adapter = format!("{} ({:?})", info.name, info.backend);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("roamsim preview"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| graphics(&e))?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| PreviewFailure::Graphics("the surface fits no adapter".into()))?;
        let capabilities = surface.get_capabilities(&adapter);
        if let Some(&srgb) = capabilities.formats.iter().find(|f| f.is_srgb()) {
            config.format = srgb;
        }
        surface.configure(&device, &config);
        let depth = depth_view(&device, &config);
        let renderer = Renderer::new(device, queue, config.format);
        Ok(SurfaceState {
            window,
            surface,
            config,
            renderer,
            depth,
        })
    }

    fn draw(&mut self, event_loop: &ActiveEventLoop) {
        let lanes = self.visible_lanes();
        let title: Vec<String> = lanes
            .iter()
            .filter_map(|&k| self.replay.lane(k).map(|lane| lane.caption()))
            .collect();
        let Some(state) = self.surface.as_mut() else {
            return;
        };
        state.window.set_title(&format!(
            "{}{}",
            title.join("  |  "),
            if self.playing { "" } else { "  [paused]" }
        ));
        let frame = match state.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame)
            | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                state
                    .surface
                    .configure(state.renderer.device(), &state.config);
                state.window.request_redraw();
                return;
            }
            _ => return,
        };
        let area = Viewport {
            x: 0,
            y: 0,
            width: state.config.width,
            height: state.config.height,
        };
        let options = DrawOptions {
            wireframe: self.wireframe,
            tint_culled: self.view == ViewChoice::Overview,
            roles: self.roles,
        };
        let Some(panes) = self
            .panes
            .build(&self.replay, &lanes, area, self.view, options)
        else {
            return;
        };
        let target = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder =
            state
                .renderer
                .device()
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("preview frame"),
                });
        state
            .renderer
            .draw_panes(&mut encoder, &target, &state.depth, &panes);
        state.renderer.queue().submit([encoder.finish()]);
        state.window.pre_present_notify();
        state.renderer.queue().present(frame);
        self.frames_drawn += 1;
        if self
            .quit_after_frames
            .is_some_and(|n| self.frames_drawn >= n)
        {
            event_loop.exit();
        }
    }
}

fn depth_view(device: &wgpu::Device, config: &wgpu::SurfaceConfiguration) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("window depth"),
            size: wgpu::Extent3d {
                width: config.width,
                height: config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.surface.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(state) => {
                state.window.request_redraw();
                self.surface = Some(state);
            }
            Err(failure) => self.fail(event_loop, failure),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(state) = self.surface.as_mut()
                    && size.width > 0
                    && size.height > 0
                {
                    state.config.width = size.width;
                    state.config.height = size.height;
                    state
                        .surface
                        .configure(state.renderer.device(), &state.config);
                    state.depth = depth_view(state.renderer.device(), &state.config);
                    state.window.request_redraw();
                }
            }
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        logical_key,
                        state: ElementState::Pressed,
                        ..
                    },
                ..
            } => self.on_key(event_loop, &logical_key),
            WindowEvent::RedrawRequested => self.draw(event_loop),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.playing {
            self.step(event_loop);
            event_loop.set_control_flow(ControlFlow::Poll);
            if let Some(state) = &self.surface {
                state.window.request_redraw();
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}
