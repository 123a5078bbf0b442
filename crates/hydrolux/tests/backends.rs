//! Every built-in scene renders alike on wgpu's Vulkan and OpenGL backends
//! (in CI: Mesa lavapipe and llvmpipe, one machine's two drivers). The two
//! images of each scene are compared with the golden-image metric and its
//! tolerances (tests/golden/mod.rs: mean ΔE ≤ 1.5, 99th percentile ≤ 8
//! after the eye's blur): the backends differ in rasterisation rules and
//! float rounding, never in what is drawn.

mod golden;

use hydrolux::core::scene::Scene;
use hydrolux::headless::HeadlessTarget;
use hydrolux::wgpu::Backends;
use hydrolux::{GpuContext, Renderer};

fn render_all(backend: Backends, name: &str) -> Vec<(String, Vec<u8>)> {
    let ctx = GpuContext::headless_on(Some(backend)).unwrap_or_else(|e| {
        panic!(
            "{name}: {e} (CI installs mesa-vulkan-drivers for Vulkan, libegl1 and \
             libgl1-mesa-dri for OpenGL)"
        )
    });
    assert_eq!(ctx.adapter.get_info().backend, backend_of(backend), "{name}");
    hydrolux::core::scene::BUILTIN_SCENES
        .iter()
        .map(|builtin| {
            let scene_name = builtin.name;
            let scene = Scene::load(scene_name, &[]).expect("built-in");
            let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)
                .unwrap_or_else(|e| panic!("{name}, {scene_name}: {e}"));
            let target = HeadlessTarget::new(&ctx.device, (W, H));
            let px = target
                .render(&mut r, scene.camera(), 0.0)
                .unwrap_or_else(|e| panic!("{name}, {scene_name}: {e}"));
            (scene_name.to_string(), px)
        })
        .collect()
}

fn backend_of(b: Backends) -> hydrolux::wgpu::Backend {
    if b == Backends::GL { hydrolux::wgpu::Backend::Gl } else { hydrolux::wgpu::Backend::Vulkan }
}

const W: u32 = 160;
const H: u32 = 90;

#[test]
fn every_builtin_scene_looks_the_same_on_vulkan_and_opengl() {
    let vulkan = render_all(Backends::VULKAN, "Vulkan");
    let gl = render_all(Backends::GL, "OpenGL");
    let mut failures = Vec::new();
    for ((name, a), (_, b)) in vulkan.iter().zip(&gl) {
        let (mean, p99) = golden::mean_and_p99(W, H, a, b);
        eprintln!("{name:14} Vulkan vs OpenGL: mean ΔE {mean:.2}, 99th percentile {p99:.2}");
        if !golden::within_tolerance(mean, p99) {
            golden::write_failure(&format!("{name}.opengl"), W, H, b, a);
            failures.push(format!("{name}: mean ΔE {mean:.2}, 99th percentile {p99:.2}"));
        }
    }
    assert!(failures.is_empty(), "OpenGL differs from Vulkan: {}", failures.join("; "));
}
