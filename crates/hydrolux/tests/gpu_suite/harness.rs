// The GPU suite's harness: one shared device on the backends the test
// binary names (`crate::BACKENDS`: tests/gpu.rs whatever wgpu finds, Mesa
// lavapipe in CI; tests/gpu_gl.rs wgpu's OpenGL backend, llvmpipe in CI),
// small scenes and renderers, and the helpers several techniques' tests use.

pub(crate) use crate::BACKENDS;
pub(crate) use crate::golden;
pub(crate) use hydrolux::core::scene::Scene;
pub(crate) use hydrolux::core::sky::Sky;
pub(crate) use hydrolux::core::tonemap::{aces_filmic, linear_to_srgb};
pub(crate) use hydrolux::core::waves::ocean::{OceanFields, OceanSpectrum};
pub(crate) use hydrolux::core::waves::sines::SineWaves;
pub(crate) use hydrolux::headless::HeadlessTarget;
pub(crate) use hydrolux::{GpuContext, Renderer};
pub(crate) use std::sync::{Mutex, OnceLock};

pub(crate) fn gpu() -> &'static Mutex<GpuContext> {
    static GPU: OnceLock<Mutex<GpuContext>> = OnceLock::new();
    GPU.get_or_init(|| {
        Mutex::new(GpuContext::headless_on(BACKENDS).unwrap_or_else(|e| {
            panic!(
                "GPU tests need an adapter (CI installs mesa-vulkan-drivers, and libegl1 with \
                 libgl1-mesa-dri for OpenGL): {e}"
            )
        }))
    })
}

pub(crate) fn scene(sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::load("ocean", &sets).expect("test scene")
}

/// A renderer at the `high` tier (the scene as written) unless the test
/// asks for another: these tests check the settings they give.
pub(crate) fn renderer(ctx: &GpuContext, scene: &Scene) -> Renderer {
    Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &high(scene))
        .expect("renderer")
}

pub(crate) fn high(scene: &Scene) -> Scene {
    use hydrolux::core::scene::Quality;
    let mut s = scene.clone();
    if s.render.quality == Quality::Auto {
        s.render.quality = Quality::High;
    }
    // A jump in time simulates the white water from `memory` seconds back,
    // each step evaluating the FFT ocean again: 3 s (60 steps) shows foam
    // and particles in every test and keeps the suite quick on lavapipe.
    s.whitewater.memory = s.whitewater.memory.min(3.0);
    s
}

pub(crate) const SMALL_OCEAN: &[&str] =
    &["ocean.resolution=64", "ocean.cascades=2", "ocean.patch_size=200", "ocean.wind_speed=12"];

pub(crate) fn render(scene: &Scene, size: (u32, u32), time: f64) -> (Vec<u8>, Vec<[f32; 4]>) {
    let ctx = gpu().lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer(&ctx, scene);
    let target = HeadlessTarget::new(&ctx.device, size);
    let px = target.render(&mut r, scene.camera(), time).expect("frame");
    let hdr = r.read_hdr().expect("rendered").2;
    (px, hdr)
}

/// A thing carried to where it stands in `standing` (scenes that differ in
/// its start and velocity) is drawn, at 4 s, as it is standing there
/// (within the golden metric; `name` its failure images).
pub(crate) fn assert_moved_looks_standing(name: &str, moved: &Scene, standing: &Scene) {
    let (w, h) = (96, 54);
    let (a, _) = render(moved, (w, h), 4.0);
    let (b, _) = render(standing, (w, h), 4.0);
    let (mean, p99) = golden::mean_and_p99(w, h, &a, &b);
    if !golden::within_tolerance(mean, p99) {
        golden::write_failure(name, w, h, &a, &b);
    }
    assert!(golden::within_tolerance(mean, p99), "{name}: mean ΔE {mean:.2}, p99 {p99:.2}");
}

/// Render `s` at `size` and time `t` with `r`, and return a lookup of the
/// linear HDR pixel under the projection of a world point.
pub(crate) fn render_and_project(
    ctx: &GpuContext,
    r: &mut Renderer,
    s: &Scene,
    size: (u32, u32),
    t: f64,
) -> impl Fn(glam::Vec3) -> [f32; 4] + use<> {
    let target = HeadlessTarget::new(&ctx.device, size);
    target.render(r, s.camera(), t).expect("frame");
    let (w, _, hdr) = r.read_hdr().expect("rendered");
    let vp = s.camera().view_projection(size.0 as f32 / size.1 as f32);
    move |p: glam::Vec3| {
        let uv = hydrolux::core::projective::clip_to_uv(vp * p.extend(1.0)).expect("in front");
        hdr[(uv.y * size.1 as f32) as usize * w as usize + (uv.x * size.0 as f32) as usize]
    }
}

/// Means of two maps and their correlation coefficient.
pub(crate) fn means_and_correlation(a: &[f32], b: &[f32]) -> (f32, f32, f32) {
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (ma, mb) = (mean(a), mean(b));
    let cov: f32 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let var = |v: &[f32], m: f32| v.iter().map(|x| (x - m) * (x - m)).sum::<f32>();
    (ma, mb, cov / (var(a, ma) * var(b, mb)).sqrt())
}

/// A small periodic test surface (n × n heights over l × l m, a few sines),
/// written as a `.npy` in the temp folder; returns its path and heights.
pub(crate) fn test_heightfield(n: usize, l: f32, tag: &str) -> (std::path::PathBuf, Vec<f32>) {
    let k = std::f32::consts::TAU / l;
    let heights: Vec<f32> = (0..n * n)
        .map(|idx| {
            let (x, z) = ((idx % n) as f32 / n as f32 * l, (idx / n) as f32 / n as f32 * l);
            0.04 * (2.0 * k * x).sin()
                + 0.03 * (3.0 * k * z + 1.0).sin()
                + 0.02 * (k * (x + 2.0 * z)).cos()
        })
        .collect();
    let path =
        std::env::temp_dir().join(format!("hydrolux-heightfield-{tag}-{}.npy", std::process::id()));
    std::fs::write(&path, hydrolux::core::npy::encode_f32(&[n, n], &heights)).expect("temp file");
    (path, heights)
}

/// A small interactive-water scene: flat water, drops and rain.
pub(crate) fn ripple_scene(edges: &str) -> Scene {
    use hydrolux::core::scene::{DropDesc, EmitterDesc};
    let mut s = scene(&[
        "water.model=\"flat\"",
        "water.dynamic=true",
        "ripples.resolution=32",
        "ripples.extent=2.0",
        "ripples.center=[0.4, -0.3]",
        &format!("ripples.edges=\"{edges}\""),
        "floor.depth=0.5",
        "caustics.method=\"off\"",
        "godrays.method=\"off\"",
        // An open domain goes half a metre ahead of the camera: onto the drops.
        "camera.position=[0.4, 3.0, 0.2]",
        "camera.look_at=[0.4, 0.0, -0.3]",
    ]);
    s.drops = vec![
        DropDesc { time: 0.0, position: [0.6, -0.2], radius: 0.15, strength: 0.01 },
        DropDesc { time: 0.2, position: [-0.3, 0.3], radius: 0.1, strength: -0.005 },
    ];
    s.emitters =
        vec![EmitterDesc { rate: 30.0, size: [1.5, 1.5], radius: 0.08, ..Default::default() }];
    s.validate().expect("valid ripple scene");
    s
}
