//! `hydrolux render`: headless images, numbered image sequences and videos
//! (through ffmpeg, `video.rs`).

use crate::SceneArgs;
use crate::dumps::{self, Dump};
use crate::output::{self, FloatImage, Format, Staged};
use crate::video::{Container, Quality, VideoWriter};
use anyhow::{Result, bail};
use clap::Args;
use hydrolux::Renderer;
use hydrolux::core::clock::MAX_TIME_S;
use hydrolux::headless::HeadlessTarget;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output: .png (8-bit sRGB, tone-mapped), .exr (linear float, pre-exposed radiance), or a video of all the frames, .mp4 (H.264) or .webm (VP9), encoded by ffmpeg.
    #[arg(long, default_value = "hydrolux.png")]
    pub out: PathBuf,
    #[command(flatten)]
    pub size: crate::SizeArgs,
    /// Simulation time of the (first) frame, seconds [default: the scene's start_time].
    /// From -1e9 to 1e9 s; any time costs at most twice the scene's memory
    /// of simulation (`hydrolux scenes`).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::time)]
    pub time: Option<f64>,
    /// Number of frames; more than one writes OUT_0000.png, OUT_0001.png, …
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::values::frame_count)]
    pub frames: u32,
    /// Render only frames FIRST to LAST (inclusive, counted from 0; FIRST..LAST is the same) of the
    /// sequence, numbered and timed as in the whole sequence: to resume one
    /// that stopped, or to split it between machines.
    #[arg(long, value_name = "FIRST-LAST")]
    pub frame_range: Option<String>,
    /// Frames per second of simulated time in a sequence (and of the video).
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true, value_parser = crate::values::fps)]
    pub fps: f64,
    /// Video quality: constant rate factor, 0 (lossless) to 51 (smallest file); default 20.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::crf)]
    pub crf: Option<u32>,
    /// Video bitrate instead of --crf, bits per second with an optional k or M (e.g. 8M).
    #[arg(long)]
    pub bitrate: Option<String>,
    /// Anti-aliasing samples per written frame (with `render.antialias = "temporal"`, the
    /// default): the frame is drawn this many times at its time with sub-pixel offsets and
    /// averaged, each frame on its own (a slice of a sequence renders the frames of the
    /// whole). 1 writes the frame as drawn. From 1 to 64.
    #[arg(long, default_value_t = 8, allow_hyphen_values = true, value_parser = crate::values::samples)]
    pub samples: u32,
    #[arg(long = "dump", value_name = "KIND=FILE", help = crate::dumps::help())]
    pub dump: Vec<String>,
}

/// `ocean.png`, frame 3 of a sequence → `ocean_0003.png`.
pub fn numbered(path: &Path, frame: u32, frames: u32) -> PathBuf {
    if frames <= 1 {
        return path.to_path_buf();
    }
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("png");
    path.with_file_name(format!("{stem}_{frame:04}.{ext}"))
}

pub fn run(a: RenderArgs) -> Result<()> {
    a.size.check()?;
    let container = Container::of(&a.out);
    let format = match container {
        Some(_) => Format::Png,
        None => output::format_of(&a.out, &[Format::Png, Format::Exr], "--out")
            .map_err(|e| anyhow::anyhow!("{e}, or .mp4 or .webm for a video"))?,
    };
    let quality = Quality::from_args(a.crf, a.bitrate.as_deref())?;
    if container.is_none() && (a.crf.is_some() || a.bitrate.is_some()) {
        bail!("--crf and --bitrate are for videos: --out must end in .mp4 or .webm");
    }
    let dumps: Vec<Dump> = a.dump.iter().map(|d| dumps::parse(d)).collect::<Result<_>>()?;
    output::check_writable(&a.out)?;
    for d in &dumps {
        output::check_writable(&d.path)?;
    }
    // Two outputs to one file: the second would silently replace the first.
    let mut outputs = vec![(format!("--out {}", a.out.display()), output::same_file_key(&a.out))];
    for (d, text) in dumps.iter().zip(&a.dump) {
        let key = output::same_file_key(&d.path);
        if let Some((first, _)) = outputs.iter().find(|(_, k)| *k == key) {
            bail!("--dump {text}: the same file as {first}; give each output its own file");
        }
        outputs.push((format!("--dump {text}"), key));
    }
    let scene = a.scene.load_offline()?;
    let start = a.time.unwrap_or(scene.start_time);
    for d in &dumps {
        dumps::check(d, &scene)?;
    }
    // The frames to render, and how many the sequence's numbering counts.
    let frames_given = a.frames != 1;
    let (range, numbering) = match &a.frame_range {
        Some(text) => {
            let range = parse_range(text, a.frames, frames_given)?;
            (range.clone(), a.frames.max(range.end).max(2))
        }
        None => (0..a.frames, a.frames),
    };
    // The last frame's time must be a time too.
    let last = start + (numbering - 1) as f64 / a.fps;
    if last.abs() > MAX_TIME_S {
        bail!(
            "--frames {numbering} at --fps {} from t = {start} s ends at t = {last:e} s: the latest time is {MAX_TIME_S:e} s",
            a.fps
        );
    }
    let ctx = crate::headless_context()?;
    let max = hydrolux::Capabilities::of(&ctx.device).max_texture_2d;
    if a.size.width > max || a.size.height > max {
        bail!(
            "{}×{} is larger than this GPU allows ({max} pixels per side)",
            a.size.width,
            a.size.height
        );
    }
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, hydrolux::headless::FORMAT, &scene)?;
    // Every frame from its time's own origin: a slice renders the frames of the whole.
    renderer.set_exact_time(true);
    renderer.set_catch_up_progress(Some(catch_up_bar(start)));
    let target = HeadlessTarget::new(&ctx.device, (a.size.width, a.size.height));
    // A video holds every frame of the range in one file, written whole or not at all.
    let mut video = match container {
        Some(c) => {
            Some(VideoWriter::start(&a.out, c, (a.size.width, a.size.height), a.fps, &quality)?)
        }
        None => None,
    };
    let count = range.end - range.start;
    let progress = (count > 1).then(|| {
        let bar = indicatif::ProgressBar::new(count as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} frames  {elapsed} (eta {eta})",
            )
            .expect("valid template"),
        );
        bar
    });
    for i in range.clone() {
        // Each frame's outputs (image and dumps) appear together or not at all.
        let written = frame(
            &a,
            start,
            &dumps,
            format,
            &scene,
            &mut renderer,
            &target,
            i,
            numbering,
            &mut video,
        );
        if let Err(e) = written {
            if let Some(bar) = &progress {
                bar.abandon();
            }
            if numbering == 1 {
                return Err(e);
            }
            if video.is_some() {
                bail!("frame {i}: {e:#}; no video written (it is written whole or not at all)");
            }
            let done = i - range.start;
            let resume = format!("resume with --frame-range {i}-{}", range.end - 1);
            let so_far = match done {
                0 => "no frame written".to_string(),
                1 => format!(
                    "1 frame written ({})",
                    numbered(&a.out, range.start, numbering).display()
                ),
                n => format!(
                    "{n} frames written ({} … {})",
                    numbered(&a.out, range.start, numbering).display(),
                    numbered(&a.out, i - 1, numbering).display()
                ),
            };
            bail!("frame {i}: {e:#}; {so_far}; {resume}");
        }
        if let Some(bar) = &progress {
            bar.inc(1);
        }
    }
    if let Some(bar) = progress {
        bar.finish();
    }
    if let Some(v) = video {
        let n = v.finish()?;
        eprintln!(
            "wrote {} ({n} frame{}, {}×{}, {} fps)",
            a.out.display(),
            if n == 1 { "" } else { "s" },
            a.size.width,
            a.size.height,
            a.fps
        );
        return Ok(());
    }
    if numbering == 1 {
        eprintln!("wrote {}", a.out.display());
    } else {
        eprintln!(
            "wrote {count} frame{}: {} … {}",
            if count == 1 { "" } else { "s" },
            numbered(&a.out, range.start, numbering).display(),
            numbered(&a.out, range.end - 1, numbering).display()
        );
    }
    Ok(())
}

/// A progress bar for a long catch-up of the simulations (a late time):
/// shown once one takes more than a batch of steps.
pub fn catch_up_bar(start: f64) -> Box<dyn FnMut(u64, u64)> {
    let mut bar: Option<indicatif::ProgressBar> = None;
    Box::new(move |done, total| {
        let b = bar.get_or_insert_with(|| {
            let b = indicatif::ProgressBar::new(total);
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{msg} {bar:30} {pos}/{len} steps  {elapsed} (eta {eta})",
                )
                .expect("valid template"),
            );
            b.set_message(format!(
                "simulating {:.0} s of the scene's past near t = {start} s",
                total as f64 * hydrolux::renderer::SIMULATION_STEP_S
            ));
            b
        });
        b.set_length(total);
        b.set_position(done.min(total));
        if done >= total {
            b.finish_and_clear();
            bar = None;
        }
    })
}

/// Render frame `i` and publish its image and dumps together.
#[allow(clippy::too_many_arguments)]
fn frame(
    a: &RenderArgs,
    start: f64,
    dumps: &[Dump],
    format: Format,
    scene: &hydrolux::core::scene::Scene,
    renderer: &mut Renderer,
    target: &HeadlessTarget,
    i: u32,
    numbering: u32,
    video: &mut Option<VideoWriter>,
) -> Result<()> {
    let time = start + i as f64 / a.fps;
    let render = &scene.render;
    let antialiased = render.antialias == hydrolux::core::scene::Antialias::Temporal
        && render.view == hydrolux::core::scene::DebugView::Final;
    if antialiased && a.samples > 1 {
        // The frame's own samples, whatever was drawn before it.
        renderer.restart_antialiasing();
        for _ in 1..a.samples {
            target.submit(renderer, scene.camera(), time)?;
        }
    }
    let pixels = target.render(renderer, scene.camera(), time)?;
    let out = numbered(&a.out, i, numbering);
    let mut staged = Staged::new();
    match (format, video.as_mut()) {
        (_, Some(v)) => v.frame(&pixels)?,
        (Format::Png, None) => staged.png(&out, a.size.width, a.size.height, &pixels)?,
        (_, None) => {
            let Some((w, h, px)) = renderer.read_hdr() else { bail!("no frame rendered") };
            let data: Vec<f32> = px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
            // A quality tier renders smaller: the image has the size asked
            // for, upscaled as the PNG is (`--dump hdr` keeps the buffer's).
            let size = (a.size.width as usize, a.size.height as usize);
            let data = output::resize_rgb(&data, (w as usize, h as usize), size);
            let image = FloatImage { width: size.0, height: size.1, channels: 3, data: &data };
            staged.exr(&out, &image)?;
        }
    }
    for d in dumps {
        let path = numbered(&d.path, i, numbering);
        dumps::write(&Dump { path, ..d.clone() }, renderer, &mut staged)?;
    }
    staged.publish()?;
    Ok(())
}

/// `--frame-range FIRST-LAST` → FIRST..LAST+1, checked against `--frames`
/// when that was given.
fn parse_range(text: &str, frames: u32, frames_given: bool) -> Result<std::ops::Range<u32>> {
    let bad = || {
        anyhow::anyhow!(
            "--frame-range `{text}`: expected FIRST-LAST (or FIRST..LAST), two frame numbers from 0 with FIRST ≤ LAST, both rendered (e.g. 42-99)"
        )
    };
    let (first, last) = text.split_once("..").or_else(|| text.split_once('-')).ok_or_else(bad)?;
    let first: u32 = first.trim().parse().map_err(|_| bad())?;
    let last: u32 = last.trim().parse().map_err(|_| bad())?;
    if first > last || last == u32::MAX {
        return Err(bad());
    }
    if frames_given && last >= frames {
        bail!(
            "--frame-range {text}: the sequence has {frames} frames (--frames), numbered 0 to {}",
            frames - 1
        );
    }
    Ok(first..last + 1)
}
