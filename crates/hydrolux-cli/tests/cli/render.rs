//! Rendering: images, sequences, scenes, and what they write.

use super::*;

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
fn compare_draws_the_liquid_four_ways_against_the_finest_mesh() {
    // A coarse dam break a twentieth of a second in (the default for a
    // scene with a liquid and no surface water).
    let dir = scratch("compare_surfaces");
    let out = Command::new(env!("CARGO_BIN_EXE_hydrolux"))
        .args(["compare", "--scene", "dam_break", "--set", "fluid.resolution=16", "--time", "0.05"])
        .args(["--width", "64", "--height", "36", "--out", "s"])
        .current_dir(&dir)
        .output()
        .expect("runs");
    let (stdout, stderr) =
        (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    let mut means = Vec::new();
    for s in ["marching_cubes", "screen_mesh", "screen_space", "points"] {
        for f in [format!("s-{s}.png"), format!("s-{s}-error.png")] {
            assert_eq!(&std::fs::read(dir.join(&f)).unwrap()[1..4], b"PNG", "{f}");
        }
        let line = stdout.lines().find(|l| l.starts_with(s)).expect("a line per surface");
        let words: Vec<&str> = line.split_whitespace().collect();
        let pixels: u32 = words[1].parse().unwrap();
        assert!(pixels > 20, "{line}");
        let mean = words.iter().position(|w| *w == "mean").expect("a mean");
        means.push(words[mean + 1].parse::<f32>().unwrap());
    }
    // Each differs from the reference, and the surfaces less than points.
    assert!(means.iter().all(|m| m.is_finite() && *m > 0.0), "{stdout}");
    assert!(means[..3].iter().all(|m| *m < means[3]), "{stdout}");
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
