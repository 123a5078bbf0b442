//! Writing files: PNG (8-bit sRGB), EXR (linear float) and NumPy `.npy`.
//! Every output of one command (or of one frame of a sequence) is written
//! to a temporary sibling first and published (renamed into place) only
//! when all of them were written: a failed or interrupted run never leaves
//! a half-written file, nor some outputs without the others. Errors name
//! the file.

use anyhow::{Context, Result, anyhow, bail};
use exr::prelude::*;
use std::path::{Path, PathBuf};
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
    Npy,
    Json,
}

/// The format of `path` from its extension, if it is one of `allowed`.
pub fn format_of(path: &Path, allowed: &[Format], what: &str) -> Result<Format> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let f = match ext.as_deref() {
        Some("png") => Some(Format::Png),
        Some("exr") => Some(Format::Exr),
        Some("npy") => Some(Format::Npy),
        Some("json") => Some(Format::Json),
        _ => None,
    };
    match f {
        Some(f) if allowed.contains(&f) => Ok(f),
        _ => {
            let names: Vec<&str> = allowed
                .iter()
                .map(|f| match f {
                    Format::Png => ".png",
                    Format::Exr => ".exr",
                    Format::Npy => ".npy",
                    Format::Json => ".json",
                })
                .collect();
            bail!("{what} `{}` must end in {}", path.display(), names.join(" or "))
        }
    }
}

/// What identifies the file `path` names, whatever the spelling
/// (`./x.npy`, `dir/../x.npy`): its folder made canonical, and its name.
pub fn same_file_key(path: &Path) -> PathBuf {
    let dir = parent_dir(path);
    let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
    dir.join(path.file_name().unwrap_or_default())
}

/// Fail early if `path` cannot be written (missing folder, not a folder, read-only).
pub fn check_writable(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        bail!("cannot write `{}`: folder `{}` does not exist", path.display(), dir.display());
    }
    if path.is_dir() {
        bail!("cannot write `{}`: it is a folder", path.display());
    }
    let probe = dir.join(format!(".hydrolux-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").with_context(|| {
        format!("cannot write `{}`: folder `{}` is not writable", path.display(), dir.display())
    })?;
    let _ = std::fs::remove_file(probe);
    Ok(())
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Why writing failed, in a user's words ("no space left on device", not
/// "… (os error 28)").
fn io_reason(e: &std::io::Error) -> String {
    match e.raw_os_error() {
        Some(28) => "no space left on device".into(),
        Some(122) => "disk quota exceeded".into(),
        Some(30) => "the file system is read-only".into(),
        _ => {
            let s = e.to_string();
            s.split(" (os error").next().unwrap_or(&s).to_string()
        }
    }
}

/// The reason of an error chain, with I/O errors in plain words.
fn reason(e: &anyhow::Error) -> String {
    match e.chain().find_map(|c| c.downcast_ref::<std::io::Error>()) {
        Some(io) => io_reason(io),
        None => e.to_string(),
    }
}

/// Files written to temporary siblings, published together by
/// [`Staged::publish`]; whatever is not published is removed on drop.
#[derive(Default)]
pub struct Staged {
    /// (temporary file, final path)
    files: Vec<(PathBuf, PathBuf)>,
}

impl Staged {
    pub fn new() -> Self {
        Self::default()
    }

    /// Write `path` through a temporary sibling; errors name `path`.
    fn stage(&mut self, path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("output");
        let tmp = parent_dir(path).join(format!(
            ".{name}.{}-{}.tmp.{}",
            std::process::id(),
            self.files.len(),
            path.extension().and_then(|e| e.to_str()).unwrap_or("bin")
        ));
        // Registered first, so that a partial temporary is removed too
        // (and by an interruption).
        self.files.push((tmp.clone(), path.to_path_buf()));
        crate::interrupt::watch(&tmp);
        write(&tmp).map_err(|e| anyhow!("cannot write `{}`: {}", path.display(), reason(&e)))
    }

    /// Rename every staged file into place. Should one rename fail, the
    /// files already published by this call are removed again (the others
    /// are still temporaries), so it is all or nothing.
    pub fn publish(mut self) -> Result<Vec<PathBuf>> {
        let files = std::mem::take(&mut self.files);
        let mut done: Vec<PathBuf> = Vec::new();
        for (i, (tmp, path)) in files.iter().enumerate() {
            if let Err(e) = std::fs::rename(tmp, path) {
                for p in &done {
                    let _ = std::fs::remove_file(p);
                }
                for (t, _) in &files[i..] {
                    let _ = std::fs::remove_file(t);
                }
                bail!("cannot write `{}`: {}", path.display(), io_reason(&e));
            }
            crate::interrupt::forget(tmp);
            done.push(path.clone());
        }
        for (t, _) in &files {
            crate::interrupt::forget(t);
        }
        Ok(done)
    }

    pub fn png(&mut self, path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
        self.stage(path, |tmp| {
            let file = std::fs::File::create(tmp)?;
            let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
            enc.set_color(png::ColorType::Rgba);
            enc.set_depth(png::BitDepth::Eight);
            enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            let mut w = enc.write_header()?;
            w.write_image_data(rgba8)?;
            w.finish()?;
            Ok(())
        })
    }

    pub fn exr(&mut self, path: &Path, img: &FloatImage) -> Result<()> {
        // OpenEXR cannot open an image without pixels: never write one.
        if img.width == 0 || img.height == 0 {
            bail!(
                "cannot write `{}`: the data is empty ({}×{}), which an EXR image cannot hold; write .npy",
                path.display(),
                img.width,
                img.height
            );
        }
        let names: &[&str] = match img.channels {
            1 => &["Y"],
            3 => &["R", "G", "B"],
            4 => &["R", "G", "B", "A"],
            n => bail!("cannot store {n} channels in EXR"),
        };
        let channels: Vec<AnyChannel<FlatSamples>> = names
            .iter()
            .enumerate()
            .map(|(c, name)| {
                let samples = img.data.iter().skip(c).step_by(img.channels).copied().collect();
                AnyChannel::new(*name, FlatSamples::F32(samples))
            })
            .collect();
        let image =
            Image::from_channels((img.width, img.height), AnyChannels::sort(channels.into()));
        self.stage(path, |tmp| {
            image.write().to_file(tmp).map_err(|e| match e {
                exr::error::Error::Io(io) => anyhow::Error::from(io),
                other => anyhow!("{other}"),
            })
        })
    }

    pub fn text(&mut self, path: &Path, text: &str) -> Result<()> {
        self.stage(path, |tmp| {
            std::fs::write(tmp, text)?;
            Ok(())
        })
    }

    pub fn npy(&mut self, path: &Path, img: &FloatImage) -> Result<()> {
        let shape: Vec<usize> = if img.channels == 1 {
            vec![img.height, img.width]
        } else {
            vec![img.height, img.width, img.channels]
        };
        let bytes = hydrolux::core::npy::encode_f32(&shape, img.data);
        self.stage(path, |tmp| {
            std::fs::write(tmp, &bytes)?;
            Ok(())
        })
    }

    pub fn float(&mut self, path: &Path, format: Format, img: &FloatImage) -> Result<()> {
        match format {
            Format::Exr => self.exr(path, img),
            Format::Npy => self.npy(path, img),
            Format::Png | Format::Json => {
                bail!("`{}`: float buffers are written as .npy or .exr", path.display())
            }
        }
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        for (tmp, _) in &self.files {
            let _ = std::fs::remove_file(tmp);
            crate::interrupt::forget(tmp);
        }
    }
}

/// `rgb` (width × height, 3 floats a pixel) resampled bilinearly to
/// `to`, pixel centres aligned and edges clamped (as the GPU's linear
/// sampler upscales a tier's smaller frame to the output).
pub fn resize_rgb(rgb: &[f32], from: (usize, usize), to: (usize, usize)) -> Vec<f32> {
    if from == to {
        return rgb.to_vec();
    }
    let (fw, fh) = from;
    let texel = |x: usize, y: usize, c: usize| rgb[(y * fw + x) * 3 + c];
    let mut out = Vec::with_capacity(to.0 * to.1 * 3);
    for y in 0..to.1 {
        let v = ((y as f32 + 0.5) * fh as f32 / to.1 as f32 - 0.5).clamp(0.0, (fh - 1) as f32);
        let (y0, b) = (v.floor() as usize, v.fract());
        let y1 = (y0 + 1).min(fh - 1);
        for x in 0..to.0 {
            let u = ((x as f32 + 0.5) * fw as f32 / to.0 as f32 - 0.5).clamp(0.0, (fw - 1) as f32);
            let (x0, a) = (u.floor() as usize, u.fract());
            let x1 = (x0 + 1).min(fw - 1);
            for c in 0..3 {
                let top = texel(x0, y0, c) * (1.0 - a) + texel(x1, y0, c) * a;
                let bottom = texel(x0, y1, c) * (1.0 - a) + texel(x1, y1, c) * a;
                out.push(top * (1.0 - b) + bottom * b);
            }
        }
    }
    out
}

/// A float buffer of `height × width × channels` (row-major, rows top to bottom).
pub struct FloatImage<'a> {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    pub data: &'a [f32],
}

/// One PNG, atomically.
pub fn write_png(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    let mut staged = Staged::new();
    staged.png(path, width, height, rgba8)?;
    staged.publish().map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resizing_keeps_a_ramp_and_a_constant() {
        // A horizontal ramp 0..3 over 4 pixels, doubled to 8: centres map back.
        let ramp: Vec<f32> = (0..4).flat_map(|x| [x as f32; 3]).collect();
        let big = resize_rgb(&ramp, (4, 1), (8, 2));
        assert_eq!(big.len(), 8 * 2 * 3);
        let row: Vec<f32> = big.chunks(3).take(8).map(|p| p[0]).collect();
        assert_eq!(row, [0.0, 0.25, 0.75, 1.25, 1.75, 2.25, 2.75, 3.0]);
        let flat = resize_rgb(&[0.5; 12], (2, 2), (5, 3));
        assert!(flat.iter().all(|&v| (v - 0.5).abs() < 1e-6));
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("hydrolux-out-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn nothing_is_published_when_one_output_fails() {
        let d = dir("fail");
        let img = FloatImage { width: 2, height: 1, channels: 1, data: &[1.0, 2.0] };
        let mut staged = Staged::new();
        staged.png(&d.join("a.png"), 1, 1, &[0, 0, 0, 255]).unwrap();
        let e = staged.npy(&d.join("missing/b.npy"), &img).unwrap_err().to_string();
        assert!(e.contains("missing/b.npy"), "{e}");
        drop(staged);
        assert!(names(&d).is_empty(), "left behind: {:?}", names(&d));
    }

    #[test]
    fn all_outputs_appear_together() {
        let d = dir("ok");
        let img = FloatImage { width: 2, height: 1, channels: 1, data: &[1.0, 2.0] };
        let mut staged = Staged::new();
        staged.png(&d.join("a.png"), 1, 1, &[0, 0, 0, 255]).unwrap();
        staged.npy(&d.join("b.npy"), &img).unwrap();
        staged.exr(&d.join("c.exr"), &img).unwrap();
        assert_eq!(names(&d).iter().filter(|n| !n.starts_with('.')).count(), 0);
        staged.publish().unwrap();
        assert_eq!(names(&d), ["a.png", "b.npy", "c.exr"]);
    }

    #[test]
    fn a_full_disk_is_named_with_the_file() {
        let e = std::io::Error::from_raw_os_error(28);
        let mut staged = Staged::new();
        let path = std::env::temp_dir().join("x.npy");
        let err = staged.stage(&path, |_| Err(e.into())).unwrap_err().to_string();
        assert_eq!(err, format!("cannot write `{}`: no space left on device", path.display()));
    }

    #[test]
    fn a_failed_rename_unpublishes_the_others() {
        let d = dir("rename");
        let mut staged = Staged::new();
        staged.png(&d.join("a.png"), 1, 1, &[0, 0, 0, 255]).unwrap();
        staged.png(&d.join("b.png"), 1, 1, &[0, 0, 0, 255]).unwrap();
        // The second target becomes a non-empty folder: its rename fails.
        std::fs::create_dir_all(d.join("b.png/x")).unwrap();
        let e = staged.publish().unwrap_err().to_string();
        assert!(e.contains("b.png"), "{e}");
        assert_eq!(names(&d), ["b.png"], "a.png must be gone again, no temporaries left");
    }
}
