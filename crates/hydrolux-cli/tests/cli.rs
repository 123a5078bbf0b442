//! The `hydrolux` binary as a user meets it: bad input gives one line naming
//! the bad value, exit status 1, no panic and no file; good input writes
//! valid files.

use std::path::PathBuf;
use std::process::Command;

fn hydrolux(args: &[&str], dir: &PathBuf) -> (i32, String) {
    hydrolux_env(args, dir, &[])
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hydrolux-cli-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn bad_input_is_one_line_exit_1_and_writes_nothing() {
    let dir = scratch("bad");
    std::fs::write(dir.join("broken.toml"), "[ocean]\nwind_speed = = 3\n").unwrap();
    std::fs::write(dir.join("no_mesh.toml"), "[[objects]]\nmesh = \"nope.obj\"\n").unwrap();
    std::fs::write(dir.join("bad.glb"), "not a glb").unwrap();
    std::fs::write(dir.join("ripples_only.toml"), "[ripples]\nresolution = 64\n").unwrap();
    std::fs::write(dir.join("bad_mesh.toml"), "[[objects]]\nmesh = \"bad.glb\"\n").unwrap();
    std::fs::write(
        dir.join("no_texture.toml"),
        "[[objects]]\n[objects.material]\ntexture = \"nope.png\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("refractive_in_water.toml"),
        "[[objects]]\nprimitive = \"sphere\"\nmaterial = { ior = 1.333 }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("unknown_builtin_mesh.toml"),
        "[water]\nmodel = \"none\"\n[[objects]]\nmesh = \"builtin:teapot\"\n",
    )
    .unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--scene", "nowhere"], "unknown scene `nowhere`"),
        (&["render", "--scene", "missing.toml"], "cannot read scene file missing.toml"),
        (&["render", "--scene", "broken.toml"], "broken.toml:2:"),
        (&["render", "--set", "ocean.wind_sped=3"], "did you mean `ocean.wind_speed`"),
        (&["render", "--set", "ocean.wind_speed=\"fast\""], "must be a number"),
        (&["render", "--set", "ocean.wind_speed=-1"], "`ocean.wind_speed` = -1 is out of range"),
        (&["render", "--set", "ocean.resolution=100"], "power of two"),
        (&["render", "--set", "camera.fov_y_deg=0"], "(0, 180)"),
        (
            &["render", "--width", "0"],
            "'0' for '--width <WIDTH>': must be a whole number from 1 to 16384 pixels",
        ),
        (&["render", "--out", "picture.jpg"], "must end in .png or .exr"),
        (&["render", "--out", "no/such/folder/x.png"], "does not exist"),
        (&["render", "--dump", "sky=x.npy"], "unknown buffer"),
        (
            &["render", "--frames", "0"],
            "'0' for '--frames <FRAMES>': must be a whole number from 1",
        ),
        (&["bench", "--frames", "0"], "must be a whole number from 1 to 1000000 frames"),
        // Each number in its option's own terms (not the integer type's),
        // and every time within the clock's range (1e30 once aborted).
        (
            &["render", "--time", "1e30"],
            "'1e30' for '--time <TIME>': must be a time from -1e9 to 1e9 s",
        ),
        (
            &["render", "--time", "-inf"],
            "'-inf' for '--time <TIME>': must be a time from -1e9 to 1e9 s",
        ),
        (&["render", "--time=nan"], "must be a time from -1e9 to 1e9 s"),
        (&["compare", "--time", "1e300"], "must be a time from -1e9 to 1e9 s"),
        (
            &["bench", "--start", "1e30"],
            "'1e30' for '--start <START>': must be a time from 0 to 1e9 s",
        ),
        (&["bench", "--start", "-1"], "must be a time from 0 to 1e9 s"),
        (
            &["render", "--frames", "3", "--fps", "1e-30"],
            "must be 0.001 to 10000 frames per second",
        ),
        (
            &["render", "--crf=-1", "--out", "v.mp4"],
            "must be a whole number from 0 (lossless) to 51",
        ),
        (&["render", "--height", "-1"], "must be a whole number from 1 to 16384 pixels"),
        (
            &["render", "--frames", "4000000000", "--fps", "1"],
            "--frames 4000000000 at --fps 1 from t = 0 s ends at t = 3.999999999e9 s: the latest time is 1e9 s",
        ),
        (&["render", "--scene", "no_mesh.toml"], "cannot load mesh nope.obj: no such file"),
        (&["render", "--scene", "bad_mesh.toml"], "cannot load mesh bad.glb"),
        (&["render", "--scene", "no_texture.toml"], "cannot load texture nope.png: no such file"),
        (&["render", "--set", "water.medium=swamp"], "turbid_harbor"),
        (&["render", "--view", "xray"], "render.view"),
        (&["render", "--dump", "caustics=c.npy"], "the scene has no caustics"),
        (
            &["render", "--scene", "lake", "--set", "water.model=none", "--dump", "caustics=c.npy"],
            "the scene has no caustics",
        ),
        (&["render", "--set", "caustics.photons=3"], "`caustics.photons` = 3 is out of range"),
        (&["render", "--set", "water.model=heightfield"], "water.heightfield"),
        (
            &["render", "--set", "water.model=heightfield", "--set", "water.heightfield=nope.npy"],
            "cannot load heightfield nope.npy: no such file",
        ),
        (
            &[
                "render",
                "--set",
                "water.model=heightfield",
                "--set",
                "water.heightfield=broken.toml",
            ],
            "cannot load heightfield broken.toml: not a .npy file",
        ),
        (&["render", "--set", "godrays.method=rays"], "godrays.method"),
        (&["render", "--set", "godrays.resolution=2"], "`godrays.resolution` = 2 is out of range"),
        (&["render", "--set", "godrays.photons=1"], "`godrays.photons` = 1 is out of range"),
        (&["render", "--set", "air.fog=-0.1"], "`air.fog` = -0.1 is out of range"),
        (
            &["render", "--scene", "refractive_in_water.toml"],
            "refractive objects need water.model = \"none\"",
        ),
        (&["render", "--scene", "unknown_builtin_mesh.toml"], "cannot load mesh builtin:teapot"),
        (&["render", "--set", "godrays.method=off", "--dump", "godrays=g.npy"], "god rays are off"),
        (&["render", "--dump", "object_caustics=o.npy"], "no refractive object"),
        (&["render", "--dump", "ripples=r.npy"], "no interactive water"),
        (&["render", "--dump", "bodies=b.json"], "no moving object"),
        (&["render", "--scene", "pool", "--dump", "bodies=b.npy"], "must end in .json"),
        (&["render", "--scene", "pool", "--set", "ripples.rate=7"], "ripples.rate"),
        (&["render", "--out", "x.exr", "--dump", "hdr=./x.exr"], "the same file as --out x.exr"),
        (&["render", "--dump", "particles=p.exr"], "which an EXR image cannot hold; write .npy"),
        (
            &["render", "--dump", "hdr=h.npy", "--dump", "height=h.npy"],
            "--dump height=h.npy: the same file as --dump hdr=h.npy",
        ),
        (&["render", "--width", "-1"], "'--width <WIDTH>'"),
        (&["render", "--widht", "3"], "a similar argument exists: '--width'"),
        (&["render", "--frames", "-2"], "'--frames <FRAMES>'"),
        (&["render", "--set", "air.fog_g=1"], "open interval (-1, 1)"),
        (&["render", "--set", "water.method=exact"], "water.method"),
        (&["compare", "--view", "normals"], "--view"),
        (
            &["compare", "--set", "water.model=none"],
            "--set water.model=none: the scene then has no water to compare",
        ),
        // Settings and views without effect are refused, naming both keys.
        (
            &["render", "--scene", "ripples_only.toml"],
            "`[ripples]` has no effect without `water.dynamic = true`",
        ),
        (
            &["render", "--set", "drops=[{time=1.0}]"],
            "`[[drops]]` has no effect without `water.dynamic = true`",
        ),
        (
            &["render", "--scene", "pool", "--set", "water.model=none"],
            "`water.dynamic = true` has no effect with `water.model = \"none\"`",
        ),
        (
            &["render", "--view", "ripples"],
            "\"ripples\" is out of range: it shows the interactive water, and the scene has none",
        ),
        (
            &["render", "--view", "foam", "--set", "whitewater.foam=false"],
            "it shows the foam, and the scene has none",
        ),
        (
            &["render", "--scene", "water_dragon", "--view", "fresnel"],
            "it is a view of the water, and the scene has none",
        ),
        (
            &["render", "--scene", "pool", "--set", "ripples.resolution=4294967296"],
            "bad --set `ripples.resolution=4294967296`: out of range: must be a power of two from 16 to 512",
        ),
        (
            &["render", "--set", "objects=[{rotation_deg=[1e30,0,0]}]"],
            "must be angles within ±1000000 degrees",
        ),
        (&["compare", "--width", "0"], "'0' for '--width <WIDTH>'"),
    ];
    for (args, want) in cases {
        let (code, err) = hydrolux(args, &dir);
        assert_eq!(code, 1, "{args:?}: exit {code}, stderr {err}");
        assert!(err.contains(want), "{args:?}: `{err}` lacks `{want}`");
        assert_eq!(err.lines().count(), 1, "{args:?}: not one line: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    let mut left: Vec<String> =
        left.into_iter().map(|f| f.to_string_lossy().into_owned()).collect();
    left.sort();
    assert_eq!(
        left,
        [
            "bad.glb",
            "bad_mesh.toml",
            "broken.toml",
            "no_mesh.toml",
            "no_texture.toml",
            "refractive_in_water.toml",
            "ripples_only.toml",
            "unknown_builtin_mesh.toml"
        ],
        "files were written: {left:?}"
    );
}

/// The latest frames of a four-billion-frame sequence, and the latest time
/// allowed, render at once: each simulated from its own origin, under
/// twice the scene's memory before it (once they stepped from t = 0).
#[test]
fn the_latest_frames_render_in_a_bounded_time() {
    let dir = scratch("late");
    let small = ["--width", "16", "--height", "16", "--set", "whitewater.memory=2"];
    let mut args = vec!["render", "--out", "f.png", "--frames", "4000000000"];
    args.extend(["--frame-range", "3999999998-3999999999"]);
    args.extend(small);
    let (code, err) = hydrolux(&args, &dir);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("f_3999999998.png").is_file() && dir.join("f_3999999999.png").is_file());
    let mut args = vec!["render", "--out", "late.png", "--time", "1e9"];
    args.extend(small);
    let (code, err) = hydrolux(&args, &dir);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("late.png").is_file());
}

#[test]
fn a_negative_time_is_a_time_in_either_spelling() {
    let dir = scratch("negative-time");
    for args in [&["--time", "-1.5"][..], &["--time=-1.5"][..]] {
        let mut all = vec!["render", "--width", "16", "--height", "16", "--out", "t.png"];
        all.extend_from_slice(args);
        let (code, err) = hydrolux(&all, &dir);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(dir.join("t.png").is_file());
    }
}

#[test]
fn render_writes_png_exr_and_npy_dumps() {
    let dir = scratch("good");
    let (code, err) = hydrolux(
        &[
            "render",
            "--width",
            "48",
            "--height",
            "32",
            "--set",
            "ocean.resolution=64",
            "--out",
            "a.png",
            "--dump",
            "height=h.npy",
            "--dump",
            "jacobian=j.exr",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let png = std::fs::read(dir.join("a.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let npy = std::fs::read(dir.join("h.npy")).unwrap();
    let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    assert!(std::str::from_utf8(&npy[10..10 + hlen]).unwrap().contains("'shape': (64, 64)"));
    assert_eq!(npy.len(), 10 + hlen + 64 * 64 * 4);
    let heights: Vec<f32> = npy[10 + hlen..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert!(heights.iter().any(|h| h.abs() > 0.05), "the sea is flat");
    assert_eq!(&std::fs::read(dir.join("j.exr")).unwrap()[..4], &[0x76, 0x2f, 0x31, 0x01]);
    let (code, err) = hydrolux(
        &[
            "render",
            "--width",
            "32",
            "--height",
            "16",
            "--out",
            "s.png",
            "--frames",
            "2",
            "--set",
            "water.model=flat",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("s_0000.png").exists() && dir.join("s_0001.png").exists());
    // Outputs are what was asked: an EXR at the low tier (which renders at
    // half size) has the requested size; no particles alive is an NPY of
    // zero rows.
    let args = ["render", "--width", "32", "--height", "16", "--out", "low.exr", "--time", "0"];
    let more = ["--set", "render.quality=low", "--dump", "particles=p.npy"];
    let all: Vec<&str> = args.iter().chain(&more).copied().collect();
    let (code, err) = hydrolux(&all, &dir);
    assert_eq!(code, 0, "{err}");
    let exr = exr::prelude::read_first_rgba_layer_from_file(
        dir.join("low.exr"),
        |_, _| (),
        |_, _, _: (f32, f32, f32, f32)| (),
    )
    .expect("a readable EXR");
    assert_eq!(exr.layer_data.size.0, 32);
    assert_eq!(exr.layer_data.size.1, 16);
    let npy = std::fs::read(dir.join("p.npy")).unwrap();
    let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    let header = std::str::from_utf8(&npy[10..10 + hlen]).unwrap();
    assert!(header.contains("'shape': (0, 8)") && npy.len() == 10 + hlen, "{header}");
}

#[test]
fn compare_writes_both_frames_and_the_error_with_its_statistics() {
    let dir = scratch("compare");
    let out = Command::new(env!("CARGO_BIN_EXE_hydrolux"))
        .args(["compare", "--scene", "lake", "--width", "64", "--height", "36", "--out", "c"])
        .current_dir(&dir)
        .output()
        .expect("runs");
    let (stdout, stderr) =
        (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    for f in ["c-projective.png", "c-raytrace.png", "c-error.png"] {
        assert_eq!(&std::fs::read(dir.join(f)).unwrap()[1..4], b"PNG", "{f}");
    }
    // The water is found and measured: a share of the frame, a finite mean.
    let water = stdout.lines().find(|l| l.starts_with("water ")).expect("a water line");
    let pixels: u32 = water.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!(pixels > 64 * 36 / 5, "{water}");
    assert!(stdout.contains("reflection-dominated") && stdout.contains("refraction-dominated"));
    let (p, t) =
        (std::fs::read(dir.join("c-projective.png")), std::fs::read(dir.join("c-raytrace.png")));
    assert_ne!(p.unwrap(), t.unwrap(), "the two methods drew the same image");
}

#[test]
fn scenes_with_mesh_files_and_every_debug_view_render() {
    let dir = scratch("views");
    // An OBJ without normals, referred to relative to the scene file.
    std::fs::write(
        dir.join("tetra.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 1 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let scene = "[floor]\ndepth = 3\n[[objects]]\nmesh = \"tetra.obj\"\nposition = [0, -0.5, -8]\nscale = [2, 2, 2]\n";
    std::fs::write(dir.join("mesh.toml"), scene).unwrap();
    let mut images = Vec::new();
    for view in [
        "final",
        "reflection",
        "refraction",
        "depth",
        "normals",
        "shadow",
        "medium",
        "caustics",
        "fresnel",
    ] {
        let out = format!("{view}.png");
        let (code, err) = hydrolux(
            &[
                "render",
                "--scene",
                "mesh.toml",
                "--view",
                view,
                "--width",
                "64",
                "--height",
                "36",
                "--out",
                &out,
            ],
            &dir,
        );
        assert_eq!(code, 0, "{view}: {err}");
        images.push(std::fs::read(dir.join(&out)).unwrap());
    }
    for i in 0..images.len() {
        for j in i + 1..images.len() {
            assert_ne!(images[i], images[j], "debug views {i} and {j} are the same image");
        }
    }
}

fn write_png(
    path: &std::path::Path,
    w: u32,
    h: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(color);
    enc.set_depth(depth);
    enc.write_header().unwrap().write_image_data(data).unwrap();
}

#[test]
fn heightmap_terrain_and_textured_objects_render() {
    let dir = scratch("assets");
    // A 16-bit ramp heightmap (big-endian samples) and a red texture.
    let mut ramp = Vec::new();
    for _y in 0..8 {
        for x in 0..8u16 {
            ramp.extend_from_slice(&(x * 9362).to_be_bytes());
        }
    }
    write_png(
        &dir.join("ramp.png"),
        8,
        8,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        &ramp,
    );
    let red: Vec<u8> = (0..16).flat_map(|_| [220u8, 10, 10]).collect();
    write_png(&dir.join("red.png"), 4, 4, png::ColorType::Rgb, png::BitDepth::Eight, &red);
    let scene = r#"
[camera]
position = [0, 4, 12]
look_at = [0, 3, 0]
[sun]
elevation_deg = 30
azimuth_deg = 90
[floor]
terrain = "heightmap"
heightmap = "ramp.png"
depth = 6
relief = 10
size = 60
resolution = 32
[[objects]]
primitive = "plane"
position = [0, 3, 0]
rotation_deg = [90, 0, 0]
scale = [6, 1, 6]
[objects.material]
albedo = [1, 1, 1]
texture = "red.png"
"#;
    std::fs::write(dir.join("assets.toml"), scene).unwrap();
    let (code, err) = hydrolux(
        &["render", "--scene", "assets.toml", "--width", "48", "--height", "32", "--out", "a.png"],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let decoder =
        png::Decoder::new(std::io::BufReader::new(std::fs::File::open(dir.join("a.png")).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bpp = info.line_size / info.width as usize;
    let centre = &buf[16 * info.line_size + 24 * bpp..][..3];
    assert!(
        centre[0] > 2 * centre[1] && centre[0] > 2 * centre[2],
        "the textured plane is not red: {centre:?}"
    );
    // Zero wind is a flat sea, not a crash.
    let (code, err) = hydrolux(
        &[
            "render",
            "--set",
            "ocean.wind_speed=0",
            "--width",
            "16",
            "--height",
            "16",
            "--out",
            "calm.png",
        ],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
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
    let shape = |file: &str| {
        let npy = std::fs::read(dir.join(file)).unwrap();
        let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
        let header = std::str::from_utf8(&npy[10..10 + hlen]).unwrap().to_string();
        let values: Vec<f32> = npy[10 + hlen..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        (header, values)
    };
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

/// Like [`hydrolux`] with extra environment variables (None removes one).
fn hydrolux_env(args: &[&str], dir: &PathBuf, env: &[(&str, Option<&str>)]) -> (i32, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hydrolux"));
    cmd.args(args).current_dir(dir).env("XDG_RUNTIME_DIR", std::env::temp_dir());
    for (k, v) in env {
        match v {
            Some(v) => cmd.env(k, v),
            None => cmd.env_remove(k),
        };
    }
    let out = cmd.output().expect("run hydrolux");
    let stderr = String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
        .collect::<Vec<_>>()
        .join("\n");
    (out.status.code().unwrap_or(-1), stderr)
}

fn files_in(dir: &PathBuf) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn hostile_input_is_refused_plainly() {
    let dir = scratch("hostile");
    let w = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
    // Input that never ends, is not a file, or is too large.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.toml")).unwrap();
        std::os::unix::fs::symlink("/dev/urandom", dir.join("random.npy")).unwrap();
        std::os::unix::fs::symlink("loop_b.obj", dir.join("loop_a.obj")).unwrap();
        std::os::unix::fs::symlink("loop_a.obj", dir.join("loop_b.obj")).unwrap();
    }
    let fifo =
        Command::new("mkfifo").arg(dir.join("fifo.toml")).status().is_ok_and(|s| s.success());
    std::fs::create_dir_all(dir.join("folder.obj")).unwrap();
    let object = "[[objects]]\nprimitive = \"sphere\"\nposition = [1, 2, 3]\n";
    w("huge.toml", object.repeat((5 << 20) / object.len() + 1).as_bytes());
    // Meshes, arrays and images that are corrupt.
    w("binary.obj", &[0xff, 0xfe, 0x00, 0x01]);
    w("bad_face.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    w("garbage.gltf", b"{ this is not json");
    w(
        "needs_bin.gltf",
        br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"geometry.bin"}]}"#,
    );
    w("garbage.npy", b"\x93NUMPY\x01\x00\x08\x00garbage!");
    w("text.png", b"not an image at all");
    let mesh = |name: &str| format!("[water]\nmodel = \"none\"\n[[objects]]\nmesh = \"{name}\"\n");
    for (scene, m) in [
        ("m_folder", "folder.obj"),
        ("m_loop", "loop_a.obj"),
        ("m_binary", "binary.obj"),
        ("m_face", "bad_face.obj"),
        ("m_garbage", "garbage.gltf"),
        ("m_bin", "needs_bin.gltf"),
    ] {
        w(&format!("{scene}.toml"), mesh(m).as_bytes());
    }
    w("texture.toml", b"[[objects]]\n[objects.material]\ntexture = \"text.png\"\n");
    w("empty_mesh.toml", b"[[objects]]\nmesh = \"\"\n");
    w("torus.toml", b"[[objects]]\n[[objects]]\nprimitive = \"torus\"\n");
    w("far.toml", b"[[objects]]\nposition = [1e30, 0, 0]\n");
    w("inf_scale.toml", b"[[objects]]\nscale = [inf, 1, 1]\n");
    w("seed.toml", b"[ocean]\nseed = 18446744073709551615\n");
    w("many.toml", "[[objects]]\n".repeat(300_000).as_bytes());
    w("pure_and_custom.toml", b"[water]\nmedium = \"pure\"\nabsorption = [1, 1, 1]\n");
    let heightfield = |file: &str| {
        vec!["render", "--set", "water.model=heightfield", "--set", "water.heightfield=FILE"]
            .into_iter()
            .map(|a| {
                if a == "water.heightfield=FILE" {
                    format!("water.heightfield={file}")
                } else {
                    a.into()
                }
            })
            .collect::<Vec<String>>()
    };
    let long_number = format!("ocean.wind_speed={}", "9".repeat(400));
    let mut cases: Vec<(Vec<String>, &str)> = vec![
        (heightfield("random.npy"), "not a regular file (a device, pipe or socket)"),
        (heightfield("garbage.npy"), "not a NumPy header dictionary"),
        (heightfield("folder.obj"), "it is a folder, not a file"),
        (
            vec!["render".into(), "--scene".into(), "huge.toml".into()],
            "more than the 4.0 MB allowed",
        ),
        (vec!["render".into(), "--set".into(), long_number], "a number TOML cannot hold"),
        (
            vec!["render".into(), "--set".into(), "ocean.seed=18446744073709551615".into()],
            "9223372036854775807",
        ),
        (
            vec!["render".into(), "--set".into(), "ocean.resolution=4294967296".into()],
            "bad --set `ocean.resolution=4294967296`: out of range: must be a power of two",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.position=[inf,0,0]".into()],
            "`camera.position`",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.position=[1e30,0,0]".into()],
            "`camera.position`",
        ),
        (
            vec!["render".into(), "--set".into(), "camera.look_at=[nan,0,0]".into()],
            "must be finite",
        ),
        (vec!["render".into(), "--set".into(), "camera.up=[nan,1,0]".into()], "`camera.up`"),
        (
            vec![
                "render".into(),
                "--scene".into(),
                "pool".into(),
                "--set".into(),
                "water.absorption=[1,1,1]".into(),
                "--set".into(),
                "water.medium=pure".into(),
            ],
            "`water.absorption` must be given only with water.medium = \"custom\"",
        ),
        (
            vec![
                "render".into(),
                "--set".into(),
                "water.model=none".into(),
                "--dump".into(),
                "height=h.npy".into(),
            ],
            "no water surface",
        ),
        (vec!["render".into(), "--dump".into(), "godrays=g.npy".into()], "no god-ray buffer"),
        (vec!["render".into(), "--frame-range".into(), "5-2".into()], "FIRST ≤ LAST"),
        (
            vec![
                "render".into(),
                "--frames".into(),
                "3".into(),
                "--frame-range".into(),
                "1-3".into(),
            ],
            "numbered 0 to 2",
        ),
    ];
    for (scene, want) in [
        ("zero.toml", "not a regular file"),
        ("m_folder.toml", "cannot load mesh folder.obj: it is a folder, not a file"),
        ("m_loop.toml", "a loop of symbolic links"),
        ("m_binary.toml", "not text"),
        ("m_face.toml", "line 4: a face refers to vertex 9, of 3 defined before it"),
        ("m_garbage.toml", "not valid glTF JSON"),
        (
            "m_bin.toml",
            "cannot load mesh buffer geometry.bin: no such file (used by needs_bin.gltf)",
        ),
        ("texture.toml", "cannot load texture text.png: it is not a PNG or JPEG image"),
        ("empty_mesh.toml", "`objects[0].mesh`"),
        ("torus.toml", "`objects[1].primitive` must be one of"),
        ("far.toml", "`objects[0].position`"),
        ("inf_scale.toml", "`objects[0].scale`"),
        ("seed.toml", "`ocean.seed`: u64 value was too large"),
        ("many.toml", "(line 1025 starts object 1025) is out of range: at most 1024 objects"),
        ("pure_and_custom.toml", "`water.absorption`"),
    ] {
        cases.push((vec!["render".into(), "--scene".into(), scene.into()], want));
    }
    if fifo {
        cases.push((
            vec!["render".into(), "--scene".into(), "fifo.toml".into()],
            "not a regular file",
        ));
    }
    let before = files_in(&dir);
    for (args, want) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let t0 = std::time::Instant::now();
        let (code, err) = hydrolux(&args, &dir);
        let short: Vec<&str> =
            args.iter().map(|a| if a.len() > 60 { &a[..60] } else { a }).collect();
        assert_eq!(code, 1, "{short:?}: exit {code}, stderr {err}");
        assert!(err.contains(want), "{short:?}: `{err}` lacks `{want}`");
        assert_eq!(err.lines().count(), 1, "{short:?}: not one line: {err}");
        assert!(!err.contains("panicked") && !err.contains(".rs:"), "{short:?}: {err}");
        // Refused at once, not after reading an endless stream.
        assert!(t0.elapsed().as_secs() < 60, "{short:?} took {:?}", t0.elapsed());
    }
    assert_eq!(files_in(&dir), before, "a refused command wrote a file");
    // The environment: a backend that is no backend, and no display.
    let (code, err) = hydrolux_env(&["info"], &dir, &[("WGPU_BACKEND", Some("bogus"))]);
    assert!(code == 1 && err.contains("WGPU_BACKEND=\"bogus\"") && err.contains("vulkan"), "{err}");
    let no_display = [("DISPLAY", None), ("WAYLAND_DISPLAY", None), ("WAYLAND_SOCKET", None)];
    let (code, err) = hydrolux_env(&["view"], &dir, &no_display);
    assert!(code == 1 && err.contains("cannot open a window") && !err.contains(".rs:"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn outputs_are_all_or_nothing_and_sequences_resume() {
    let dir = scratch("atomic");
    // The image renders, the god-ray dump cannot (camera above water): neither appears.
    let args =
        ["render", "--width", "16", "--height", "12", "--out", "o.png", "--dump", "godrays=g.npy"];
    let (code, err) = hydrolux(&args, &dir);
    assert_eq!(code, 1, "{err}");
    assert!(files_in(&dir).is_empty(), "left behind: {:?}", files_in(&dir));
    // A sequence whose second frame cannot be written: the first stays,
    // the message says how to resume, nothing half-written is left.
    std::fs::create_dir_all(dir.join("seq_0001.png/blocker")).unwrap();
    let seq = [
        "render",
        "--width",
        "16",
        "--height",
        "12",
        "--frames",
        "3",
        "--out",
        "seq.png",
        "--dump",
        "hdr=h.npy",
    ];
    let (code, err) = hydrolux(&seq, &dir);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("frame 1: cannot write `seq_0001.png`")
            && err.contains("1 frame written (seq_0000.png)")
            && err.contains("resume with --frame-range 1-2"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(files_in(&dir), ["h_0000.npy", "seq_0000.png", "seq_0001.png"]);
    // Resume where it stopped.
    std::fs::remove_dir_all(dir.join("seq_0001.png")).unwrap();
    let mut resume = seq.to_vec();
    resume.extend(["--frame-range", "1-2"]);
    let (code, err) = hydrolux(&resume, &dir);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        files_in(&dir),
        ["h_0000.npy", "h_0001.npy", "h_0002.npy", "seq_0000.png", "seq_0001.png", "seq_0002.png"]
    );
}

#[test]
fn the_first_command_works_on_a_machine_with_only_opengl() {
    // No Vulkan driver to be found (as on a Debian machine without
    // mesa-vulkan-drivers): wgpu falls back to OpenGL, and the README's
    // first command still writes its image.
    let dir = scratch("gl-only");
    let no_vulkan = [
        ("VK_ICD_FILENAMES", Some("/nonexistent.json")),
        ("VK_DRIVER_FILES", Some("/nonexistent.json")),
    ];
    let (code, err) = hydrolux_env(
        &["render", "--out", "ocean.png", "--width", "64", "--height", "36"],
        &dir,
        &no_vulkan,
    );
    assert_eq!(code, 0, "{err}");
    let png = std::fs::read(dir.join("ocean.png")).expect("written");
    assert!(png.starts_with(b"\x89PNG"), "a PNG");
    // `info` says which adapter and how Hydrolux adapted to it.
    let out = Command::new(env!("CARGO_BIN_EXE_hydrolux"))
        .arg("info")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .envs(no_vulkan.iter().map(|(k, v)| (k, v.unwrap())))
        .output()
        .expect("run hydrolux");
    let info = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{info}");
    assert!(info.contains(", Gl)") && info.contains("all run"), "{info}");
    assert!(info.contains("adapted to this device") && info.contains("stencil copied"), "{info}");
}

fn ffprobe(path: &std::path::Path, entries: &str) -> String {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-count_frames", "-show_entries"])
        .arg(format!("stream={entries}"))
        .args(["-of", "default=nw=1"])
        .arg(path)
        .output()
        .expect("ffprobe (CI installs ffmpeg)");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn videos_are_playable_and_written_whole_or_not_at_all() {
    let dir = scratch("video");
    let args = ["render", "--scene", "calm", "--width", "64", "--height", "36", "--frames", "5"];
    let with = |extra: &[&str]| -> Vec<String> {
        args.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |a: &[String], env: &[(&str, Option<&str>)]| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        hydrolux_env(&a, &dir, env)
    };
    // H.264 in MP4 and VP9 in WebM, every frame, the size asked for.
    let (code, err) = run(&with(&["--out", "clip.mp4"]), &[]);
    assert_eq!(code, 0, "{err}");
    let probe = ffprobe(&dir.join("clip.mp4"), "codec_name,width,height,pix_fmt,nb_read_frames");
    for want in ["codec_name=h264", "width=64", "height=36", "pix_fmt=yuv420p", "nb_read_frames=5"]
    {
        assert!(probe.contains(want), "{want} in {probe}");
    }
    let (code, err) = run(&with(&["--out", "clip.webm", "--bitrate", "500k"]), &[]);
    assert_eq!(code, 0, "{err}");
    let probe = ffprobe(&dir.join("clip.webm"), "codec_name,nb_read_frames");
    assert!(probe.contains("codec_name=vp9") && probe.contains("nb_read_frames=5"), "{probe}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm"]);

    // No ffmpeg: one line saying how to get it, nothing written.
    let empty = scratch("video-missing");
    for env in [
        vec![("HYDROLUX_FFMPEG", None), ("PATH", Some("/nonexistent"))],
        vec![("HYDROLUX_FFMPEG", Some("/nonexistent/ffmpeg"))],
    ] {
        let a: Vec<String> = with(&["--out", "none.mp4"]);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let (code, err) = hydrolux_env(&a, &empty, &env);
        assert!(
            code == 1 && err.contains("ffmpeg") && err.contains("apt-get install ffmpeg"),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(files_in(&empty).is_empty());
    }
    // ffmpeg failing mid-stream (it wrote part of its file, then quit).
    let script = dir.join("failing-ffmpeg.sh");
    std::fs::write(
        &script,
        "#!/bin/sh\nfor last; do :; done\necho partial > \"$last\"\nhead -c 20000 > /dev/null\n\
         echo 'Conversion failed!' >&2\nexit 1\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    let failing = [("HYDROLUX_FFMPEG", Some(script.to_str().unwrap()))];
    let (code, err) = run(&with(&["--out", "broken.mp4"]), &failing);
    assert!(
        code == 1
            && err.contains("cannot write `broken.mp4`")
            && err.contains("Conversion failed!")
            && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm", "failing-ffmpeg.sh"], "no partial file");

    // Sizes and options a video cannot take.
    for (extra, want) in [
        (vec!["--out", "x.png", "--crf", "20"], "--crf and --bitrate are for videos"),
        (vec!["--out", "x.mp4", "--crf", "60"], "0 (lossless) to 51"),
        (vec!["--out", "x.mp4", "--bitrate", "fast"], "--bitrate `fast`"),
        (vec!["--out", "x.mp4", "--crf", "20", "--bitrate", "8M"], "not both"),
        (vec!["--out", "x.gif"], "or .mp4 or .webm for a video"),
    ] {
        let (code, err) = run(&with(&extra), &[]);
        assert!(code == 1 && err.contains(want), "{extra:?}: {err}");
    }
    let odd = ["render", "--width", "63", "--height", "36", "--out", "odd.mp4"];
    let (code, err) = hydrolux(&odd, &dir);
    assert!(code == 1 && err.contains("63×36") && err.contains("even width and height"), "{err}");
    assert_eq!(files_in(&dir), ["clip.mp4", "clip.webm", "failing-ffmpeg.sh"]);
}

/// An ffmpeg that stops reading is stopped after the timeout and named;
/// one whose `#!` interpreter is missing is said so; SIGINT and SIGTERM
/// mid-video remove its temporary and end by the signal.
#[cfg(unix)]
#[test]
fn a_stuck_ffmpeg_and_interruptions_leave_nothing() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("interrupt");
    let script = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
        p.to_str().unwrap().to_string()
    };
    let stuck = script("stuck.sh", "#!/bin/sh\nexec sleep 600\n");
    let lost = script("lost.sh", "#!/nonexistent/interpreter\n");
    let small = ["render", "--width", "64", "--height", "36", "--set", "whitewater.memory=1"];
    let args = |extra: &[&str]| -> Vec<String> {
        small.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    // 40 frames of 9 KB fill a pipe ffmpeg never reads.
    let a = args(&["--frames", "40", "--out", "v.mp4"]);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let env = [("HYDROLUX_FFMPEG", Some(stuck.as_str())), ("HYDROLUX_FFMPEG_TIMEOUT", Some("1"))];
    let (code, err) = hydrolux_env(&a, &dir, &env);
    assert!(code == 1 && err.contains("ffmpeg took no frame for 1 s, so it was stopped"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    let (code, err) = hydrolux_env(&a, &dir, &[("HYDROLUX_FFMPEG", Some(lost.as_str()))]);
    assert!(code == 1 && err.contains("interpreter `/nonexistent/interpreter`"), "{err}");
    assert_eq!(files_in(&dir), ["lost.sh", "stuck.sh"]);
    // Interrupted once its temporary video exists.
    for (signal, number) in [("INT", 2), ("TERM", 15)] {
        let a = args(&["--frames", "100000", "--out", "long.mp4"]);
        let child = Command::new(env!("CARGO_BIN_EXE_hydrolux"))
            .args(&a)
            .current_dir(&dir)
            .env("XDG_RUNTIME_DIR", std::env::temp_dir())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let started = std::time::Instant::now();
        while !files_in(&dir).iter().any(|f| f.ends_with(".tmp.mp4")) {
            assert!(started.elapsed().as_secs() < 120, "no temporary video appeared");
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        std::thread::sleep(std::time::Duration::from_millis(500));
        let status = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.signal(), Some(number), "SIG{signal}: {:?} {err}", out.status);
        assert!(err.contains(&format!("interrupted (SIG{signal})")), "{err}");
        assert_eq!(files_in(&dir), ["lost.sh", "stuck.sh"], "SIG{signal} left files");
    }
}

#[test]
fn slices_of_a_sequence_render_the_same_frames_as_the_whole() {
    // Split between machines (a job array): frames are the same bytes
    // whichever slice renders them, the simulation state being reached
    // deterministically from t = 0.
    let dir = scratch("slices");
    let base = ["render", "--scene", "pool", "--width", "48", "--height", "32", "--frames", "4"];
    let whole: Vec<&str> = base.iter().copied().chain(["--out", "whole.png"]).collect();
    assert_eq!(hydrolux(&whole, &dir).0, 0);
    for range in ["0-1", "2..3"] {
        let slice: Vec<&str> =
            base.iter().copied().chain(["--out", "part.png", "--frame-range", range]).collect();
        let (code, err) = hydrolux(&slice, &dir);
        assert_eq!(code, 0, "{err}");
    }
    for i in 0..4 {
        let a = std::fs::read(dir.join(format!("whole_{i:04}.png"))).unwrap();
        let b = std::fs::read(dir.join(format!("part_{i:04}.png"))).unwrap();
        assert!(a == b, "frame {i} differs between the whole sequence and its slice");
    }
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

/// `render` without `--time` and `render.quality` draws the scene as
/// written at its `start_time` (the gallery's command is what a user
/// types): the pool at 2 s, at `high` (its frame at the output's size)
/// even on a software adapter; `--time` and `render.quality` still win.
#[test]
fn render_draws_the_scene_as_written_at_its_start_time() {
    let dir = scratch("defaults");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            "pool",
            "--set",
            "caustics.method=\"off\"",
            "--width",
            "32",
            "--height",
            "18",
            "--dump",
            "bodies=b.json",
            "--dump",
            "hdr=h.npy",
            "--out",
            "p.png",
        ];
        args.extend_from_slice(extra);
        let (code, err) = hydrolux(&args, &dir);
        assert_eq!(code, 0, "{err}");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("b.json")).unwrap()).unwrap();
        let npy = std::fs::read(dir.join("h.npy")).unwrap();
        let hlen = u16::from_le_bytes([npy[8], npy[9]]) as usize;
        let header = std::str::from_utf8(&npy[10..10 + hlen]).unwrap().to_string();
        (json["time"].as_f64().unwrap(), header)
    };
    let (time, header) = run(&[]);
    assert_eq!(time, 2.0, "the pool opens at its start_time");
    assert!(header.contains("'shape': (18, 32, 3)"), "drawn at the output's size: {header}");
    let (time, header) = run(&["--time", "0.5", "--set", "render.quality=\"low\""]);
    assert_eq!(time, 0.5);
    assert!(header.contains("'shape': (9, 16, 3)"), "low draws at half: {header}");
    // The help names every dump kind.
    let out = Command::new(env!("CARGO_BIN_EXE_hydrolux")).args(["render", "--help"]).output();
    let help = String::from_utf8_lossy(&out.expect("run hydrolux").stdout).to_string();
    for kind in ["ripples", "bodies", "foam", "particles", "object_caustics"] {
        assert!(help.contains(kind), "render --help lacks {kind}");
    }
}
