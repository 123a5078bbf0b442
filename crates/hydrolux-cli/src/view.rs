//! `hydrolux view`: a window with a fly camera and an egui panel that edits
//! every scene parameter live (generated from the scene's TOML table, so new
//! parameters appear without UI code). winit 0.30 + egui 0.37.
//!
//! Keys: W A S D fly, Q/E down/up, Shift faster, right mouse drag (or arrow
//! keys) to look, O to orbit instead (the drag swings the camera around the
//! point it looks at), the wheel to move along the view, Space pause, [ and ] time scale, V next debug view,
//! P screenshot, Tab fold or unfold the panel, Esc quit. The water is drawn
//! beside the panel, not under it: into an image the size of the rest of
//! the window, copied in next to the panel.

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
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
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

/// How long a key's or a screenshot's status line stays in the panel (s).
const STATUS_SECONDS: f32 = 4.0;

struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    renderer: Renderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    /// The image the water is drawn into (the window beside the panel),
    /// when the window's surface takes copies; else it is drawn on the
    /// surface, under the panel.
    image: Option<(wgpu::Texture, (u32, u32))>,
    can_copy: bool,
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
    status_at: Instant,
    fatal: Option<anyhow::Error>,
    /// The last frame's submission, waited for before the next is submitted.
    in_flight: Option<wgpu::SubmissionIndex>,
    /// The panel's width in pixels (0 folded): the view starts right of it.
    panel_px: u32,
    panel_open: bool,
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
        let mut descriptor = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            event_loop.owned_display_handle(),
        ));
        descriptor.flags = hydrolux::context::instance_flags(descriptor.flags);
        let instance = wgpu::Instance::new(descriptor);
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
        let can_copy = caps.usages.contains(wgpu::TextureUsages::COPY_DST);
        let config = wgpu::SurfaceConfiguration {
            usage: if can_copy {
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST
            } else {
                wgpu::TextureUsages::RENDER_ATTACHMENT
            },
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 1,
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
            image: None,
            can_copy,
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
                self.editor.accepted(&s);
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
        self.say(format!("{section}.{key}: {next}"));
        self.apply_table();
    }

    fn panel(&mut self, ui: &mut egui::Ui) {
        let actions = header_ui(ui, &mut self.clock, &mut self.camera, "screenshot (P)");
        if actions.step {
            self.clock.step();
        }
        if actions.restart {
            self.clock.restart();
        }
        if actions.reset_camera {
            let orbit = self.camera.orbit;
            self.camera = FlyCamera::from_scene(&self.scene.camera());
            self.camera.orbit = orbit;
        }
        self.screenshot_requested |= actions.screenshot;
        // What a key or a screenshot just did, for a few seconds (a line
        // that stayed said "render.view: reflection" long after the view
        // was switched back in the panel).
        if !self.status.is_empty() && self.status_at.elapsed().as_secs_f32() < STATUS_SECONDS {
            ui.label(&self.status);
        }
        let mut changed = self.editor.choices_ui(ui);
        if let Some(hint) = self.editor.hint(&self.scene) {
            ui.colored_label(egui::Color32::from_rgb(240, 200, 110), hint);
        }
        ui.label("Tab folds this panel");
        ui.separator();
        changed |= self.editor.sections_ui(ui);
        if changed {
            self.status.clear();
            self.apply_table();
        }
    }

    /// Show `text` in the panel for [`STATUS_SECONDS`].
    fn say(&mut self, text: String) {
        self.status = text;
        self.status_at = Instant::now();
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

    /// Where the water is drawn in the window: x offset and size (px).
    fn view_rect(&self, g: &Gfx) -> (u32, (u32, u32)) {
        let left =
            if g.can_copy { self.panel_px.min(g.config.width.saturating_sub(16)) } else { 0 };
        (left, ((g.config.width - left).max(1), g.config.height.max(1)))
    }

    /// The cursor in normalised device coordinates of the view, and the
    /// view's aspect.
    fn cursor_ndc(&self) -> ([f32; 2], f32) {
        let Some(g) = &self.gfx else { return ([0.0, 0.0], 1.0) };
        let (left, (w, h)) = self.view_rect(g);
        let (w, h) = (w as f64, h as f64);
        let x = self.cursor.0 - left as f64;
        let ndc = [(2.0 * x / w - 1.0) as f32, (1.0 - 2.0 * self.cursor.1 / h) as f32];
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
        let mut panel_right = 0.0;
        let mut out = egui_ctx.run_ui(raw, |ui| {
            if self.panel_open {
                let shown =
                    egui::Panel::left("scene").default_size(300.0).show(ui, |ui| self.panel(ui));
                panel_right = shown.response.rect.max.x;
            }
        });
        self.panel_px = (panel_right * out.pixels_per_point).ceil() as u32;
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
        let (left, size) = self.view_rect(g);
        if g.can_copy {
            if g.image.as_ref().map(|i| i.1) != Some(size) {
                let texture = g.ctx.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("viewer image"),
                    size: wgpu::Extent3d {
                        width: size.0,
                        height: size.1,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: g.config.format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                });
                g.image = Some((texture, size));
            }
            let image = &g.image.as_ref().expect("made above").0;
            let image_view = image.create_view(&Default::default());
            let time = self.clock.sim_time;
            let input = FrameInput { target: &image_view, size, camera, time };
            g.renderer.render(&mut encoder, &input);
            encoder.copy_texture_to_texture(
                image.as_image_copy(),
                wgpu::TexelCopyTextureInfo {
                    texture: &frame.texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: left, y: 0, z: 0 },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
            );
        } else {
            let time = self.clock.sim_time;
            g.renderer.render(&mut encoder, &FrameInput { target: &view, size, camera, time });
        }
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
        let submitted = g.ctx.queue.submit([encoder.finish()]);
        if let Some(e) = g.ctx.take_error() {
            anyhow::bail!("GPU error while drawing the viewer's frame: {e}");
        }
        // At most one frame in flight: on a slow adapter queued frames made
        // every key and drag show seconds late. The next frame is recorded
        // while this one runs; it waits for this one before it is drawn.
        if let Some(previous) = self.in_flight.replace(submitted) {
            let _ = g
                .ctx
                .device
                .poll(wgpu::PollType::Wait { submission_index: Some(previous), timeout: None });
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
            let said =
                self.screenshot(g, camera).unwrap_or_else(|e| format!("screenshot failed: {e:#}"));
            eprintln!("{said}");
            self.say(said);
        }
        Ok(())
    }

    /// The current view (without the panel) to a PNG: the image on screen
    /// read back, or where the window cannot take copies, the view rendered
    /// again at its size by a new renderer (which steps its simulations
    /// from t = 0 to now).
    fn screenshot(&mut self, g: &mut Gfx, camera: Camera) -> Result<String> {
        let (_, (w, h)) = self.view_rect(g);
        let px = match &g.image {
            Some((image, size)) if *size == (w, h) => {
                hydrolux::headless::read_rgba8(&g.ctx.device, &g.ctx.queue, image)
            }
            _ => {
                let mut r = Renderer::new(
                    &g.ctx.device,
                    &g.ctx.queue,
                    hydrolux::headless::FORMAT,
                    &self.scene,
                )?;
                let target = hydrolux::headless::HeadlessTarget::new(&g.ctx.device, (w, h));
                target.render(&mut r, camera, self.clock.sim_time)?
            }
        };
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
        let mut consumed = g.egui_state.on_window_event(&g.window, &event).consumed;
        if let WindowEvent::KeyboardInput { .. } = &event {
            // Keys are the panel's only while a text field has the focus
            // (egui keeps a clicked slider, combo box or button focused,
            // and took every key: P, Space and the first Esc did nothing
            // until the view was clicked). Esc in a field leaves the field.
            consumed = g.egui_ctx.text_edit_focused();
        }
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
                            KeyCode::Tab => self.panel_open = !self.panel_open,
                            KeyCode::KeyN => self.clock.step(),
                            KeyCode::KeyO => {
                                self.camera.orbit = !self.camera.orbit;
                                let what = if self.camera.orbit {
                                    format!(
                                        "orbiting the point {:.1} m ahead (O: fly)",
                                        self.camera.distance
                                    )
                                } else {
                                    "flying (O: orbit)".to_string()
                                };
                                self.say(what);
                            }
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
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.camera.dolly(lines);
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
    let clock = Playback::at(scene.start_time, false);
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
        clock,
        last_frame: Instant::now(),
        frames: 0,
        screenshot_requested: false,
        status: String::new(),
        status_at: Instant::now(),
        fatal: None,
        in_flight: None,
        panel_px: 0,
        panel_open: true,
    };
    event_loop.run_app(&mut viewer).context("window event loop failed")?;
    match viewer.fatal {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
