//! `hydrolux compare`: the truth mode of issue #16. One frame rendered with
//! the projective approximations (seeds 000/002) and ray traced (seed 003
//! §3.3.1, `water.method = "raytrace"`) from the same camera, and the
//! per-pixel error between them (CIELAB ΔE of what is displayed) over the
//! water, split into reflection- and refraction-dominated pixels by the
//! water's Fresnel reflectance there (the `fresnel` debug view).
//!
//! For a scene with the volumetric liquid (issue #30), `--surfaces` (the
//! default where the scene has no surface water) compares its surfaces
//! instead: the same liquid drawn by marching cubes, a screen-space mesh,
//! screen-space fluid rendering and points, each against marching cubes at the finest grid, with the
//! error over the pixels the liquid changes.

use crate::SceneArgs;
use crate::output::{self, Staged};
use anyhow::{Result, bail};
use clap::Args;
use hydrolux::Renderer;
use hydrolux::core::compare::{ErrorStats, delta_e, heat};
use hydrolux::core::scene::Scene;
use hydrolux::headless::HeadlessTarget;
use std::path::{Path, PathBuf};

/// Reflection-dominated pixels: the water reflects at least this much.
pub const REFLECTION_DOMINATED: f32 = 0.2;
/// Refraction-dominated pixels: the water reflects less than this.
pub const REFRACTION_DOMINATED: f32 = 0.05;

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub size: crate::SizeArgs,
    /// Simulation time of the frame, seconds [default: the scene's start_time].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::time)]
    pub time: Option<f64>,
    /// Where to write: OUT-projective.png, OUT-raytrace.png and OUT-error.png
    /// (ΔE: black 0, red 10, yellow 20, white 40 and more).
    #[arg(long, default_value = "compare")]
    pub out: PathBuf,
    /// Compare the liquid's surfaces (marching cubes, screen-space mesh,
    /// screen-space fluid rendering, points) against marching cubes at its finest grid: OUT-S.png and
    /// OUT-S-error.png for each [default where the scene has a liquid and
    /// no surface water].
    #[arg(long)]
    pub surfaces: bool,
}

fn with_suffix(out: &Path, suffix: &str) -> PathBuf {
    let name = out.file_name().and_then(|n| n.to_str()).unwrap_or("compare");
    let stem = name.strip_suffix(".png").unwrap_or(name);
    out.with_file_name(format!("{stem}-{suffix}.png"))
}

fn scene_with(args: &SceneArgs, sets: &[&str]) -> Result<Scene> {
    let mut a = args.clone();
    a.set.extend(sets.iter().map(|s| s.to_string()));
    a.load_offline()
}

pub fn run(a: CompareArgs) -> Result<()> {
    a.size.check()?;
    if let Some(t) = a.time
        && !t.is_finite()
    {
        bail!("--time {t}: must be a finite number of seconds");
    }
    if a.scene.view.is_some() {
        bail!(
            "--view: compare renders the final image (and its own Fresnel view); leave --view out"
        );
    }
    let plain = a.scene.load_offline()?;
    if a.surfaces || (plain.fluid.enabled() && !plain.has_water()) {
        return surfaces(&a, &plain);
    }
    let paths = ["projective", "raytrace", "error"].map(|s| with_suffix(&a.out, s));
    for p in &paths {
        output::check_writable(p)?;
    }
    let projective = scene_with(&a.scene, &["water.method=projective"])?;
    if !projective.has_water() {
        // Say which input took the water away: the scene, or a --set.
        let set = a.scene.set.iter().find(|s| s.replace(' ', "").starts_with("water.model="));
        match set {
            Some(s) => bail!("--set {s}: the scene then has no water to compare"),
            None => bail!("--scene {}: it has no water to compare", a.scene.scene),
        }
    }
    let traced = scene_with(&a.scene, &["water.method=raytrace"])?;
    let time = a.time.unwrap_or(projective.start_time);
    // Nothing drawn over the surface (god rays, fog) may change the view's values.
    let fresnel = scene_with(
        &a.scene,
        &["water.method=projective", "render.view=fresnel", "godrays.method=off", "air.fog=0"],
    )?;
    let ctx = crate::headless_context()?;
    let (w, h) = (a.size.width, a.size.height);
    let target = HeadlessTarget::new(&ctx.device, (w, h));
    let frame = |scene: &Scene| -> Result<(Vec<u8>, Renderer)> {
        let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, scene)?;
        r.set_exact_time(true);
        r.set_catch_up_progress(Some(crate::render::catch_up_bar(time)));
        let pixels = target.render(&mut r, scene.camera(), time)?;
        Ok((pixels, r))
    };
    let (p_pixels, _) = frame(&projective)?;
    let (t_pixels, _) = frame(&traced)?;
    let (_, fresnel_renderer) = frame(&fresnel)?;
    let Some((fw, fh, reflectance)) = fresnel_renderer.read_hdr() else {
        bail!("the Fresnel view rendered nothing");
    };
    let mut error = vec![0u8; (w * h * 4) as usize];
    let (mut all, mut reflecting, mut refracting) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let rgb = |p: &[u8]| [p[4 * i], p[4 * i + 1], p[4 * i + 2]];
            let e = delta_e(rgb(&p_pixels), rgb(&t_pixels));
            let c = heat(e);
            error[4 * i..4 * i + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
            // The Fresnel view may be drawn smaller (the quality's scale).
            let (sx, sy) = (
                (x as u64 * fw as u64 / w as u64) as u32,
                (y as u64 * fh as u64 / h as u64) as u32,
            );
            let v = reflectance[(sy * fw + sx) as usize];
            if v[1] == 1.0 && v[2] == 0.0 {
                all.push(e);
                if v[0] >= REFLECTION_DOMINATED {
                    reflecting.push(e);
                } else if v[0] < REFRACTION_DOMINATED {
                    refracting.push(e);
                }
            }
        }
    }
    let mut staged = Staged::new();
    staged.png(&paths[0], w, h, &p_pixels)?;
    staged.png(&paths[1], w, h, &t_pixels)?;
    staged.png(&paths[2], w, h, &error)?;
    staged.publish()?;
    println!(
        "compare   {} {w}×{h} at t = {} s: water.method projective against raytrace (ΔE*ab of the displayed colours)",
        a.scene.scene, time
    );
    let line = |name: &str, s: ErrorStats| {
        let share = 100.0 * s.pixels as f64 / (w * h) as f64;
        println!(
            "{name:<34} {:>8} px ({share:4.1}%)   mean {:6.2}   p95 {:6.2}   max {:6.2}",
            s.pixels, s.mean, s.p95, s.max
        );
    };
    line("water", ErrorStats::of(&all));
    line(
        &format!("reflection-dominated (F ≥ {REFLECTION_DOMINATED})"),
        ErrorStats::of(&reflecting),
    );
    line(
        &format!("refraction-dominated (F < {REFRACTION_DOMINATED})"),
        ErrorStats::of(&refracting),
    );
    for p in &paths {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The surfaces compared, and the reference's grid.
const SURFACES: [&str; 4] = ["marching_cubes", "screen_mesh", "screen_space", "points"];

/// `--surfaces`: each of the liquid's surfaces against marching cubes at
/// its finest grid, over the pixels where the liquid changes the image
/// (where the reference differs from the scene without the liquid drawn).
fn surfaces(a: &CompareArgs, plain: &Scene) -> Result<()> {
    if !plain.fluid.enabled() {
        bail!("--surfaces: the scene {} has no liquid ([fluid] with sources)", a.scene.scene);
    }
    let mut paths = Vec::new();
    for s in SURFACES {
        paths.push(with_suffix(&a.out, s));
        paths.push(with_suffix(&a.out, &format!("{s}-error")));
    }
    for p in &paths {
        output::check_writable(p)?;
    }
    let finest =
        format!("fluid.surface_resolution={}", hydrolux::core::scene::MAX_SURFACE_RESOLUTION);
    let reference = scene_with(&a.scene, &["fluid.surface=marching_cubes", &finest])?;
    let bare = scene_with(&a.scene, &["fluid.surface=none"])?;
    let time = a.time.unwrap_or(plain.start_time);
    let ctx = crate::headless_context()?;
    let (w, h) = (a.size.width, a.size.height);
    let target = HeadlessTarget::new(&ctx.device, (w, h));
    let frame = |scene: &Scene| -> Result<Vec<u8>> {
        let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, scene)?;
        r.set_exact_time(true);
        r.set_catch_up_progress(Some(crate::render::catch_up_bar(time)));
        Ok(target.render(&mut r, scene.camera(), time)?)
    };
    let truth = frame(&reference)?;
    let without = frame(&bare)?;
    let rgb = |p: &[u8], i: usize| [p[4 * i], p[4 * i + 1], p[4 * i + 2]];
    // The liquid's pixels: it changes them by more than a just noticeable
    // difference.
    let liquid: Vec<bool> =
        (0..(w * h) as usize).map(|i| delta_e(rgb(&truth, i), rgb(&without, i)) > 1.0).collect();
    let mut staged = Staged::new();
    let mut lines = Vec::new();
    for (k, s) in SURFACES.iter().enumerate() {
        let pixels = frame(&scene_with(&a.scene, &[&format!("fluid.surface={s}")])?)?;
        let mut error = vec![0u8; (w * h * 4) as usize];
        let mut over = Vec::new();
        for i in 0..(w * h) as usize {
            let e = delta_e(rgb(&pixels, i), rgb(&truth, i));
            let c = heat(e);
            error[4 * i..4 * i + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
            if liquid[i] {
                over.push(e);
            }
        }
        staged.png(&paths[2 * k], w, h, &pixels)?;
        staged.png(&paths[2 * k + 1], w, h, &error)?;
        lines.push((s, ErrorStats::of(&over)));
    }
    staged.publish()?;
    println!(
        "compare   {} {w}×{h} at t = {time} s: the liquid's surfaces against marching cubes on {} cells (ΔE*ab of the displayed colours, over the liquid's pixels)",
        a.scene.scene,
        hydrolux::core::scene::MAX_SURFACE_RESOLUTION
    );
    for (s, e) in lines {
        let share = 100.0 * e.pixels as f64 / (w * h) as f64;
        println!(
            "{s:<16} {:>8} px ({share:4.1}%)   mean {:6.2}   p95 {:6.2}   max {:6.2}",
            e.pixels, e.mean, e.p95, e.max
        );
    }
    for p in &paths {
        println!("wrote {}", p.display());
    }
    Ok(())
}
