//! Memory stays flat however long Hydrolux renders: scenes that between
//! them run every technique (FFT ocean, caustics, offscreen views, god rays
//! under water, refractive objects in fog, ray tracing with a moving camera,
//! the error view, the volumetric liquid with a nozzle, as a mesh and in screen space), a few hundred tiny frames in all, resident memory measured after a warm-up and at the end. (Its own
//! test binary, so no other test allocates meanwhile.) The 10,000-frame soak
//! of every scene is in BENCHMARKS.md.
//!
//! What this guards against, found on Mesa's lavapipe 22: a shader that
//! branches on a uniform is recompiled each time its bind groups are set,
//! and every copy is kept (about 1 MB a frame). Hydrolux specialises its
//! pipelines to the surface model and keeps such branches out of shaders
//! that are bound per object or per pass.

use hydrolux::core::scene::Scene;
use hydrolux::headless::{HeadlessTarget, resident_mb};
use hydrolux::{GpuContext, Renderer};

#[test]
fn memory_is_flat_over_hundreds_of_frames() {
    if resident_mb().is_none() {
        eprintln!("skipped: no /proc/self/status on this system");
        return;
    }
    let ctx = GpuContext::headless().expect("GPU tests need an adapter");
    let target = HeadlessTarget::new(&ctx.device, (32, 24));
    let (warm_up, frames) = (30, 120);
    let mut report = Vec::new();
    // The ray-traced lake with its camera circling (the traced windows move
    // every frame), and the error view (two drawings a frame).
    // The liquid poured from a nozzle (a coarse grid: lavapipe steps it
    // eight times a frame).
    // The same drawn by screen-space fluid rendering (a texture lookup at
    // a projected point leaked 2.5 MB a frame there).
    // White water's particles with their pool full from the first frame
    // (`docs/particles-bench.toml`'s downpour at the most 60 ripple steps a second allow, 2^16
    // particles): past its high-water mark, memory stays where it is
    // (at 10^6 lavapipe's plateau is 1.3 GB, reached while the pool
    // fills; BENCHMARKS.md).
    let particles = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/particles-bench.toml");
    let cases: [(&str, &[&str], bool); 9] = [
        ("pool", &[], false),
        ("underwater", &[], false),
        ("water_dragon", &[], false),
        ("ocean", &[], false),
        ("lake", &["water.method=raytrace"], true),
        ("pool", &["render.view=error"], false),
        ("pour", &["fluid.resolution=8"], false),
        ("pour", &["fluid.resolution=8", "fluid.surface=screen_space"], false),
        (
            particles,
            &[
                "whitewater.budget=65536",
                "ripples.resolution=64",
                "emitters=[{center=[0.0,0.0],size=[7.5,7.5],rate=1900.0,radius=0.45,strength=0.2}]",
            ],
            false,
        ),
    ];
    for (name, sets, moving) in cases {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load(name, &sets).expect("built-in scene");
        let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)
            .expect("renderer");
        let name = std::iter::once(name.rsplit('/').next().unwrap_or(name).to_string())
            .chain(sets)
            .collect::<Vec<_>>()
            .join(" ");
        let mut after_warm_up = 0.0;
        for i in 0..frames {
            let mut camera = scene.camera();
            if moving {
                let a = i as f32 * 0.05;
                let offset = glam::Vec3::new(a.cos(), 0.0, a.sin()) * (3.0 + 0.2 * i as f32);
                camera.position += offset;
                camera.look_at += offset;
            }
            let index = target.submit(&mut r, camera, i as f64 / 30.0).expect("frame");
            ctx.device
                .poll(hydrolux::wgpu::PollType::Wait {
                    submission_index: Some(index),
                    timeout: None,
                })
                .expect("frame finishes");
            if i + 1 == warm_up {
                after_warm_up = resident_mb().expect("checked above");
                if name.starts_with("particles-bench") {
                    let p = r.particle_counts().expect("particles");
                    assert!(
                        p.alive as f64 >= 0.9 * p.capacity as f64,
                        "the pool is full by the warm-up's end: {} alive of {}",
                        p.alive,
                        p.capacity
                    );
                }
            }
        }
        let growth = resident_mb().expect("checked above") - after_warm_up;

        report.push(format!("{}: {growth:+.1} MB", name));
        // The leaks this guards against took 0.4 to 1.4 MB a frame, i.e.
        // 36 to 130 MB here; the liquid's draw (a small uniform buffer that
        // lavapipe inlined per draw) 3.7 MB. Allocator noise is 0.0–0.2 MB.
        assert!(
            growth < 2.0,
            "{}: resident memory grew {growth:.1} MB over {} frames after warm-up",
            name,
            frames - warm_up
        );
    }
    eprintln!("growth over {} frames: {}", frames - warm_up, report.join(", "));
}
