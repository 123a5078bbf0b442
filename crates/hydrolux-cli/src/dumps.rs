//! `--dump KIND=FILE`: internal buffers as float arrays (.npy or .exr).
//! Surface buffers are sampled on the N×N grid of the largest cascade
//! (x_j = j·L/N, row = z, col = x), before horizontal displacement; for the
//! FFT ocean they come from the GPU's float32 FFT output.

use crate::output::{self, FloatImage, Format};
use anyhow::{Result, bail};
use hydrolux::Renderer;
use hydrolux::core::scene::WaterModel;
use hydrolux::core::waves::SurfaceSample;
use hydrolux::core::waves::ocean::OceanFields;
use hydrolux::core::whitewater::BUBBLE;
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DumpKind {
    Height,
    Displacement,
    Normals,
    Jacobian,
    Hdr,
    Caustics,
    /// The god-ray buffer (linear radiance, pre-exposed, buffer size).
    Godrays,
    /// The caustic of refractive objects in their light view.
    ObjectCaustics,
    /// The interactive water's heights over its domain.
    Ripples,
    /// The moving bodies' state (JSON).
    Bodies,
    /// The foam field over its window.
    Foam,
    /// The bubbles and spray alive: position, velocity, radius, kind.
    Particles,
}

/// Every dump kind, in the order `--help` lists them (one list for the
/// help, the messages and the parser's test).
macro_rules! dump_kinds {
    () => {
        "height, displacement, normals, jacobian, hdr, caustics, godrays, object_caustics, ripples, bodies, foam, particles"
    };
}
pub const KINDS: &str = dump_kinds!();
/// `render --help`'s text for `--dump`, from the same list.
pub const HELP: &str = concat!(
    "Write an internal buffer: KIND=FILE.npy|FILE.exr (bodies: FILE.json) with KIND one of ",
    dump_kinds!(),
    ". Repeatable."
);

#[derive(Clone, Debug)]
pub struct Dump {
    pub kind: DumpKind,
    pub path: PathBuf,
    pub format: Format,
}

/// The name of a kind as `--dump` spells it.
pub fn dump_name(kind: DumpKind) -> &'static str {
    match kind {
        DumpKind::Height => "height",
        DumpKind::Displacement => "displacement",
        DumpKind::Normals => "normals",
        DumpKind::Jacobian => "jacobian",
        DumpKind::Hdr => "hdr",
        DumpKind::Caustics => "caustics",
        DumpKind::Godrays => "godrays",
        DumpKind::ObjectCaustics => "object_caustics",
        DumpKind::Ripples => "ripples",
        DumpKind::Bodies => "bodies",
        DumpKind::Foam => "foam",
        DumpKind::Particles => "particles",
    }
}

pub fn parse(text: &str) -> Result<Dump> {
    let Some((kind, file)) = text.split_once('=') else {
        bail!("--dump `{text}`: expected KIND=FILE with KIND one of {KINDS}");
    };
    let kind = match kind {
        "height" => DumpKind::Height,
        "displacement" => DumpKind::Displacement,
        "normals" => DumpKind::Normals,
        "jacobian" => DumpKind::Jacobian,
        "hdr" => DumpKind::Hdr,
        "caustics" => DumpKind::Caustics,
        "godrays" => DumpKind::Godrays,
        "object_caustics" => DumpKind::ObjectCaustics,
        "ripples" => DumpKind::Ripples,
        "bodies" => DumpKind::Bodies,
        "foam" => DumpKind::Foam,
        "particles" => DumpKind::Particles,
        other => bail!("--dump `{other}`: unknown buffer; choose one of {KINDS}"),
    };
    let path = PathBuf::from(file);
    let allowed: &[Format] =
        if kind == DumpKind::Bodies { &[Format::Json] } else { &[Format::Npy, Format::Exr] };
    let format = output::format_of(&path, allowed, &format!("--dump {} file", dump_name(kind)))?;
    // A list that may be empty: EXR has no image of zero rows.
    if kind == DumpKind::Particles && format == Format::Exr {
        bail!(
            "--dump particles={file}: the particles are a list that is empty when none are alive, which an EXR image cannot hold; write .npy (N rows of 8 columns, 0 rows when none are alive)"
        );
    }
    Ok(Dump { kind, path, format })
}

/// Surface samples on the largest cascade's grid.
fn surface_grid(renderer: &Renderer) -> (usize, Vec<SurfaceSample>) {
    let scene = renderer.rendered_scene();
    let n = scene.ocean.resolution as usize;
    let l = scene.ocean.patch_size as f64;
    let points: Vec<[f64; 2]> = (0..n)
        .flat_map(|z| (0..n).map(move |x| [x as f64 * l / n as f64, z as f64 * l / n as f64]))
        .collect();
    let samples = match (scene.water.model, renderer.read_ocean_fields()) {
        (WaterModel::Fft, Some(texels)) => {
            let fields = OceanFields {
                resolution: n,
                patch_sizes: scene
                    .ocean_settings()
                    .cascades()
                    .iter()
                    .map(|c| c.patch_size)
                    .collect(),
                texels,
            };
            points.iter().map(|p| fields.sample(p[0], p[1])).collect()
        }
        _ => renderer
            .probe_surface(&points.iter().map(|p| [p[0] as f32, p[1] as f32]).collect::<Vec<_>>()),
    };
    (n, samples)
}

/// What can be known before rendering: a caustics dump needs caustics.
pub fn check(dump: &Dump, scene: &hydrolux::core::scene::Scene) -> Result<()> {
    if dump.kind == DumpKind::Caustics && !scene.has_caustics() {
        bail!(
            "--dump caustics: the scene has no caustics (it needs water (water.model other than \"none\"), caustics.method other than \"off\", a floor (floor.depth > 0) and the sun up)"
        );
    }
    if dump.kind == DumpKind::Godrays
        && scene.godrays.method == hydrolux::core::scene::GodRayMethod::Off
    {
        bail!(
            "--dump godrays: god rays are off in this scene (set godrays.method to \"lines\" or \"march\")"
        );
    }
    let surface_dump = matches!(
        dump.kind,
        DumpKind::Height | DumpKind::Displacement | DumpKind::Normals | DumpKind::Jacobian
    );
    if surface_dump && scene.water.model == WaterModel::None {
        bail!(
            "--dump {}: the scene has no water surface (water.model = \"none\")",
            dump_name(dump.kind)
        );
    }
    if dump.kind == DumpKind::ObjectCaustics && !scene.objects.iter().any(|o| o.material.ior > 0.0)
    {
        bail!(
            "--dump object_caustics: the scene has no refractive object (an object with material.ior > 0)"
        );
    }
    if dump.kind == DumpKind::Ripples && scene.ripple_settings().is_none() {
        bail!(
            "--dump ripples: the scene has no interactive water (set water.dynamic = true, with water.model other than \"none\")"
        );
    }
    let whitewater = |on: bool| scene.has_whitewater() && on;
    if dump.kind == DumpKind::Foam && !whitewater(scene.whitewater.foam) {
        bail!(
            "--dump foam: the scene has no foam (it needs whitewater.foam = true and water that moves: water.model \"fft\" or \"sines\", water.dynamic = true or a moving object)"
        );
    }
    if dump.kind == DumpKind::Particles && !whitewater(scene.whitewater.particles) {
        bail!(
            "--dump particles: the scene has no bubbles or spray (it needs whitewater.particles = true and water that moves: water.model \"fft\" or \"sines\", water.dynamic = true or a moving object)"
        );
    }
    let moving = scene.objects.iter().any(|o| o.dynamic || o.velocity.iter().any(|&v| v != 0.0));
    if dump.kind == DumpKind::Bodies && !moving {
        bail!(
            "--dump bodies: the scene has no moving object (an object with dynamic = true or a velocity)"
        );
    }
    Ok(())
}

/// The moving bodies as JSON: time, then per body its object, position,
/// orientation (quaternion x, y, z, w), velocities and submerged volume.
fn bodies_json(renderer: &Renderer) -> String {
    let scene = renderer.scene();
    let bodies: Vec<serde_json::Value> = renderer
        .bodies()
        .iter()
        .map(|b| {
            let o = &scene.objects[b.object];
            serde_json::json!({
                "object": b.object,
                "name": o.name,
                "position": b.pose.position.to_array(),
                "orientation": b.pose.rotation.to_array(),
                "velocity": b.velocity.to_array(),
                "angular_velocity": b.angular_velocity.to_array(),
                "submerged_volume": b.submerged,
            })
        })
        .collect();
    let doc = serde_json::json!({ "time": renderer.simulation_time(), "bodies": bodies });
    serde_json::to_string_pretty(&doc).expect("JSON of numbers and strings") + "\n"
}

/// Read the buffer back and stage it for writing.
pub fn write(dump: &Dump, renderer: &Renderer, staged: &mut output::Staged) -> Result<()> {
    if dump.kind == DumpKind::Bodies {
        return staged.text(&dump.path, &bodies_json(renderer));
    }
    let (width, height, channels, data): (usize, usize, usize, Vec<f32>) = if dump.kind
        == DumpKind::Ripples
    {
        let Some(f) = renderer.read_ripples() else {
            bail!("--dump ripples: the scene has no interactive water (water.dynamic = false)")
        };
        println!(
            "ripples: {n}×{n} cells of {c} m, cell (0, 0) centred at x = {x}, z = {z} m",
            n = f.cells,
            c = f.cell_size,
            x = f.origin[0] + 0.5 * f.cell_size,
            z = f.origin[1] + 0.5 * f.cell_size
        );
        (f.cells as usize, f.cells as usize, 1, f.heights)
    } else if dump.kind == DumpKind::Foam {
        let Some(f) = renderer.read_foam() else { bail!("--dump foam: the scene has no foam") };
        println!(
            "foam: {n}×{n} cells of {c} m, cell (0, 0) centred at x = {x}, z = {z} m; whitecap cover {w:.2}%",
            n = f.cells,
            c = f.cell_size,
            x = f.origin[0] + 0.5 * f.cell_size,
            z = f.origin[1] + 0.5 * f.cell_size,
            w = 100.0 * f.coverage()
        );
        (f.cells as usize, f.cells as usize, 1, f.amount)
    } else if dump.kind == DumpKind::Particles {
        let Some(ps) = renderer.read_particles() else {
            bail!("--dump particles: the scene has no bubbles or spray")
        };
        let bubbles = ps.iter().filter(|p| p.kind == BUBBLE).count();
        println!(
            "particles: {} alive ({bubbles} bubbles, {} spray); columns x y z vx vy vz radius kind (1 bubble, 2 spray)",
            ps.len(),
            ps.len() - bubbles
        );
        let data: Vec<f32> = ps
            .iter()
            .flat_map(|p| {
                let [x, y, z] = p.position;
                let [vx, vy, vz] = p.velocity;
                [x, y, z, vx, vy, vz, p.radius, p.kind as f32]
            })
            .collect();
        (8, ps.len(), 1, data)
    } else if dump.kind == DumpKind::Hdr {
        let Some((w, h, px)) = renderer.read_hdr() else {
            bail!("no frame has been rendered to dump")
        };
        (w as usize, h as usize, 3, px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect())
    } else if dump.kind == DumpKind::Caustics {
        let Some((m, map)) = renderer.read_caustics() else {
            bail!(
                "--dump caustics: the scene has no caustics (it needs caustics.method other than \"off\", a floor (floor.depth > 0) and the sun up)"
            )
        };
        (m as usize, m as usize, 1, map)
    } else if dump.kind == DumpKind::Godrays {
        let Some((w, h, px)) = renderer.read_godrays() else {
            bail!(
                "--dump godrays: this frame has no god-ray buffer: the camera is above the water and the air has no fog (from above, the water's shader draws the shafts itself; the buffer holds them for a camera under water or in fog)"
            )
        };
        (w as usize, h as usize, 3, px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect())
    } else if dump.kind == DumpKind::ObjectCaustics {
        let (k, map) = renderer.read_object_caustics();
        (k as usize, k as usize, 3, map.iter().flat_map(|p| [p[0], p[1], p[2]]).collect())
    } else {
        let (n, samples) = surface_grid(renderer);
        let (c, data): (usize, Vec<f32>) = match dump.kind {
            DumpKind::Height => (1, samples.iter().map(|s| s.displacement[1]).collect()),
            DumpKind::Displacement => (3, samples.iter().flat_map(|s| s.displacement).collect()),
            DumpKind::Normals => (3, samples.iter().flat_map(|s| s.normal().to_array()).collect()),
            DumpKind::Jacobian => (1, samples.iter().map(|s| s.jacobian()).collect()),
            DumpKind::Hdr
            | DumpKind::Caustics
            | DumpKind::Godrays
            | DumpKind::ObjectCaustics
            | DumpKind::Ripples
            | DumpKind::Bodies
            | DumpKind::Foam
            | DumpKind::Particles => unreachable!("handled above"),
        };
        (n, n, c, data)
    };
    staged.float(&dump.path, dump.format, &FloatImage { width, height, channels, data: &data })
}

#[cfg(test)]
mod tests {
    /// Every kind the help names parses, and the help names every kind.
    #[test]
    fn the_help_lists_every_dump_kind() {
        for kind in super::KINDS.split(", ") {
            let file = if kind == "bodies" { "b.json" } else { "x.npy" };
            super::parse(&format!("{kind}={file}")).unwrap_or_else(|e| panic!("{kind}: {e}"));
            assert!(super::HELP.contains(kind), "{kind}");
        }
        assert_eq!(super::KINDS.split(", ").count(), 12);
    }
}
