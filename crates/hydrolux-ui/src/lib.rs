//! What `hydrolux view` and the web page (`hydrolux-web`) share, so that
//! both show the same controls: the scene editor ([`SceneEditor`]), an
//! egui panel generated from the scene's TOML table (new scene parameters
//! appear without UI code), and the camera ([`FlyCamera`]) that keys,
//! mouse and touch steer.

pub mod camera;
pub mod editor;
pub mod pointer;

pub use camera::FlyCamera;
pub use editor::SceneEditor;
pub use pointer::Pointer;

/// The clock a viewer shows and steers.
pub struct Playback {
    pub sim_time: f64,
    /// Where the scene opens and `restart` goes back to (its `start_time`).
    pub start: f64,
    pub time_scale: f64,
    pub paused: bool,
    /// Smoothed frame time (ms).
    pub frame_ms: f64,
}

impl Playback {
    /// A clock at `start` (s), running unless `paused`.
    pub fn at(start: f64, paused: bool) -> Self {
        Playback { sim_time: start, start, time_scale: 1.0, paused, frame_ms: 0.0 }
    }

    /// One simulation step forward, pausing.
    pub fn step(&mut self) {
        self.paused = true;
        self.sim_time += 1.0 / 60.0;
    }

    /// Back to where the scene opens (its `start_time`; the simulation
    /// starts over from t = 0 and catches up to it).
    pub fn restart(&mut self) {
        self.sim_time = self.start;
    }
}

/// What the header's buttons asked for this frame.
#[derive(Default)]
pub struct HeaderActions {
    pub reset_camera: bool,
    pub screenshot: bool,
    /// Start the simulation over (still water, bodies where they began).
    pub restart: bool,
    /// One simulation step forward (while paused).
    pub step: bool,
}

/// The panel's header, the same in the viewer and the page: title, frame
/// time and clock, play/pause and time scale, camera reset, flying or
/// orbiting, and screenshot.
pub fn header_ui(
    ui: &mut egui::Ui,
    p: &mut Playback,
    camera: &mut FlyCamera,
    screenshot_label: &str,
) -> HeaderActions {
    ui.heading("Hydrolux");
    ui.label(format!(
        "{:.1} ms/frame   t = {:.1} s{}",
        p.frame_ms,
        p.sim_time,
        if p.paused { "  (paused)" } else { "" }
    ));
    let mut actions = HeaderActions::default();
    ui.horizontal(|ui| {
        if ui.button(if p.paused { "play" } else { "pause" }).clicked() {
            p.paused = !p.paused;
        }
        actions.step = ui.button("step").on_hover_text("one step of 1/60 s").clicked();
        let hint = if p.start > 0.0 {
            format!("back to the scene's start, t = {} s (run from still water at t = 0)", p.start)
        } else {
            "t = 0: still water".to_string()
        };
        actions.restart = ui.button("restart").on_hover_text(hint).clicked();
    });
    ui.add(egui::Slider::new(&mut p.time_scale, 0.0..=4.0).text("time ×"));
    ui.horizontal(|ui| {
        actions.reset_camera = ui.button("reset camera").clicked();
        ui.checkbox(&mut camera.orbit, "orbit").on_hover_text(format!(
            "O: a drag swings the camera around the point {:.1} m ahead (the wheel closes in)",
            camera.distance
        ));
        actions.screenshot = ui.button(screenshot_label).clicked();
    });
    actions
}
