//! `--dump`: each buffer's shape and content.

use super::*;

/// An `.npy` file of f32: its header and values.
fn npy_f32(path: &std::path::Path) -> (String, Vec<f32>) {
    let npy = std::fs::read(path).unwrap();
    let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    let header = std::str::from_utf8(&npy[10..10 + hlen]).unwrap().to_string();
    let values: Vec<f32> = npy[10 + hlen..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    (header, values)
}

#[test]
fn caustics_dump_is_an_m_by_m_float_grid() {
    let dir = scratch("caustics");
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "pool",
            "--set",
            "caustics.map_resolution=32",
            // Still water (the pool opens at 2 s, its ripples under way).
            "--time",
            "0",
            "--width",
            "16",
            "--height",
            "16",
            "--dump",
            "caustics=c.npy",
            "--out",
            "p.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let npy = std::fs::read(dir.join("c.npy")).unwrap();
    let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    assert!(std::str::from_utf8(&npy[10..10 + hlen]).unwrap().contains("'shape': (32, 32)"));
    let values: Vec<f32> = npy[10 + hlen..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let mean = values.iter().sum::<f32>() / values.len() as f32;
    // The pool's sun is 58° up: flat water would give T·sin 58° ≈ 0.83 everywhere.
    assert!((mean - 0.83).abs() < 0.02, "mean floor irradiance {mean}");
}

#[test]
fn god_ray_and_object_caustic_dumps_have_their_shapes() {
    let dir = scratch("volume");
    let shape = |file: &str| npy_f32(&dir.join(file));
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "underwater",
            "--width",
            "32",
            "--height",
            "20",
            "--set",
            "godrays.photons=64",
            // The buffer is a fraction of the frame, which lower tiers draw smaller.
            "--set",
            "render.quality=\"high\"",
            "--dump",
            "godrays=g.npy",
            "--out",
            "u.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let (header, values) = shape("g.npy");
    assert!(header.contains("'shape': (10, 16, 3)"), "{header}");
    assert!(
        values.iter().all(|v| v.is_finite() && *v >= 0.0) && values.iter().any(|v| *v > 0.0),
        "the buffer holds light"
    );
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "water_dragon",
            "--width",
            "24",
            "--height",
            "16",
            "--set",
            "godrays.object_resolution=128",
            "--dump",
            "object_caustics=o.npy",
            "--out",
            "d.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let (header, values) = shape("o.npy");
    assert!(header.contains("'shape': (128, 128, 3)"), "{header}");
    let peak = values.iter().cloned().fold(0.0f32, f32::max);
    assert!(peak > 1.0, "the water bunny focuses sunlight somewhere: peak {peak}");
}

#[test]
fn ripples_and_bodies_dumps_hold_the_water_and_the_ball() {
    let dir = scratch("ripples");
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "pool",
            "--set",
            "ripples.resolution=32",
            "--set",
            "caustics.method=\"off\"",
            "--time",
            "1.0",
            "--width",
            "16",
            "--height",
            "16",
            "--dump",
            "ripples=r.npy",
            "--dump",
            "bodies=b.json",
            "--dump",
            "foam=f.npy",
            "--dump",
            "particles=q.npy",
            "--out",
            "p.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    // The stones' splashes (at 0.2 and 0.8 s): bubbles still rising, foam.
    let floats = |name: &str| -> (String, Vec<f32>) {
        let npy = std::fs::read(dir.join(name)).unwrap();
        let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
        let header = std::str::from_utf8(&npy[10..10 + hlen]).unwrap().to_string();
        let values = npy[10 + hlen..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        (header, values)
    };
    let (header, particles) = floats("q.npy");
    assert!(header.contains(", 8)"), "{header}");
    let kinds: Vec<f32> = particles.chunks_exact(8).map(|p| p[7]).collect();
    assert!(kinds.contains(&1.0), "bubbles: {kinds:?}");
    assert!(kinds.iter().all(|&k| k == 1.0 || k == 2.0), "kinds: {kinds:?}");
    assert!(particles.iter().all(|v| v.is_finite()));
    let (_, foam) = floats("f.npy");
    let most = foam.iter().fold(0.0f32, |m, &f| m.max(f));
    assert!(most > 0.5, "foam where the stones fell: most {most}");
    let npy = std::fs::read(dir.join("r.npy")).unwrap();
    let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    assert!(std::str::from_utf8(&npy[10..10 + hlen]).unwrap().contains("'shape': (32, 32)"));
    let heights: Vec<f32> = npy[10 + hlen..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let peak = heights.iter().fold(0.0f32, |m, h| m.max(h.abs()));
    assert!(peak > 1e-3 && peak < 0.5, "the ball's splash: peak {peak} m");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("b.json")).unwrap()).unwrap();
    assert_eq!(json["time"], 1.0);
    let ball = &json["bodies"][0];
    assert_eq!(ball["name"], "sphere");
    assert_eq!(ball["position"].as_array().unwrap().len(), 3);
    assert_eq!(ball["orientation"].as_array().unwrap().len(), 4);
    assert!(ball["submerged_volume"].as_f64().unwrap() > 0.0);
}

#[test]
fn fluid_dumps_hold_the_particles_and_the_cells() {
    // The dam break on a coarse grid (16 cells along the tank, 7.5 cm), a
    // twentieth of a second in: every particle a row, every cell its
    // liquid fraction, pressure and divergence.
    let dir = scratch("fluid");
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "dam_break",
            "--set",
            "fluid.resolution=16",
            "--time",
            "0.05",
            "--width",
            "16",
            "--height",
            "16",
            "--dump",
            "fluid=f.npy",
            "--dump",
            "fluid_grid=g.npy",
            "--set",
            "fluid.surface_resolution=32",
            "--dump",
            "fluid_mesh=m.npy",
            "--out",
            "d.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let read = |file: &str| npy_f32(&dir.join(file));
    // 16 × 12 × 4 cells; the column holds 3 × 7 × 4 cells' centres, 8 each.
    let (header, particles) = read("f.npy");
    assert!(header.contains("'shape': (672, 6)"), "{header}");
    assert!(particles.iter().all(|v| v.is_finite()));
    assert!(particles.chunks(6).any(|p| p[4] < -0.1), "the column is falling");
    let (header, cells) = read("g.npy");
    assert!(header.contains("'shape': (48, 16, 3)"), "{header}");
    let liquid: f32 = cells.chunks(3).map(|c| c[0]).sum();
    assert!((liquid - 84.0).abs() <= 12.0, "liquid cells {liquid}");
    let deepest = cells.chunks(3).map(|c| c[1]).fold(0.0f32, f32::max);
    // Below a 0.5 m column ρ·g·h ≈ 4.9 kPa; a collapsing one less.
    assert!(deepest > 1000.0 && deepest < 5500.0, "pressure {deepest} Pa");
    // The surface the frame drew: a row per triangle, closed around the
    // column's 672 particles of (3.75 cm)³ (by the divergence theorem; the
    // coarse grid and the smoothing round its edges), and carried through
    // the tank's closed walls and floor that the column touches (−x, −y,
    // ±z; `fluid::surface::Walls`), each by at most two of the surface
    // grid's 3.75-cm cells: no less than the particles' volume, no more
    // than their 22.5 × 52.5 × 30 cm block so widened.
    let (header, triangles) = read("m.npy");
    assert!(header.contains(", 9)"), "{header}");
    assert!(triangles.len() > 100 * 9 && triangles.iter().all(|v| v.is_finite()));
    let volume: f64 = triangles
        .chunks(9)
        .map(|t| {
            let [a, b, c] = [0, 3, 6].map(|i| [t[i], t[i + 1], t[i + 2]].map(f64::from));
            let cross =
                [b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]];
            (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
        })
        .sum();
    let particles = 672.0 * 0.0375f64.powi(3);
    let cell = 1.2 / 32.0;
    let carried = (0.225 + 2.0 * cell) * (0.525 + 2.0 * cell) * (0.3 + 4.0 * cell);
    assert!(
        volume > 0.9 * particles && volume < carried,
        "encloses {volume} m³, particles {particles} m³, carried block {carried} m³"
    );
}

#[test]
fn the_screen_mesh_dump_is_the_liquid_the_camera_sees() {
    // The same coarse dam break drawn by a screen-space mesh: the dump is
    // the mesh the frame drew, every corner on the liquid's side of the
    // camera and within the tank (plus a particle radius).
    let dir = scratch("screen_mesh");
    let (code, err) = hydrolux(
        &[
            "render",
            "--scene",
            "dam_break",
            "--set",
            "fluid.resolution=16",
            "--set",
            "fluid.surface=screen_mesh",
            "--time",
            "0.05",
            "--width",
            "64",
            "--height",
            "36",
            "--dump",
            "fluid_mesh=m.npy",
            "--out",
            "d.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let (header, triangles) = npy_f32(&dir.join("m.npy"));
    assert!(header.contains(", 9)"), "{header}");
    assert!(triangles.len() > 20 * 9, "{} triangles", triangles.len() / 9);
    // The tank (x −0.6…0.6, y 0…0.9) and a particle radius (3.75 cm).
    for p in triangles.chunks(3) {
        assert!(p[0].abs() < 0.65 && p[1] > -0.05 && p[1] < 0.95, "corner {p:?}");
    }
}

#[test]
fn the_screen_space_dump_is_the_liquid_as_the_frame_filtered_it() {
    // The coarse dam break by screen-space fluid rendering: the dump is
    // the frame's filtered depth and thickness, the liquid where the
    // camera (about 2 m off) sees the tank, and nothing elsewhere.
    let dir = scratch("screen_space");
    let args = [
        "render",
        "--scene",
        "dam_break",
        "--set",
        "fluid.resolution=16",
        "--set",
        "fluid.surface=screen_space",
        "--time",
        "0.05",
        "--width",
        "64",
        "--height",
        "36",
        "--dump",
        "fluid_screen_space=s.npy",
        "--out",
        "d.png",
    ];
    let (code, err) = hydrolux(&args, &dir);
    assert_eq!(code, 0, "{err}");
    let (header, maps) = npy_f32(&dir.join("s.npy"));
    assert!(header.contains("(36, 64, 2)"), "{header}");
    let covered: Vec<&[f32]> = maps.chunks(2).filter(|p| p[0] > 0.0).collect();
    assert!(covered.len() > 20, "{} pixels", covered.len());
    for p in &covered {
        assert!(p[0] > 1.2 && p[0] < 3.0, "depth {} m", p[0]);
        assert!(p[1] >= 0.0 && p[1] < 1.0, "thickness {} m", p[1]);
    }
    assert!(covered.iter().any(|p| p[1] > 0.05), "no thick liquid");
    // Asked of a liquid drawn another way: one line, nothing written.
    let mut other = args.to_vec();
    other[6] = "fluid.surface=marching_cubes";
    other[14] = "fluid_screen_space=t.npy";
    let (code, err) = hydrolux(&other, &dir);
    assert_ne!(code, 0);
    assert!(err.contains("screen_space"), "{err}");
    assert!(!dir.join("t.npy").exists());
}
