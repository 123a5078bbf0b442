//! `hydrolux bench`: frame-time statistics (median, p95) measured as wall
//! clock around submit + wait, and per-pass GPU times from timestamp queries
//! where the adapter has them (labelled as such).

use crate::SceneArgs;
use anyhow::{Result, bail};
use clap::Args;
use hydrolux::Renderer;
use hydrolux::headless::{HeadlessTarget, resident_mb};
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub size: crate::SizeArgs,
    /// Frames to measure (after 3 warm-up frames).
    #[arg(long, default_value_t = 60, allow_hyphen_values = true, value_parser = crate::values::bench_frames)]
    pub frames: u32,
    /// Simulated time (s) of the first warm-up frame: start with the
    /// simulations (foam, particles, the interactive water) already running.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = crate::values::start)]
    pub start: f64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i]
}

pub fn run(a: BenchArgs) -> Result<()> {
    a.size.check()?;
    if a.frames == 0 {
        bail!("--frames 0: must be at least 1");
    }
    let scene = a.scene.load()?;
    let ctx = crate::headless_context()?;
    let info = ctx.adapter.get_info();
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)?;
    renderer.set_catch_up_progress(Some(crate::render::catch_up_bar(a.start)));
    let triangles = renderer.scene_triangles();
    let (quality, requested) = (renderer.quality(), scene.render.quality);
    let rendered = renderer.rendered_scene().clone();
    renderer.set_timing(true);
    let target = HeadlessTarget::new(&ctx.device, (a.size.width, a.size.height));
    let camera = scene.camera();
    for i in 0..3 {
        target.submit(&mut renderer, camera, a.start + i as f64 / 60.0)?;
        renderer.collect_timings();
    }
    // Resident memory after warm-up and at the end: flat however long it runs.
    let memory_start = resident_mb();
    let mut frame_ms = Vec::new();
    let mut passes: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    let mut order: Vec<&'static str> = Vec::new();
    for i in 0..a.frames {
        let t0 = Instant::now();
        let index = target.submit(&mut renderer, camera, a.start + (i + 3) as f64 / 60.0)?;
        ctx.device.poll(hydrolux::wgpu::PollType::Wait {
            submission_index: Some(index),
            timeout: None,
        })?;
        frame_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        renderer.collect_timings();
        for (name, ms) in renderer.last_timings() {
            if !order.contains(name) {
                order.push(name);
            }
            passes.entry(name).or_default().push(*ms);
        }
    }
    let memory = memory_start.zip(resident_mb());
    frame_ms.sort_by(f64::total_cmp);
    let median = percentile(&frame_ms, 0.5);
    let p95 = percentile(&frame_ms, 0.95);
    let pass_medians: Vec<(&str, f64)> = order
        .iter()
        .map(|n| {
            let mut v = passes[n].clone();
            v.sort_by(f64::total_cmp);
            (*n, percentile(&v, 0.5))
        })
        .collect();
    let timestamps = renderer.has_timestamps();
    let particles = renderer.particle_counts();
    // The liquid's step on its own (after the frames: its extra steps
    // start the clock over).
    let liquid = renderer.bench_liquid(a.frames.clamp(1, 20));
    if a.json {
        let j = serde_json::json!({
            "adapter": info.name,
            "backend": format!("{:?}", info.backend),
            "scene": a.scene.scene,
            "overrides": a.scene.set,
            "width": a.size.width,
            "height": a.size.height,
            "frames": a.frames,
            "start_s": a.start,
            "quality": hydrolux::core::scene::Choice::name(quality),
            "render_scale": quality.render_scale(),
            "scene_triangles": triangles,
            "frame_ms": { "median": median, "p95": p95, "source": "wall clock around submit + wait" },
            "passes_ms": pass_medians.iter().map(|(n, v)| serde_json::json!({"pass": n, "median": v})).collect::<Vec<_>>(),
            "pass_times_source": if timestamps { "GPU timestamp queries" } else { "unavailable (adapter lacks TIMESTAMP_QUERY)" },
            "particles": particles.map(|p| serde_json::json!({"alive": p.alive, "capacity": p.capacity, "emitted": p.emitted, "lost": p.lost})),
            "resident_mb": memory.map(|(a, b)| serde_json::json!({"after_warm_up": a, "end": b})),
            "liquid": liquid.as_ref().map(|l| serde_json::json!({
                "particles": l.particles,
                "cells": l.cells,
                "steps": l.steps,
                "step_ms": l.step_ms,
                "steps_per_s": 1e3 / l.step_ms,
                "passes_ms": l.passes.iter().map(|(n, v)| serde_json::json!({"pass": n, "median": v})).collect::<Vec<_>>(),
                "solve_iterations": l.iterations,
                "solve_residual_per_s": l.residual,
            })),
        });
        println!("{}", serde_json::to_string_pretty(&j)?);
    } else {
        println!("adapter   {} ({:?})", info.name, info.backend);
        println!("scene     {} {}", a.scene.scene, a.scene.set.join(" "));
        println!(
            "size      {}×{}, {} frames from t = {} s",
            a.size.width, a.size.height, a.frames, a.start
        );
        let scale = quality.render_scale();
        println!(
            "quality   {}{} (drawn at {}×{}, filtered up to the output)",
            hydrolux::core::scene::Choice::name(quality),
            if requested == hydrolux::core::scene::Quality::Auto {
                " (render.quality = auto)"
            } else {
                ""
            },
            (a.size.width as f32 * scale).round(),
            (a.size.height as f32 * scale).round()
        );
        let water = if scene.water.model == hydrolux::core::scene::WaterModel::None {
            " (no water)"
        } else {
            " (+ water clipmap)"
        };
        println!(
            "geometry  {triangles} scene triangles{water}, shadow map {}², reflection at {}× output",
            rendered.render.shadow_resolution, rendered.render.reflection_resolution
        );
        println!("frame     median {median:.2} ms   p95 {p95:.2} ms   (wall clock, submit → done)");
        if let Some(p) = particles {
            println!(
                "particles {} alive of {} (budget), {} born, {} not born for want of room",
                p.alive, p.capacity, p.emitted, p.lost
            );
        }
        if let Some((a, b)) = memory {
            println!(
                "memory    {a:.0} MB resident after warm-up, {b:.0} MB at the end ({:+.1} MB)",
                b - a
            );
        }
        if timestamps {
            println!("passes    (GPU timestamps, median ms)");
            // One column for the times, however long the passes' names.
            let width = pass_medians.iter().map(|p| p.0.chars().count()).max().unwrap_or(0).max(3);
            for (n, v) in &pass_medians {
                println!("  {n:<width$} {v:8.3}");
            }
            let sum = pass_medians.iter().map(|p| p.1).sum::<f64>();
            println!("  {:<width$} {sum:8.3}", "sum");
        } else {
            println!("passes    unavailable: the adapter has no timestamp queries");
        }
        if let Some(l) = liquid {
            let [x, y, z] = l.cells;
            println!(
                "liquid    {} particles, {x}×{y}×{z} cells: {:.2} ms a step ({:.0} steps/s, wall clock over {} steps); the last solve {} iterations to |∇·u| ≤ {:.1e} 1/s",
                l.particles,
                l.step_ms,
                1e3 / l.step_ms,
                l.steps,
                l.iterations,
                l.residual
            );
            for (n, v) in &l.passes {
                println!("  {n:<20} {v:8.3}");
            }
        }
    }
    Ok(())
}
