//! The web page in a real browser: Debian's chromium, headless, WebGPU on
//! the CPU (SwiftShader). The page is built with web/build.sh (wasm32 and
//! wasm-bindgen, as a person builds it), served from this test on the
//! loopback address, and driven by web/test/browser.mjs (playwright-core):
//! every built-in scene loads, draws frames without a console error, and
//! reports its frame time; its image, both as the page shows it (a
//! screenshot through egui and the canvas) and as it rendered it (read
//! back from its texture), matches the native render of the same scene,
//! camera and time on this machine's default adapter with the golden-image
//! metric and tolerances (mean ΔE ≤ 1.5, 99th percentile ≤ 8). Then every
//! scene runs unpaused for 3 s of simulated time with the pointer dragged
//! across it, without a console error. A browser without WebGPU gets a
//! message in the page saying why the page cannot run.
//!
//! Needs chromium, node and npm (CI installs them; see .ci/run).

#[path = "../../hydrolux/tests/golden/mod.rs"]
mod golden;

use hydrolux::core::scene::{BUILTIN_SCENES, Scene};
use hydrolux::headless::HeadlessTarget;
use hydrolux::{GpuContext, Renderer};
use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::Command;

const W: u32 = 160;
const H: u32 = 90;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn run(cmd: &mut Command, what: &str) {
    let status = cmd.status().unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    assert!(status.success(), "{what} failed ({status})");
}

/// Serve the files under `root` on 127.0.0.1 (a free port) from a thread;
/// the page's URL.
fn serve(root: PathBuf) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    let port = listener.local_addr().unwrap().port();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let root = root.clone();
            std::thread::spawn(move || {
                let mut reader = BufReader::new(&stream);
                let mut line = String::new();
                if reader.read_line(&mut line).is_err() {
                    return;
                }
                // Skip the headers.
                let mut header = String::new();
                while reader.read_line(&mut header).is_ok_and(|n| n > 2) {
                    header.clear();
                }
                let path = line.split_whitespace().nth(1).unwrap_or("/");
                let path = path.split('?').next().unwrap_or("/").trim_start_matches('/');
                let file = root.join(if path.is_empty() { "index.html" } else { path });
                let (status, body, kind) = match std::fs::read(&file) {
                    Ok(b) if !path.contains("..") => ("200 OK", b, content_type(&file)),
                    // No favicon: an empty answer, not a 404 in the console.
                    _ if path == "favicon.ico" => ("204 No Content", Vec::new(), "image/x-icon"),
                    _ => ("404 Not Found", Vec::new(), "text/plain"),
                };
                let mut stream = &stream;
                let _ = write!(
                    stream,
                    "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\n\
                     Connection: close\r\n\r\n",
                    body.len()
                );
                let _ = stream.write_all(&body);
            });
        }
    });
    format!("http://127.0.0.1:{port}/index.html")
}

fn content_type(p: &Path) -> &'static str {
    match p.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html",
        Some("js") => "text/javascript",
        Some("wasm") => "application/wasm",
        _ => "application/octet-stream",
    }
}

fn read_png(path: &Path) -> Vec<u8> {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(BufReader::new(file)).read_info().expect("a png");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("png data");
    assert_eq!((info.width, info.height), (W, H), "{}", path.display());
    buf.truncate(info.buffer_size());
    match info.color_type {
        png::ColorType::Rgba => buf,
        png::ColorType::Rgb => buf.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        other => panic!("{}: {other:?}", path.display()),
    }
}

/// The scene frame whose image the page reads back (`capture=5` in
/// web/test/browser.mjs).
const CAPTURED_FRAME: u64 = 5;

#[test]
fn every_scene_runs_in_headless_chromium_and_looks_as_it_does_natively() {
    let repo = repo();
    run(Command::new("bash").arg(repo.join("web/build.sh")), "web/build.sh");
    let test_dir = repo.join("web/test");
    if !test_dir.join("node_modules/playwright-core").exists() {
        run(
            Command::new("npm").args(["ci", "--no-audit", "--no-fund"]).current_dir(&test_dir),
            "npm ci (web/test)",
        );
    }
    let out = repo.join("target/browser-test");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let url = serve(repo.join("target/web"));
    let scenes: Vec<&str> = BUILTIN_SCENES.iter().map(|b| b.name).collect();
    // Scenes with the volumetric liquid play a shorter while (browser.mjs).
    let liquid: Vec<&str> = scenes
        .iter()
        .copied()
        .filter(|name| Scene::load(name, &[]).is_ok_and(|s| s.fluid.enabled()))
        .collect();
    let mut node = Command::new("node");
    node.env("LIQUID_SCENES", liquid.join(","));
    node.arg(test_dir.join("browser.mjs"))
        .arg(&url)
        .arg(&out)
        .args([W.to_string(), H.to_string()])
        .args(&scenes);
    run(&mut node, "node web/test/browser.mjs (chromium)");

    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    let entries = report.as_array().expect("one entry per scene");
    assert_eq!(entries.len(), scenes.len(), "every scene ran");
    let ctx = GpuContext::headless().expect("a native adapter");
    let mut failures = Vec::new();
    for entry in entries {
        let name = entry["scene"].as_str().unwrap();
        let state = &entry["state"];
        let errors: Vec<&str> =
            entry["errors"].as_array().unwrap().iter().filter_map(|e| e.as_str()).collect();
        let frames = state["frames"].as_f64().unwrap_or(0.0);
        let frame_ms = state["frame_ms"].as_f64().unwrap_or(f64::NAN);
        eprintln!(
            "{name:14} in chromium: {frames} frames, {frame_ms:.0} ms a frame, adapter {}",
            state["adapter"]
        );
        if !errors.is_empty() || state["error"].is_string() {
            failures.push(format!("{name}: {errors:?} {}", state["error"]));
            continue;
        }
        // Run unpaused with the pointer dragged across it (web/test/browser.mjs).
        let played = &entry["played"];
        let played_errors: Vec<&str> = played["errors"]
            .as_array()
            .map(|a| a.iter().filter_map(|e| e.as_str()).collect())
            .unwrap_or_default();
        let played_time = played["time"].as_f64().unwrap_or(0.0);
        let advanced = played["advanced"].as_f64().unwrap_or(0.0);
        let wanted = played["wanted"].as_f64().unwrap_or(f64::INFINITY);
        eprintln!(
            "{name:14} running: {advanced:.1} s simulated, to t = {played_time:.1} s, in {} frames, {:.0} s",
            played["frames"],
            played["seconds"].as_f64().unwrap_or(f64::NAN)
        );
        if !played_errors.is_empty() || played["error"].is_string() || advanced < wanted {
            failures.push(format!(
                "{name} running: {played_errors:?} {} (ran {advanced} s of the {wanted} s asked)",
                played["error"]
            ));
        }
        assert!(frames >= 5.0 && frame_ms.is_finite() && frame_ms > 0.0, "{name}: {state}");
        assert!(state["adapter"].as_str().unwrap_or("").contains("WebGpu"), "{name}: {state}");
        // The native render of the same scene, camera and time, as many
        // frames in: paused, the page goes on drawing its jittered frames
        // and averages them (render.antialias), the image read back at the
        // scene's fifth frame (`capture=5`), the page's screenshot at about
        // `scene_frames`.
        let scene = Scene::load(name, &[]).unwrap();
        let mut r = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)
            .expect("native renderer");
        let target = HeadlessTarget::new(&ctx.device, (W, H));
        let mut drawn = 0u64;
        let mut native_after = |frames: u64| {
            while drawn + 1 < frames {
                target.submit(&mut r, scene.camera(), 0.0).expect("native frame");
                drawn += 1;
            }
            drawn += 1;
            target.render(&mut r, scene.camera(), 0.0).expect("native frame")
        };
        let captured = native_after(CAPTURED_FRAME);
        let page_frames = state["scene_frames"].as_f64().unwrap_or(0.0) as u64;
        let shown = native_after(page_frames.max(CAPTURED_FRAME + 1));
        for (what, file, native) in [
            ("page", format!("{name}.png"), &shown),
            ("image", format!("{name}.capture.png"), &captured),
        ] {
            let web = read_png(&out.join(&file));
            let (mean, p99) = golden::mean_and_p99(W, H, &web, native);
            eprintln!("{name:14} {what:5} vs native: mean ΔE {mean:.2}, 99th percentile {p99:.2}");
            if !golden::within_tolerance(mean, p99) {
                golden::write_failure(&format!("web-{name}-{what}"), W, H, &web, native);
                failures.push(format!("{name} ({what}): mean ΔE {mean:.2}, p99 {p99:.2}"));
            }
        }
    }
    assert!(failures.is_empty(), "in the browser: {}", failures.join("; "));

    let dropped: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("dropped.json")).unwrap()).unwrap();
    eprintln!("a scene dropped onto the page: {dropped}");
    assert!(
        dropped["shown"].as_bool() == Some(true)
            && dropped["errors"].as_array().is_some_and(|e| e.is_empty()),
        "a scene's TOML dropped onto the page opens: {dropped}"
    );

    let without: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("no-webgpu.json")).unwrap()).unwrap();
    let said = without["status"].as_str().unwrap_or("");
    eprintln!("without WebGPU the page says: {said}");
    assert!(
        said.starts_with("Hydrolux cannot run") || said.starts_with("Hydrolux could not start"),
        "the page must say why it cannot run: {said}"
    );
}
