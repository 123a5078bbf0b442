//! `render --out clip.mp4|clip.webm`: frames piped to ffmpeg as raw RGBA
//! (the tone-mapped sRGB image, as the PNGs hold it), encoded H.264 (.mp4)
//! or VP9 (.webm) in yuv420p so that every player takes it. ffmpeg writes
//! a temporary sibling that is renamed into place only once it finished
//! cleanly: a missing, failing or killed ffmpeg leaves no file behind.
//! `HYDROLUX_FFMPEG` names another ffmpeg than the one on PATH.

use anyhow::{Context, Result, anyhow, bail};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    Mp4,
    Webm,
}

impl Container {
    /// The container `path`'s extension names, if it is a video.
    pub fn of(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "mp4" => Some(Container::Mp4),
            "webm" => Some(Container::Webm),
            _ => None,
        }
    }

    /// ffmpeg's encoder arguments for a constant quality or a bitrate.
    fn codec_args(self, quality: &Quality) -> Vec<String> {
        let mut args: Vec<String> = match self {
            // faststart: the index at the front, so a browser plays it while loading.
            Container::Mp4 => ["-c:v", "libx264", "-preset", "medium", "-movflags", "+faststart"]
                .map(String::from)
                .to_vec(),
            Container::Webm => ["-c:v", "libvpx-vp9", "-row-mt", "1"].map(String::from).to_vec(),
        };
        match quality {
            Quality::Crf(crf) => {
                args.extend(["-crf".into(), crf.to_string()]);
                if self == Container::Webm {
                    // VP9's constant-quality mode needs the bitrate cap off.
                    args.extend(["-b:v".into(), "0".into()]);
                }
            }
            Quality::Bitrate(rate) => args.extend(["-b:v".into(), rate.clone()]),
        }
        args.extend(["-pix_fmt".into(), "yuv420p".into()]);
        args
    }
}

/// Constant quality (CRF: 0 lossless … 51 worst) or a target bitrate.
#[derive(Clone, Debug, PartialEq)]
pub enum Quality {
    Crf(u32),
    Bitrate(String),
}

/// The default quality: visually clean water (x264's 18–23 is "good").
pub const DEFAULT_CRF: u32 = 20;

impl Quality {
    /// From `--crf` and `--bitrate` (at most one of them).
    pub fn from_args(crf: Option<u32>, bitrate: Option<&str>) -> Result<Self> {
        match (crf, bitrate) {
            (Some(_), Some(_)) => bail!("--crf and --bitrate: give one of them, not both"),
            (Some(c), None) if c > 51 => {
                bail!("--crf {c}: must be 0 (lossless) to 51 (smallest file)")
            }
            (Some(c), None) => Ok(Quality::Crf(c)),
            (None, Some(b)) => {
                let digits = b.strip_suffix(['k', 'K', 'm', 'M']).unwrap_or(b);
                let ok = !digits.is_empty()
                    && digits.chars().all(|c| c.is_ascii_digit())
                    && digits.parse::<u64>().is_ok_and(|n| n > 0);
                if !ok {
                    bail!(
                        "--bitrate `{b}`: expected bits per second, a positive whole number with an optional k or M (e.g. 8M, 2500k)"
                    );
                }
                Ok(Quality::Bitrate(b.to_string()))
            }
            (None, None) => Ok(Quality::Crf(DEFAULT_CRF)),
        }
    }
}

/// The ffmpeg to run: `HYDROLUX_FFMPEG`, else `ffmpeg` on PATH.
fn ffmpeg_program() -> Result<PathBuf> {
    let how = "install it (Debian/Ubuntu: apt-get install ffmpeg; macOS: brew install ffmpeg; \
               Windows: winget install ffmpeg) or write an image sequence (--out frame.png --frames N)";
    if let Some(p) = std::env::var_os("HYDROLUX_FFMPEG") {
        let p = PathBuf::from(p);
        if !p.is_file() {
            bail!("HYDROLUX_FFMPEG `{}` is not a file: video needs ffmpeg; {how}", p.display());
        }
        return Ok(p);
    }
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .flat_map(|dir| [dir.join("ffmpeg"), dir.join("ffmpeg.exe")])
            .find(|p| p.is_file())
    });
    found.ok_or_else(|| anyhow!("writing a video needs ffmpeg, which is not installed: {how}"))
}

/// How long ffmpeg may go without taking a frame, or without finishing
/// once the frames are all sent, before it is stopped (s; a stuck ffmpeg
/// once held the command forever). `HYDROLUX_FFMPEG_TIMEOUT` sets another.
pub const FFMPEG_TIMEOUT_S: f64 = 120.0;

fn ffmpeg_timeout() -> Result<Duration> {
    let Some(v) = std::env::var_os("HYDROLUX_FFMPEG_TIMEOUT") else {
        return Ok(Duration::from_secs_f64(FFMPEG_TIMEOUT_S));
    };
    let text = v.to_string_lossy();
    match text.trim().parse::<f64>() {
        Ok(s) if (0.1..=86_400.0).contains(&s) => Ok(Duration::from_secs_f64(s)),
        _ => bail!("HYDROLUX_FFMPEG_TIMEOUT `{text}`: must be 0.1 to 86400 seconds"),
    }
}

/// An ffmpeg process taking frames on its standard input, written by a
/// thread of their own so that an ffmpeg that stops reading is noticed.
pub struct VideoWriter {
    child: Arc<Mutex<Child>>,
    /// Frames to the writing thread (dropped: its stdin closes).
    frames_to: Option<mpsc::Sender<Vec<u8>>>,
    /// One message per frame written (or the write's error).
    written: mpsc::Receiver<std::io::Result<()>>,
    /// Frames sent and not yet written.
    in_flight: u32,
    /// What ffmpeg said (its errors), read on a thread so that it never blocks.
    stderr: Option<std::thread::JoinHandle<String>>,
    tmp: PathBuf,
    out: PathBuf,
    frame_bytes: usize,
    frames: u32,
    timeout: Duration,
    finished: bool,
}

impl VideoWriter {
    /// Check the size, find ffmpeg and start it writing `out`'s temporary.
    pub fn start(
        out: &Path,
        container: Container,
        size: (u32, u32),
        fps: f64,
        quality: &Quality,
    ) -> Result<Self> {
        if !size.0.is_multiple_of(2) || !size.1.is_multiple_of(2) {
            bail!(
                "{}×{}: video (yuv420p, what every player takes) needs an even width and height",
                size.0,
                size.1
            );
        }
        let timeout = ffmpeg_timeout()?;
        let program = ffmpeg_program()?;
        let name = out.file_name().and_then(|n| n.to_str()).unwrap_or("video");
        let dir = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let ext = if container == Container::Mp4 { "mp4" } else { "webm" };
        let tmp = dir.join(format!(".{name}.{}.tmp.{ext}", std::process::id()));
        let mut cmd = Command::new(&program);
        cmd.args(["-hide_banner", "-loglevel", "error", "-nostats", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{}x{}", size.0, size.1)])
            .args(["-framerate", &format!("{fps}"), "-i", "-"])
            .args(container.codec_args(quality))
            .args(["-r", &format!("{fps}")])
            .arg(&tmp)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        crate::interrupt::watch(&tmp);
        let mut child = cmd.spawn().map_err(|e| {
            crate::interrupt::forget(&tmp);
            anyhow!("cannot start ffmpeg (`{}`): {}", program.display(), spawn_reason(&program, &e))
        })?;
        let mut stdin = child.stdin.take().expect("piped");
        let mut err_pipe = child.stderr.take();
        let stderr = std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(p) = err_pipe.as_mut() {
                let _ = p.read_to_string(&mut s);
            }
            s
        });
        let (frames_to, frames_from) = mpsc::channel::<Vec<u8>>();
        let (written_to, written) = mpsc::channel();
        std::thread::spawn(move || {
            for frame in frames_from {
                let result = stdin.write_all(&frame);
                let failed = result.is_err();
                if written_to.send(result).is_err() || failed {
                    break;
                }
            }
            // stdin drops here: ffmpeg sees the end of the stream.
        });
        let child = Arc::new(Mutex::new(child));
        crate::interrupt::watch_child(&child);
        Ok(VideoWriter {
            child,
            frames_to: Some(frames_to),
            written,
            in_flight: 0,
            stderr: Some(stderr),
            tmp,
            out: out.to_path_buf(),
            frame_bytes: size.0 as usize * size.1 as usize * 4,
            frames: 0,
            timeout,
            finished: false,
        })
    }

    fn child(&self) -> std::sync::MutexGuard<'_, Child> {
        self.child.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Stop ffmpeg now (it is stuck or failed).
    fn kill(&self) {
        let mut c = self.child();
        let _ = c.kill();
        let _ = c.wait();
    }

    /// What ffmpeg said, as one line (after it stopped).
    fn ffmpeg_said(&mut self) -> String {
        let _ = self.child().wait();
        let text = self.stderr.take().and_then(|h| h.join().ok()).unwrap_or_default();
        let lines: Vec<&str> = text.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
        match lines.last() {
            Some(l) => format!(": {l}"),
            None => String::new(),
        }
    }

    /// Wait until at most `left` frames are still being written; a stuck
    /// or failed ffmpeg is stopped and reported.
    fn wait_written(&mut self, left: u32) -> Result<()> {
        while self.in_flight > left {
            let failure = match self.written.recv_timeout(self.timeout) {
                Ok(Ok(())) => {
                    self.in_flight -= 1;
                    continue;
                }
                Ok(Err(e)) => format!("stopped taking frames ({e})"),
                Err(mpsc::RecvTimeoutError::Disconnected) => "stopped taking frames".into(),
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    self.kill();
                    bail!(
                        "cannot write `{}`: ffmpeg took no frame for {:.0} s, so it was stopped (HYDROLUX_FFMPEG_TIMEOUT sets the limit)",
                        self.out.display(),
                        self.timeout.as_secs_f64()
                    );
                }
            };
            let status = self.child().try_wait().ok().flatten();
            let said = self.ffmpeg_said();
            let how = match status {
                Some(s) => format!("ffmpeg stopped ({s}){said}"),
                None => format!("ffmpeg {failure}{said}"),
            };
            bail!("cannot write `{}`: {how}", self.out.display());
        }
        Ok(())
    }

    /// Send one frame (tightly packed RGBA8, the size given to `start`):
    /// it is written while the next one renders.
    pub fn frame(&mut self, rgba: &[u8]) -> Result<()> {
        assert_eq!(rgba.len(), self.frame_bytes, "a frame of the video's size");
        self.wait_written(0)?;
        let sent = self.frames_to.as_ref().is_some_and(|t| t.send(rgba.to_vec()).is_ok());
        if !sent {
            self.in_flight += 1;
            return self.wait_written(0);
        }
        self.in_flight += 1;
        self.frames += 1;
        Ok(())
    }

    /// Close the stream, wait for ffmpeg (at most the timeout) and put the
    /// video in place.
    pub fn finish(mut self) -> Result<u32> {
        self.wait_written(0)?;
        drop(self.frames_to.take());
        let started = Instant::now();
        let status = loop {
            if let Some(s) = self.child().try_wait().context("waiting for ffmpeg")? {
                break s;
            }
            if started.elapsed() > self.timeout {
                self.kill();
                bail!(
                    "cannot write `{}`: ffmpeg did not finish within {:.0} s of the last frame, so it was stopped",
                    self.out.display(),
                    self.timeout.as_secs_f64()
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        if !status.success() {
            let said = self.ffmpeg_said();
            bail!("cannot write `{}`: ffmpeg failed ({status}){said}", self.out.display());
        }
        let written = std::fs::metadata(&self.tmp).map(|m| m.len()).unwrap_or(0);
        if written == 0 {
            bail!("cannot write `{}`: ffmpeg wrote nothing", self.out.display());
        }
        std::fs::rename(&self.tmp, &self.out)
            .with_context(|| format!("cannot write `{}`", self.out.display()))?;
        crate::interrupt::forget(&self.tmp);
        self.finished = true;
        Ok(self.frames)
    }
}

/// Why a program would not start, in the words that help: a script whose
/// `#!` interpreter is missing is "No such file or directory" to the OS.
fn spawn_reason(program: &Path, e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::NotFound && program.is_file() {
        let first = std::fs::read(program).ok().and_then(|b| {
            let line = b.split(|&c| c == b'\n').next()?.to_vec();
            String::from_utf8(line).ok()
        });
        if let Some(shebang) = first.as_deref().and_then(|l| l.strip_prefix("#!")) {
            return format!(
                "its interpreter `{}` (the script's #! line) does not exist",
                shebang.trim()
            );
        }
    }
    e.to_string()
}

impl Drop for VideoWriter {
    /// Unfinished (an error): stop ffmpeg, remove its file.
    fn drop(&mut self) {
        drop(self.frames_to.take());
        if !self.finished {
            self.kill();
            let _ = std::fs::remove_file(&self.tmp);
            crate::interrupt::forget(&self.tmp);
        }
        crate::interrupt::forget_child(&self.child);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn containers_and_quality_options() {
        assert_eq!(Container::of(Path::new("a/clip.MP4")), Some(Container::Mp4));
        assert_eq!(Container::of(Path::new("clip.webm")), Some(Container::Webm));
        assert_eq!(Container::of(Path::new("clip.png")), None);
        assert_eq!(Quality::from_args(None, None).unwrap(), Quality::Crf(DEFAULT_CRF));
        assert_eq!(Quality::from_args(Some(0), None).unwrap(), Quality::Crf(0));
        assert_eq!(Quality::from_args(None, Some("8M")).unwrap(), Quality::Bitrate("8M".into()));
        assert!(Quality::from_args(None, Some("2500k")).is_ok());
        for bad in ["", "M", "8MB", "-3M", "0", "1.5M", "8 M"] {
            let e = Quality::from_args(None, Some(bad)).unwrap_err().to_string();
            assert!(e.starts_with("--bitrate"), "{bad}: {e}");
        }
        assert!(
            Quality::from_args(Some(52), None).unwrap_err().to_string().contains("0 (lossless)")
        );
        assert!(Quality::from_args(Some(20), Some("8M")).is_err());
        let webm = Container::Webm.codec_args(&Quality::Crf(30)).join(" ");
        assert!(webm.contains("libvpx-vp9") && webm.contains("-crf 30 -b:v 0"), "{webm}");
    }
}
