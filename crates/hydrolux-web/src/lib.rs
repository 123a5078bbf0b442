//! Hydrolux in the browser: the viewer as a web page. wasm32 on wgpu's
//! WebGPU backend inside eframe (egui's web runner): the water is rendered
//! into a texture that the page shows, beside the same scene editor panel as
//! `hydrolux view` (`hydrolux-ui`). A browser with only WebGL2 gets a message
//! in the page (no compute shaders there); one with neither gets eframe's
//! error, shown by index.html.
//!
//! URL parameters, for links and for the browser test: `scene=NAME`,
//! `time=T` (start time, s), `paused=1`, `ui=0` (no panel), `width=W` and
//! `height=H` (a fixed image size in pixels instead of the window's).
//! `window.hydrolux` reports `frames`, `frame_ms`, `error`, `adapter` and
//! `scene` for scripts.
//!
//! Build and serve: `web/build.sh --serve` (README, "In the browser").

#[cfg(target_arch = "wasm32")]
mod app;

#[cfg(target_arch = "wasm32")]
mod web {
    use super::app::{Options, WebApp};
    use std::sync::Arc;
    use wasm_bindgen::prelude::*;

    /// The page's entry point: start eframe on the canvas `hydrolux_canvas`.
    #[wasm_bindgen(start)]
    pub fn start() {
        wasm_bindgen_futures::spawn_local(async {
            if let Err(e) = run().await {
                super::app::report_error(&e);
            }
        });
    }

    async fn run() -> Result<(), String> {
        let window = web_sys::window().ok_or("no window")?;
        let document = window.document().ok_or("no document")?;
        let canvas = document
            .get_element_by_id("hydrolux_canvas")
            .ok_or("the page has no canvas `hydrolux_canvas`")?
            .dyn_into::<web_sys::HtmlCanvasElement>()
            .map_err(|_| "`hydrolux_canvas` is not a canvas")?;
        let options = Options::from_url(&window.location().search().unwrap_or_default());
        let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
        // WebGPU first, WebGL2 to be able to say why it cannot run.
        setup.instance_descriptor.backends = wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL;
        setup.device_descriptor = Arc::new(|adapter: &wgpu::Adapter| {
            let webgl = adapter.get_info().backend == wgpu::Backend::Gl;
            wgpu::DeviceDescriptor {
                label: Some("hydrolux web"),
                required_features: if webgl {
                    wgpu::Features::empty()
                } else {
                    hydrolux::context::optional_features(adapter)
                },
                required_limits: if webgl {
                    wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits())
                } else {
                    hydrolux::context::required_limits(adapter)
                },
                ..Default::default()
            }
        });
        let web_options = eframe::WebOptions {
            wgpu_options: egui_wgpu::WgpuConfiguration {
                wgpu_setup: egui_wgpu::WgpuSetup::CreateNew(setup),
                ..Default::default()
            },
            ..Default::default()
        };
        eframe::WebRunner::new()
            .start(canvas, web_options, Box::new(move |cc| Ok(Box::new(WebApp::new(cc, options)?))))
            .await
            .map_err(|e| format!("{e:?}"))
    }

    use eframe::egui_wgpu;
    use hydrolux::wgpu;
}
