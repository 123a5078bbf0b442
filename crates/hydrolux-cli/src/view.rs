//! `hydrolux view`: a window with a fly camera and an egui panel that edits
//! every scene parameter live (generated from the scene's TOML table, so new
//! parameters appear without UI code). winit 0.30 + egui 0.37.
//!
//! Keys: W A S D fly, Q/E down/up, Shift faster, right mouse drag (or arrow
//! keys) to look, Space pause, [ and ] time scale, V next debug view,
//! P screenshot, Esc quit.

use crate::SceneArgs;
use anyhow::{Context, Result};
use clap::Args;
use hydrolux::core::camera::Camera;
use hydrolux::core::scene::{Choice, DebugView, GodRayMethod, Scene};
use hydrolux::{FrameInput, GpuContext, Renderer, wgpu};
use hydrolux_ui::camera::Motion;
use hydrolux_ui::{FlyCamera, Playback, Pointer, SceneEditor, header_ui};
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub size: crate::SizeArgs,
    /// Quit after this many frames, writing a screenshot first (for scripted checks).
    #[arg(long)]
    pub frames: Option<u64>,
}

struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    renderer: Renderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
}

struct Viewer {
    args: ViewArgs,
    scene: Scene,
    editor: SceneEditor,
    gfx: Option<Gfx>,
    camera: FlyCamera,
    keys: std::collections::HashSet<KeyCode>,
    looking: bool,
    last_cursor: Option<(f64, f64)>,
    /// The left button on the water or a body.
    pointer: Pointer,
    cursor: (f64, f64),
    clock: Playback,
    last_frame: Instant,
    frames: u64,
    screenshot_requested: bool,
    status: String,
    fatal: Option<anyhow::Error>,
}

impl Viewer {
    fn init(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let attrs = Window::default_attributes()
            .with_title(format!("Hydrolux — {}", self.args.scene.scene))
            .with_inner_size(winit::dpi::PhysicalSize::new(
                self.args.size.width,
                self.args.size.height,
            ));
        let window = Arc::new(event_loop.create_window(attrs).context("cannot open a window")?);
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .context("cannot create a drawing surface for the window")?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            compatible_surface: Some(&surface),
            force_fallback_adapter: false,
            apply_limit_buckets: false,
        }))
        .map_err(|_| match hydrolux::context::backend_from_env() {
            Ok(Some(b)) => hydrolux::ContextError::NoAdapterForBackend(b),
            Ok(None) => hydrolux::ContextError::NoAdapter,
            Err(bad) => bad,
        })?;
        let ctx = GpuContext::from_adapter(instance, adapter)?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&ctx.adapter);
        let format = caps.formats.iter().copied().find(|f| f.is_srgb()).unwrap_or(caps.formats[0]);
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&ctx.device, &config);
        let renderer = Renderer::new(&ctx.device, &ctx.queue, format, &self.scene)?;
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        let egui_renderer =
            egui_wgpu::Renderer::new(&ctx.device, format, egui_wgpu::RendererOptions::default());
        self.gfx = Some(Gfx {
            window,
            surface,
            config,
            ctx,
            renderer,
            egui_ctx,
            egui_state,
            egui_renderer,
        });
        self.last_frame = Instant::now();
        Ok(())
    }

    fn apply_table(&mut self) {
        match self.editor.scene() {
            Ok(s) => {
                if let Some(g) = &mut self.gfx
                    && let Err(e) = g.renderer.set_scene(&s)
                {
                    self.editor.error = Some(e.to_string());
                    return;
                }
                self.scene = s;
                self.editor.error = None;
            }
            Err(e) => self.editor.error = Some(e),
        }
    }

    /// Step `section.key` to the next of `names` (V: the debug view, G: the
    /// god-ray method), and apply it.
    fn cycle_option(&mut self, section: &str, key: &str, names: &[String]) {
        let next = self.editor.cycle(section, key, names);
        self.status = format!("{section}.{key}: {next}");
        self.apply_table();
    }

    fn panel(&mut self, ui: &mut egui::Ui) {
        let actions = header_ui(ui, &mut self.clock, "screenshot (P)");
        if actions.step {
            self.clock.step();
        }
        if actions.restart {
            self.clock.restart();
        }
        if actions.reset_camera {
            self.camera = FlyCamera::from_scene(&self.scene.camera());
        }
        self.screenshot_requested |= actions.screenshot;
        if !self.status.is_empty() {
            ui.label(&self.status);
        }
        let mut changed = self.editor.choices_ui(ui);
        ui.separator();
        changed |= self.editor.sections_ui(ui);
        if changed {
            self.apply_table();
        }
    }

    fn update_camera(&mut self, dt: f32) {
        let k = |c| if self.keys.contains(&c) { 1.0 } else { 0.0 };
        let motion = Motion {
            forward: k(KeyCode::KeyW) - k(KeyCode::KeyS),
            right: k(KeyCode::KeyD) - k(KeyCode::KeyA),
            up: k(KeyCode::KeyE) - k(KeyCode::KeyQ),
            turn_right: k(KeyCode::ArrowRight) - k(KeyCode::ArrowLeft),
            turn_up: k(KeyCode::ArrowUp) - k(KeyCode::ArrowDown),
            fast: self.keys.contains(&KeyCode::ShiftLeft),
        };
        self.camera.fly(motion, dt);
    }

    /// The cursor in normalised device coordinates, and the view's aspect.
    fn cursor_ndc(&self) -> ([f32; 2], f32) {
        let Some(g) = &self.gfx else { return ([0.0, 0.0], 1.0) };
        let (w, h) = (g.config.width.max(1) as f64, g.config.height.max(1) as f64);
        let ndc = [(2.0 * self.cursor.0 / w - 1.0) as f32, (1.0 - 2.0 * self.cursor.1 / h) as f32];
        (ndc, (w / h) as f32)
    }

    fn redraw(&mut self) -> Result<()> {
        let now = Instant::now();
        let real_dt = (now - self.last_frame).as_secs_f32();
        self.last_frame = now;
        self.clock.frame_ms = if self.clock.frame_ms == 0.0 {
            f64::from(real_dt) * 1000.0
        } else {
            0.9 * self.clock.frame_ms + 0.1 * f64::from(real_dt) * 1000.0
        };
        // Slow frames (software rendering, a stall) must not make the camera jump.
        let dt = real_dt.min(0.1);
        self.update_camera(dt);
        if !self.clock.paused {
            self.clock.sim_time += dt as f64 * self.clock.time_scale;
        }
        let Some(mut g) = self.gfx.take() else { return Ok(()) };
        let result = self.draw(&mut g);
        self.gfx = Some(g);
        result
    }

    fn draw(&mut self, g: &mut Gfx) -> Result<()> {
        let size = g.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised: nothing to draw
        }
        let frame = match g.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated => {
                g.surface.configure(&g.ctx.device, &g.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                // The surface itself is gone: make a new one for the same window.
                g.surface = g
                    .ctx
                    .instance
                    .create_surface(g.window.clone())
                    .context("cannot recreate the window surface")?;
                g.surface.configure(&g.ctx.device, &g.config);
                return Ok(());
            }
            _ => return Ok(()), // timeout / occluded / validation: try next frame
        };
        let view = frame.texture.create_view(&Default::default());
        let raw = g.egui_state.take_egui_input(&g.window);
        let egui_ctx = g.egui_ctx.clone();
        let mut out = egui_ctx.run_ui(raw, |ui| {
            egui::Panel::left("scene").default_size(300.0).show(ui, |ui| self.panel(ui));
        });
        g.egui_state.handle_platform_output(&g.window, out.platform_output);
        // The panel edits `self.scene` while the graphics are borrowed for
        // this frame; hand the edit to the renderer now. A scene it cannot
        // build (a missing mesh) stays an error and the old scene renders.
        if g.renderer.scene() != &self.scene
            && let Err(e) = g.renderer.set_scene(&self.scene)
        {
            self.editor.error = Some(e.to_string());
            self.scene = g.renderer.scene().clone();
        }
        let jobs = g.egui_ctx.tessellate(out.shapes, out.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [g.config.width, g.config.height],
            pixels_per_point: out.pixels_per_point,
        };
        for (id, deltas) in &out.textures_delta.set {
            for delta in deltas {
                g.egui_renderer.update_texture(&g.ctx.device, &g.ctx.queue, *id, delta);
            }
        }
        let mut encoder = g.ctx.device.create_command_encoder(&Default::default());
        let camera = self.camera.camera();
        g.renderer.render(
            &mut encoder,
            &FrameInput {
                target: &view,
                size: (g.config.width, g.config.height),
                camera,
                time: self.clock.sim_time,
            },
        );
        g.egui_renderer.update_buffers(&g.ctx.device, &g.ctx.queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                ..Default::default()
            });
            g.egui_renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        g.ctx.queue.submit([encoder.finish()]);
        if let Some(e) = g.ctx.take_error() {
            anyhow::bail!("GPU error while drawing the viewer's frame: {e}");
        }
        g.ctx.queue.present(frame);
        for id in &out.textures_delta.free {
            g.egui_renderer.free_texture(id);
        }
        // Every delta above was applied; epaint insists on being told.
        out.textures_delta.clear();
        self.frames += 1;
        let last = self.args.frames.is_some_and(|n| self.frames >= n);
        if self.screenshot_requested || last {
            self.screenshot_requested = false;
            self.status =
                self.screenshot(g, camera).unwrap_or_else(|e| format!("screenshot failed: {e:#}"));
            eprintln!("{}", self.status);
        }
        Ok(())
    }

    /// Render the current view (without the panel) at window size to a PNG.
    fn screenshot(&mut self, g: &mut Gfx, camera: Camera) -> Result<String> {
        let (w, h) = (g.config.width, g.config.height);
        let mut r =
            Renderer::new(&g.ctx.device, &g.ctx.queue, hydrolux::headless::FORMAT, &self.scene)?;
        let target = hydrolux::headless::HeadlessTarget::new(&g.ctx.device, (w, h));
        let px = target.render(&mut r, camera, self.clock.sim_time)?;
        let name = (0..)
            .map(|i| format!("hydrolux-screenshot-{i:03}.png"))
            .find(|n| !std::path::Path::new(n).exists())
            .unwrap_or_default();
        crate::output::write_png(std::path::Path::new(&name), w, h, &px)?;
        Ok(format!("wrote {name}"))
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_none()
            && let Err(e) = self.init(event_loop)
        {
            self.fatal = Some(e);
            event_loop.exit();
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(g) = &mut self.gfx else { return };
        let consumed = g.egui_state.on_window_event(&g.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) if size.width > 0 && size.height > 0 => {
                g.config.width = size.width;
                g.config.height = size.height;
                g.surface.configure(&g.ctx.device, &g.config);
            }
            WindowEvent::KeyboardInput { event, .. }
                if !consumed || event.state == ElementState::Released =>
            {
                if let PhysicalKey::Code(code) = event.physical_key {
                    if event.state == ElementState::Pressed {
                        self.keys.insert(code);
                        match code {
                            KeyCode::Escape => event_loop.exit(),
                            KeyCode::Space => self.clock.paused = !self.clock.paused,
                            KeyCode::BracketLeft => {
                                self.clock.time_scale =
                                    (self.clock.time_scale * 0.5).max(1.0 / 64.0)
                            }
                            KeyCode::BracketRight => {
                                self.clock.time_scale = (self.clock.time_scale * 2.0).min(64.0)
                            }
                            KeyCode::KeyP => self.screenshot_requested = true,
                            KeyCode::KeyN => self.clock.step(),
                            KeyCode::KeyR => self.clock.restart(),
                            KeyCode::KeyB => {
                                let (ndc, aspect) = self.cursor_ndc();
                                let camera = self.camera.camera();
                                if let Some(g) = &mut self.gfx {
                                    hydrolux_ui::pointer::drop_ball(
                                        &mut g.renderer,
                                        &camera,
                                        ndc,
                                        aspect,
                                    );
                                }
                            }
                            KeyCode::KeyV => {
                                self.cycle_option("render", "view", &DebugView::names())
                            }
                            KeyCode::KeyG => {
                                self.cycle_option("godrays", "method", &GodRayMethod::names())
                            }
                            _ => {}
                        }
                    } else {
                        self.keys.remove(&code);
                    }
                }
            }
            WindowEvent::MouseInput { button: MouseButton::Right, state, .. } => {
                self.looking = state == ElementState::Pressed && !consumed;
                self.last_cursor = None;
            }
            WindowEvent::MouseInput { button: MouseButton::Left, state, .. } => {
                if state == ElementState::Pressed && !consumed {
                    let (ndc, aspect) = self.cursor_ndc();
                    let camera = self.camera.camera();
                    if let Some(g) = &mut self.gfx {
                        self.pointer.press(&mut g.renderer, &camera, ndc, aspect);
                    }
                } else if state == ElementState::Released {
                    self.pointer.release();
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if self.looking {
                    if let Some((x, y)) = self.last_cursor {
                        self.camera.drag((position.x - x) as f32, (position.y - y) as f32);
                    }
                    self.last_cursor = Some((position.x, position.y));
                } else if self.pointer.grabbing() {
                    let (ndc, aspect) = self.cursor_ndc();
                    let camera = self.camera.camera();
                    if let Some(g) = &mut self.gfx {
                        self.pointer.drag(&mut g.renderer, &camera, ndc, aspect);
                    }
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    self.fatal = Some(e);
                    event_loop.exit();
                }
                if self.args.frames.is_some_and(|n| self.frames >= n) {
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }
}

pub fn run(args: ViewArgs) -> Result<()> {
    args.size.check()?;
    hydrolux::context::backend_from_env()?;
    let scene = args.scene.load()?;
    // winit's own message carries a source path; say it plainly instead.
    let event_loop = EventLoop::new().map_err(|e| {
        let text = e.to_string();
        let why = match text.rsplit_once(": ") {
            Some((_, reason)) if text.contains(".rs:") => reason.trim_end_matches('.').to_string(),
            _ => text,
        };
        anyhow::anyhow!(
            "cannot open a window: {why} (set DISPLAY or WAYLAND_DISPLAY to a running display, or render headless with `hydrolux render`)"
        )
    })?;
    let mut viewer = Viewer {
        editor: SceneEditor::new(&scene),
        camera: FlyCamera::from_scene(&scene.camera()),
        scene,
        args,
        gfx: None,
        keys: Default::default(),
        looking: false,
        last_cursor: None,
        pointer: Pointer::default(),
        cursor: (0.0, 0.0),
        clock: Playback { sim_time: 0.0, time_scale: 1.0, paused: false, frame_ms: 0.0 },
        last_frame: Instant::now(),
        frames: 0,
        screenshot_requested: false,
        status: String::new(),
        fatal: None,
    };
    event_loop.run_app(&mut viewer).context("window event loop failed")?;
    match viewer.fatal {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
