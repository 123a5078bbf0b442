//! `hydrolux`: render water headless, view it live, benchmark it.

mod bench;
mod compare;
mod dumps;
mod interrupt;
mod output;
mod render;
mod values;
mod video;
mod view;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use hydrolux::core::scene::{BUILTIN_SCENES, Scene};

#[derive(Parser)]
#[command(
    name = "hydrolux",
    version,
    about = "Real-time water rendering: headless images, an interactive viewer, benchmarks."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Options shared by every command that loads a scene.
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// Built-in scene name (see `hydrolux scenes`) or a path to a .toml file.
    #[arg(long, default_value = "ocean")]
    pub scene: String,
    /// Override a scene parameter: --set section.key=value (TOML value; a bare word is a string). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Show a debug view instead of the final image (= --set render.view=KIND): final,
    /// reflection, refraction, depth, normals, shadow, medium, caustics, ripples, foam, fresnel, or
    /// error (the per-pixel ΔE, as heat, of the projective water against ray tracing, or with a
    /// liquid and no water, of its surface against marching cubes on the finest grid).
    #[arg(long, value_name = "KIND")]
    pub view: Option<String>,
}

/// Output size, shared by every command that draws.
#[derive(Args, Clone, Copy)]
pub struct SizeArgs {
    #[arg(long, default_value_t = 1280, allow_hyphen_values = true, value_parser = values::pixels)]
    pub width: u32,
    #[arg(long, default_value_t = 720, allow_hyphen_values = true, value_parser = values::pixels)]
    pub height: u32,
}

impl SizeArgs {
    pub fn check(&self) -> Result<()> {
        for (name, v) in [("--width", self.width), ("--height", self.height)] {
            if !(1..=16384).contains(&v) {
                anyhow::bail!("{name} {v} is out of range: must be 1 to 16384 pixels");
            }
        }
        Ok(())
    }
}

impl SceneArgs {
    pub fn load(&self) -> Result<Scene> {
        let mut sets = self.set.clone();
        if let Some(v) = &self.view {
            sets.push(format!("render.view=\"{}\"", v.replace('"', "")));
        }
        Ok(Scene::load(&self.scene, &sets)?)
    }

    /// The scene for an offline picture (`render`, `compare`): as written,
    /// i.e. `render.quality = "auto"` is `high` whatever the adapter, since
    /// a still waits for its frame (the viewer, the web page and `bench`
    /// keep `auto`: `low` on software adapters). A tier given with `--set`
    /// or in the scene file is kept.
    pub fn load_offline(&self) -> Result<Scene> {
        let mut scene = self.load()?;
        let given = self.set.iter().any(|s| s.trim_start().starts_with("render.quality"));
        if !given && scene.render.quality == hydrolux::core::scene::Quality::Auto {
            scene.render.quality = hydrolux::core::scene::Quality::High;
        }
        Ok(scene)
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render the scene to an image (or an image sequence) without a window.
    Render(render::RenderArgs),
    /// Open a window with a fly camera and a panel that edits the scene live.
    View(view::ViewArgs),
    /// Render frames and report frame-time statistics and per-pass GPU times.
    Bench(bench::BenchArgs),
    /// Render one frame projective and ray traced; write both and the per-pixel error, print its statistics.
    Compare(compare::CompareArgs),
    /// List the built-in scenes.
    Scenes,
    /// Print the GPU adapter Hydrolux would use and its limits.
    Info,
}

fn info() -> Result<()> {
    let ctx = hydrolux::GpuContext::headless()?;
    let i = ctx.adapter.get_info();
    let l = ctx.device.limits();
    println!("adapter:      {} ({:?}, {:?})", i.name, i.device_type, i.backend);
    println!("driver:       {} {}", i.driver, i.driver_info);
    println!(
        "timestamps:   {}",
        if ctx.has_timestamps() {
            "yes (per-pass GPU times in bench)"
        } else {
            "no (bench reports wall clock only)"
        }
    );
    println!("max texture:  {} px", l.max_texture_dimension_2d);
    println!("max storage buffer binding: {} MiB", l.max_storage_buffer_binding_size >> 20);
    println!("max workgroup storage:      {} KiB", l.max_compute_workgroup_storage_size >> 10);
    let max_n = hydrolux::largest_ocean_resolution(&ctx.device, 4);
    println!("largest ocean.resolution with 4 cascades: {max_n}");
    let caps = hydrolux::Capabilities::of(&ctx.device);
    match caps.check_supported() {
        Ok(()) => {
            println!(
                "simulations (step order, those a scene has run): {}",
                hydrolux::simulation_names().join(", ")
            );
            println!(
                "techniques (frame order, all run): {}",
                hydrolux::technique_names().join(", ")
            )
        }
        Err(e) => println!("techniques: none run: {e}"),
    }
    let tier = hydrolux::core::scene::Quality::Auto.resolve(caps.cpu);
    println!(
        "render.quality = auto means: {} here ({})",
        hydrolux::core::scene::Choice::name(tier),
        if caps.cpu { "a software adapter" } else { "a GPU" }
    );
    println!("adapted to this device:");
    for line in caps.adaptations() {
        println!("  {line}");
    }
    Ok(())
}

fn scenes() {
    // One column for the descriptions, however long the names.
    // The memory: how far back any time is simulated from (`render --time`).
    let width = BUILTIN_SCENES.iter().map(|b| b.name.len()).max().unwrap_or(0);
    println!("{:<width$}  {:>6}  description", "scene", "memory");
    for b in BUILTIN_SCENES {
        let (memory, desc) = match Scene::load(b.name, &[]) {
            Ok(s) => (format!("{} s", s.simulation_memory()), s.description),
            Err(e) => ("-".into(), format!("(broken: {e})")),
        };
        println!("{:<width$}  {memory:>6}  {desc}", b.name);
    }
}

fn main() {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version go to stdout as clap writes them.
        Err(e) if !e.use_stderr() => e.exit(),
        // Bad arguments: one line naming the option (and clap's tip, such
        // as a similar option's name), exit 1, like every other bad input.
        Err(e) => {
            let text = e.to_string();
            let parts: Vec<&str> = text
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more"))
                .collect();
            eprintln!("error: {}", parts.join("; ").trim_start_matches("error: "));
            std::process::exit(1);
        }
    };
    interrupt::install();
    let result = match cli.command {
        Command::Render(a) => render::run(a),
        Command::View(a) => view::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Scenes => {
            scenes();
            Ok(())
        }
        Command::Info => info(),
    };
    if let Err(e) = result {
        // One line: the chain of causes joined.
        let msg = e.chain().map(|c| c.to_string()).collect::<Vec<_>>().join(": ");
        eprintln!("error: {msg}");
        std::process::exit(1);
    }
}

/// A headless GPU context, with the no-adapter error made actionable.
pub fn headless_context() -> Result<hydrolux::GpuContext> {
    hydrolux::GpuContext::headless().context("cannot start the GPU")
}
