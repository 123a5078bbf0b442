//! The page's app: the water rendered into a texture that egui shows, the
//! scene editor beside it, the camera under the mouse, touch and keys.

use eframe::egui_wgpu;
use hydrolux::core::scene::{BUILTIN_SCENES, Scene};
use hydrolux::wgpu;
use hydrolux::{FrameInput, Renderer};
use hydrolux_ui::camera::Motion;
use hydrolux_ui::{FlyCamera, Playback, SceneEditor, header_ui};
use std::sync::{Arc, Mutex};
use wasm_bindgen::JsValue;

/// What the URL asks for (see the crate doc).
#[derive(Clone, Debug)]
pub struct Options {
    pub scene: String,
    /// `set=section.key=value`, repeatable: as `--set` on the command line.
    pub sets: Vec<String>,
    /// Simulated time to open at (`time=`; the scene's `start_time` if absent).
    pub time: Option<f64>,
    pub paused: bool,
    pub panel: bool,
    pub size: Option<(u32, u32)>,
    /// After this many frames, read the image back and publish it as PNG
    /// bytes in `window.hydrolux.png` (the browser test: headless chromium
    /// cannot read back a WebGPU canvas).
    pub capture_after: Option<u64>,
}

impl Options {
    pub fn from_url(search: &str) -> Self {
        let params = web_sys::UrlSearchParams::new_with_str(search).ok();
        let get = |k: &str| params.as_ref().and_then(|p| p.get(k));
        let num =
            |k: &str| get(k).and_then(|v| v.parse::<u32>().ok()).filter(|v| (1..=8192).contains(v));
        Options {
            scene: get("scene").unwrap_or_else(|| "ocean".into()),
            sets: params
                .as_ref()
                .map(|p| p.get_all("set").iter().filter_map(|v| v.as_string()).collect())
                .unwrap_or_default(),
            time: get("time").and_then(|t| t.parse().ok()).filter(|t: &f64| t.is_finite()),
            paused: get("paused").as_deref() == Some("1"),
            panel: get("ui").as_deref() != Some("0"),
            size: num("width").zip(num("height")),
            capture_after: get("capture").and_then(|v| v.parse().ok()),
        }
    }
}

/// A dropped file's name and its bytes (or why they could not be read).
type DroppedScene = (String, Result<Vec<u8>, String>);

thread_local! {
    /// A scene asked for from JavaScript (`hydrolux_show`), taken by the next frame.
    static REQUESTED: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
    /// A file dropped onto the page, once read.
    static DROPPED: std::cell::RefCell<Option<DroppedScene>> = const { std::cell::RefCell::new(None) };
    /// A time scale asked for from JavaScript (`hydrolux_play`).
    static PLAY: std::cell::Cell<Option<f64>> = const { std::cell::Cell::new(None) };
}

/// Run the clock at `time_scale` × real time (unpausing it), as the
/// panel's play button and slider do; for scripts: the browser test runs
/// every scene for seconds of simulated time on a slow software adapter.
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn hydrolux_play(time_scale: f64) {
    PLAY.with(|p| p.set(Some(time_scale).filter(|s| s.is_finite() && *s >= 0.0)));
}

/// Show a built-in scene from its start (time, camera), as the scene picker
/// does; `window.hydrolux` then reports it, and with `capture=N` its image
/// N frames later. For scripts: the browser test shows every scene in one
/// page instead of loading the page once per scene.
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn hydrolux_show(scene: String) {
    REQUESTED.with(|r| *r.borrow_mut() = Some(scene));
}

/// Show a message in the page (`#status`) and in `window.hydrolux.error`.
pub fn report_error(message: &str) {
    web_sys::console::error_1(&JsValue::from_str(message));
    if let Some(el) =
        web_sys::window().and_then(|w| w.document()).and_then(|d| d.get_element_by_id("status"))
    {
        el.set_text_content(Some(message));
        el.set_class_name("error");
    }
    publish(&[("error", JsValue::from_str(message))]);
}

/// Set fields of `window.hydrolux` for scripts (the browser test).
fn publish(fields: &[(&str, JsValue)]) {
    let Some(window) = web_sys::window() else { return };
    let key = JsValue::from_str("hydrolux");
    let object = js_sys::Reflect::get(&window, &key)
        .ok()
        .filter(|v| v.is_object())
        .unwrap_or_else(|| js_sys::Object::new().into());
    for (k, v) in fields {
        let _ = js_sys::Reflect::set(&object, &JsValue::from_str(k), v);
    }
    let _ = js_sys::Reflect::set(&window, &key, &object);
}

/// The texture the water is rendered into, as egui knows it.
struct Target {
    texture: wgpu::Texture,
    /// Rendered into (sRGB: the tone map writes encoded colours).
    view: wgpu::TextureView,
    id: egui::TextureId,
    size: (u32, u32),
}

/// A screenshot on its way back from the GPU.
struct Readback {
    buffer: wgpu::Buffer,
    size: (u32, u32),
    padded_row: u32,
    ready: Arc<Mutex<Option<Result<(), String>>>>,
    /// A download for the person, or bytes for a script.
    publish: bool,
}

pub struct WebApp {
    gpu: egui_wgpu::RenderState,
    renderer: Result<Renderer, String>,
    scene: Scene,
    scene_name: String,
    editor: SceneEditor,
    camera: FlyCamera,
    target: Option<Target>,
    options: Options,
    clock: Playback,
    last_ms: Option<f64>,
    frames: u64,
    status: String,
    uncaught: Arc<Mutex<Option<String>>>,
    readback: Option<Readback>,
    /// The frame count when the current scene was first shown.
    shown_at: u64,
    /// A press on the water or a body (ripples, pulling).
    pointer: hydrolux_ui::Pointer,
}

impl WebApp {
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        options: Options,
    ) -> Result<Self, Box<dyn std::error::Error + Send + Sync>> {
        let gpu = cc.wgpu_render_state.clone().ok_or("eframe started without wgpu")?;
        let uncaught = Arc::new(Mutex::new(None));
        let sink = uncaught.clone();
        gpu.device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut slot) = sink.lock() {
                slot.get_or_insert_with(|| hydrolux::gpu_error_line(&e));
            }
        }));
        gpu.device.set_device_lost_callback(|reason, message| {
            report_error(&format!("the GPU device was lost ({reason:?}): {message}"));
        });
        let (scene_name, scene) = match Scene::load(&options.scene, &options.sets) {
            Ok(s) => (options.scene.clone(), s),
            Err(e) => {
                report_error(&format!("scene `{}`: {e}", options.scene));
                ("ocean".into(), Scene::load("ocean", &[]).map_err(|e| e.to_string())?)
            }
        };
        let info = gpu.adapter.get_info();
        let name = if info.name.is_empty() { "the browser's adapter" } else { info.name.as_str() };
        let adapter = format!("{name} ({:?})", info.backend);
        let renderer = Renderer::new(&gpu.device, &gpu.queue, TARGET_FORMAT, &scene)
            .map_err(|e| e.to_string());
        if let Err(e) = &renderer {
            report_error(&format!("Hydrolux cannot run on this adapter: {e}"));
        }
        publish(&[("adapter", JsValue::from_str(&adapter)), ("frames", JsValue::from_f64(0.0))]);
        Ok(WebApp {
            editor: SceneEditor::new(&scene),
            camera: FlyCamera::from_scene(&scene.camera()),
            clock: Playback::at(options.time.unwrap_or(scene.start_time), options.paused),
            gpu,
            renderer,
            scene,
            scene_name,
            target: None,
            options,
            last_ms: None,
            frames: 0,
            status: format!("adapter: {adapter}"),
            uncaught,
            readback: None,
            shown_at: 0,
            pointer: hydrolux_ui::Pointer::default(),
        })
    }

    /// Apply the editor's table (an edit, a key, a combo box).
    fn apply_editor(&mut self) {
        match self.editor.scene() {
            Ok(s) => {
                if let Ok(r) = &mut self.renderer
                    && let Err(e) = r.set_scene(&s)
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

    fn switch_scene(&mut self, name: &str) {
        self.show_scene(name, Scene::load(name, &self.options.sets));
    }

    /// A scene's TOML dropped onto the page (`name` its file's): opened as
    /// a built-in is, or its error said in the panel.
    fn open_dropped(&mut self, name: &str, bytes: &[u8]) {
        let scene = match std::str::from_utf8(bytes) {
            Ok(text) => Scene::from_toml(text, name, &self.options.sets).map_err(|e| e.to_string()),
            Err(_) => Err(format!("{name} is not text: a scene is a TOML file")),
        };
        self.show_scene(name, scene);
    }

    fn show_scene<E: std::fmt::Display>(&mut self, name: &str, scene: Result<Scene, E>) {
        match scene {
            Ok(s) => {
                self.editor = SceneEditor::new(&s);
                self.camera = FlyCamera::from_scene(&s.camera());
                self.scene_name = name.into();
                self.scene = s;
                self.clock.start = self.options.time.unwrap_or(self.scene.start_time);
                self.clock.sim_time = self.clock.start;
                self.shown_at = self.frames;
                if let Ok(r) = &mut self.renderer
                    && let Err(e) = r.set_scene(&self.scene)
                {
                    self.editor.error = Some(e.to_string());
                }
            }
            Err(e) => self.editor.error = Some(e.to_string()),
        }
    }

    /// The render target at `size` pixels, made or remade.
    fn target(&mut self, size: (u32, u32)) -> &Target {
        if self.target.as_ref().map(|t| t.size) != Some(size) {
            let device = &self.gpu.device;
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("hydrolux web image"),
                size: wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: TARGET_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[EGUI_FORMAT],
            });
            let view = texture.create_view(&Default::default());
            // What egui samples: the same bytes as plain unorm, because egui
            // works in gamma space on the canvas (an sRGB view would be
            // decoded to linear and shown too dark).
            let egui_view = texture.create_view(&wgpu::TextureViewDescriptor {
                format: Some(EGUI_FORMAT),
                ..Default::default()
            });
            let mut egui_renderer = self.gpu.renderer.write();
            let id = match &self.target {
                Some(old) => {
                    egui_renderer.update_egui_texture_from_wgpu_texture(
                        device,
                        &egui_view,
                        wgpu::FilterMode::Nearest,
                        old.id,
                    );
                    old.id
                }
                None => egui_renderer.register_native_texture(
                    device,
                    &egui_view,
                    wgpu::FilterMode::Nearest,
                ),
            };
            drop(egui_renderer);
            self.target = Some(Target { texture, view, id, size });
        }
        self.target.as_ref().expect("made above")
    }

    fn panel(&mut self, ui: &mut egui::Ui) {
        let actions = header_ui(ui, &mut self.clock, &mut self.camera, "screenshot");
        if actions.step {
            self.clock.step();
        }
        if actions.restart {
            self.clock.restart();
        }
        ui.label(&self.status);
        let mut pick = None;
        ui.horizontal(|ui| {
            ui.label("scene");
            egui::ComboBox::from_id_salt("scene").selected_text(&self.scene_name).show_ui(
                ui,
                |ui| {
                    for b in BUILTIN_SCENES {
                        if ui.selectable_label(self.scene_name == b.name, b.name).clicked() {
                            pick = Some(b.name);
                        }
                    }
                },
            );
        });
        if let Some(name) = pick {
            self.switch_scene(name);
        }
        if actions.reset_camera {
            let orbit = self.camera.orbit;
            self.camera = FlyCamera::from_scene(&self.scene.camera());
            self.camera.orbit = orbit;
        }
        if actions.screenshot && self.readback.is_none() {
            self.start_screenshot(false);
        }
        let mut changed = self.editor.choices_ui(ui);
        if let Some(hint) = self.editor.hint(&self.scene) {
            ui.colored_label(egui::Color32::from_rgb(240, 200, 110), hint);
        }
        ui.label(
            "drag: look, or orbit (O) (on the water: ripples; on the ball: pull it) · \
             B: drop the ball · wheel / pinch: move · W A S D Q E: fly (Shift: fast) · \
             drop a scene's .toml here to open it",
        );
        ui.separator();
        changed |= self.editor.sections_ui(ui);
        if changed {
            self.apply_editor();
        }
    }

    /// Keys fly the camera while egui is not taking them (a text field).
    fn fly(&mut self, ctx: &egui::Context, dt: f32) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        if ctx.input(|i| i.key_pressed(egui::Key::O)) {
            self.camera.orbit = !self.camera.orbit;
        }
        let m = ctx.input(|i| {
            let k = |key| if i.key_down(key) { 1.0 } else { 0.0 };
            use egui::Key;
            Motion {
                forward: k(Key::W) - k(Key::S),
                right: k(Key::D) - k(Key::A),
                up: k(Key::E) - k(Key::Q),
                turn_right: k(Key::ArrowRight) - k(Key::ArrowLeft),
                turn_up: k(Key::ArrowUp) - k(Key::ArrowDown),
                fast: i.modifiers.shift,
            }
        });
        self.camera.fly(m, dt);
    }

    /// Render the water into the target and show it; drags, wheel and
    /// pinch on it steer the camera.
    fn image(&mut self, ui: &mut egui::Ui) {
        if let Err(e) = &self.renderer {
            ui.centered_and_justified(|ui| {
                ui.colored_label(
                    egui::Color32::from_rgb(255, 140, 140),
                    format!("Hydrolux cannot run on this adapter.\n\n{e}"),
                );
            });
            return;
        }
        let ppp = ui.pixels_per_point();
        let avail = ui.available_size();
        let size = self.options.size.unwrap_or((
            ((avail.x * ppp) as u32).clamp(16, 4096),
            ((avail.y * ppp) as u32).clamp(16, 4096),
        ));
        let camera = self.camera.camera();
        let time = self.clock.sim_time;
        let (view_ok, id) = {
            let target = self.target(size);
            (target.view.clone(), target.id)
        };
        let Ok(renderer) = &mut self.renderer else { return };
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        renderer.render(&mut encoder, &FrameInput { target: &view_ok, size, camera, time });
        self.gpu.queue.submit([encoder.finish()]);
        let points = egui::vec2(size.0 as f32 / ppp, size.1 as f32 / ppp);
        let response = ui.add(egui::Image::new((id, points)).sense(egui::Sense::click_and_drag()));
        // The pointer as in the viewer (hydrolux_ui::pointer): a press on the
        // water draws ripples, on a moving body pulls it; elsewhere a drag
        // looks around. B drops the ball in under the pointer.
        let rect = response.rect;
        let ndc_of = |p: egui::Pos2| {
            [
                2.0 * (p.x - rect.min.x) / rect.width().max(1.0) - 1.0,
                1.0 - 2.0 * (p.y - rect.min.y) / rect.height().max(1.0),
            ]
        };
        let aspect = rect.width().max(1.0) / rect.height().max(1.0);
        let at = response.interact_pointer_pos().or(response.hover_pos());
        if let (Some(p), Ok(renderer)) = (at, &mut self.renderer) {
            if response.drag_started() {
                self.pointer.press(renderer, &camera, ndc_of(p), aspect);
            } else if response.dragged() && self.pointer.grabbing() {
                self.pointer.drag(renderer, &camera, ndc_of(p), aspect);
            }
            if response.hovered()
                && !ui.ctx().egui_wants_keyboard_input()
                && ui.input(|i| i.key_pressed(egui::Key::B))
            {
                hydrolux_ui::pointer::drop_ball(renderer, &camera, ndc_of(p), aspect);
            }
        }
        if response.drag_stopped() {
            self.pointer.release();
        }
        if response.dragged() && !self.pointer.grabbing() {
            let d = response.drag_delta() * ppp;
            self.camera.drag(d.x, d.y);
        }
        if response.hovered() {
            let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
            self.camera.dolly(scroll * 0.02 + (zoom - 1.0) * 20.0);
        }
    }

    /// Render the current view into the target's copy and read it back.
    fn start_screenshot(&mut self, publish: bool) {
        let Some(t) = &self.target else { return };
        let (w, h) = t.size;
        let padded_row = (w * 4).div_ceil(256) * 256;
        let buffer = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("screenshot"),
            size: u64::from(padded_row * h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            t.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row),
                    rows_per_image: Some(h),
                },
            },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        self.gpu.queue.submit([encoder.finish()]);
        let ready = Arc::new(Mutex::new(None));
        let done = ready.clone();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            if let Ok(mut slot) = done.lock() {
                *slot = Some(r.map_err(|e| e.to_string()));
            }
        });
        self.readback = Some(Readback { buffer, size: (w, h), padded_row, ready, publish });
    }

    /// A finished screenshot becomes a PNG download.
    fn finish_screenshot(&mut self) {
        let Some(rb) = &self.readback else { return };
        let Some(result) = rb.ready.lock().ok().and_then(|mut s| s.take()) else { return };
        let rb = self.readback.take().expect("checked");
        let png = result.and_then(|()| encode_png(&rb));
        if rb.publish {
            match png {
                Ok(bytes) => publish(&[("png", js_sys::Uint8Array::from(bytes.as_slice()).into())]),
                Err(e) => report_error(&format!("capture failed: {e}")),
            }
            return;
        }
        self.status = match png.and_then(|bytes| download(&bytes, &self.scene_name)) {
            Ok(name) => format!("saved {name}"),
            Err(e) => format!("screenshot failed: {e}"),
        };
    }
}

const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const EGUI_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The read-back image as PNG bytes.
fn encode_png(rb: &Readback) -> Result<Vec<u8>, String> {
    let (w, h) = rb.size;
    let data = rb.buffer.slice(..).get_mapped_range().map_err(|e| e.to_string())?;
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for row in 0..h {
        let start = (row * rb.padded_row) as usize;
        rgba.extend_from_slice(&data[start..start + (w * 4) as usize]);
    }
    drop(data);
    rb.buffer.unmap();
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()
            .and_then(|mut wr| wr.write_image_data(&rgba))
            .map_err(|e| e.to_string())?;
    }
    Ok(png_bytes)
}

/// Offer `png_bytes` as a download named after the scene.
fn download(png_bytes: &[u8], scene: &str) -> Result<String, String> {
    let array = js_sys::Uint8Array::from(png_bytes);
    let parts = js_sys::Array::of1(&array);
    let props = web_sys::BlobPropertyBag::new();
    props.set_type("image/png");
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &props)
        .map_err(|e| format!("{e:?}"))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(|e| format!("{e:?}"))?;
    let name = format!("hydrolux-{scene}.png");
    let document = web_sys::window().and_then(|w| w.document()).ok_or("no document")?;
    let a: web_sys::HtmlAnchorElement =
        wasm_bindgen::JsCast::dyn_into(document.create_element("a").map_err(|e| format!("{e:?}"))?)
            .map_err(|_| "not an anchor")?;
    a.set_href(&url);
    a.set_download(&name);
    a.click();
    let _ = web_sys::Url::revoke_object_url(&url);
    Ok(name)
}

impl eframe::App for WebApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let now = web_sys::window().and_then(|w| w.performance()).map_or(0.0, |p| p.now());
        let dt = self.last_ms.map_or(0.0, |last| (now - last) / 1000.0);
        self.last_ms = Some(now);
        if dt > 0.0 {
            self.clock.frame_ms = if self.clock.frame_ms == 0.0 {
                dt * 1000.0
            } else {
                0.9 * self.clock.frame_ms + 100.0 * dt
            };
        }
        // Slow frames (a software adapter) must not make the camera jump.
        let dt = dt.min(0.1);
        let ctx = ui.ctx().clone();
        self.fly(&ctx, dt as f32);
        if let Some(scale) = PLAY.with(|p| p.take()) {
            self.clock.paused = false;
            self.clock.time_scale = scale;
        }
        if !self.clock.paused {
            self.clock.sim_time += dt * self.clock.time_scale;
        }
        self.finish_screenshot();
        // A file dropped onto the page is read (browsers read files only
        // asynchronously) and opened on a later frame.
        if let Some(file) = ctx.input(|i| i.raw.dropped_files.first().cloned()) {
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.path().to_string_lossy().into_owned();
                let bytes = file.bytes_async().await;
                DROPPED.with(|d| *d.borrow_mut() = Some((name, bytes)));
            });
        }
        if let Some((name, bytes)) = DROPPED.with(|d| d.borrow_mut().take()) {
            let name = if name.is_empty() { "dropped.toml".to_string() } else { name };
            match bytes {
                Ok(bytes) => self.open_dropped(&name, &bytes),
                Err(e) => self.editor.error = Some(format!("{name} could not be read: {e}")),
            }
            self.clock.frame_ms = 0.0;
            publish(&[("png", JsValue::UNDEFINED)]);
        }
        if let Some(name) = REQUESTED.with(|r| r.borrow_mut().take()) {
            self.switch_scene(&name);
            self.clock.frame_ms = 0.0;
            publish(&[("png", JsValue::UNDEFINED)]);
            if let Some(e) = &self.editor.error {
                report_error(&format!("scene `{name}`: {e}"));
            }
        }
        if self.options.panel {
            egui::Panel::left("scene").default_size(300.0).show(ui, |ui| self.panel(ui));
        }
        egui::CentralPanel::no_frame().show(ui, |ui| self.image(ui));
        self.frames += 1;
        if self.options.capture_after == Some(self.frames - self.shown_at)
            && self.readback.is_none()
        {
            self.start_screenshot(true);
        }
        if let Some(e) = self.uncaught.lock().ok().and_then(|mut e| e.take()) {
            self.status = format!("GPU error: {e}");
            report_error(&self.status);
        }
        publish(&[
            ("frames", JsValue::from_f64(self.frames as f64)),
            ("scene_frames", JsValue::from_f64((self.frames - self.shown_at) as f64)),
            ("frame_ms", JsValue::from_f64(self.clock.frame_ms)),
            ("scene", JsValue::from_str(&self.scene_name)),
            ("time", JsValue::from_f64(self.clock.sim_time)),
        ]);
        ctx.request_repaint();
    }
}
