//! Writing files: PNG (8-bit sRGB), EXR (linear float) and NumPy `.npy`,
//! always atomically (a temporary file in the same folder, then a rename),
//! so a failed or interrupted run never leaves a half-written file.

use anyhow::{Context, Result, bail};
use exr::prelude::*;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
    Npy,
}

/// The format of `path` from its extension, if it is one of `allowed`.
pub fn format_of(path: &Path, allowed: &[Format], what: &str) -> Result<Format> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let f = match ext.as_deref() {
        Some("png") => Some(Format::Png),
        Some("exr") => Some(Format::Exr),
        Some("npy") => Some(Format::Npy),
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
                })
                .collect();
            bail!("{what} `{}` must end in {}", path.display(), names.join(" or "))
        }
    }
}

/// Fail early if `path` cannot be written (missing folder, not a folder, read-only).
/// What identifies the file `path` names, whatever the spelling
/// (`./x.npy`, `dir/../x.npy`): its folder made canonical, and its name.
pub fn same_file_key(path: &Path) -> PathBuf {
    let dir = parent_dir(path);
    let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
    dir.join(path.file_name().unwrap_or_default())
}

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

/// Write through a temporary sibling, then rename over `path`.
fn atomic_write(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("output");
    let tmp = parent_dir(path).join(format!(
        ".{name}.{}.tmp.{}",
        std::process::id(),
        path.extension().and_then(|e| e.to_str()).unwrap_or("bin")
    ));
    let result = write(&tmp).and_then(|_| {
        std::fs::rename(&tmp, path).with_context(|| format!("cannot write `{}`", path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

pub fn write_png(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    atomic_write(path, |tmp| {
        let file = std::fs::File::create(tmp)
            .with_context(|| format!("cannot write `{}`", path.display()))?;
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

/// A float buffer of `height × width × channels` (row-major, rows top to bottom).
pub struct FloatImage<'a> {
    pub width: usize,
    pub height: usize,
    pub channels: usize,
    pub data: &'a [f32],
}

pub fn write_exr(path: &Path, img: &FloatImage) -> Result<()> {
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
            AnyChannel::new(
                *name,
                FlatSamples::F32(img.data.iter().skip(c).step_by(img.channels).copied().collect()),
            )
        })
        .collect();
    let image = Image::from_channels((img.width, img.height), AnyChannels::sort(channels.into()));
    atomic_write(path, |tmp| {
        image.write().to_file(tmp).with_context(|| format!("cannot write `{}`", path.display()))
    })
}

pub fn write_npy(path: &Path, img: &FloatImage) -> Result<()> {
    let shape: Vec<usize> = if img.channels == 1 {
        vec![img.height, img.width]
    } else {
        vec![img.height, img.width, img.channels]
    };
    let bytes = hydrolux::core::npy::encode_f32(&shape, img.data);
    atomic_write(path, |tmp| {
        std::fs::write(tmp, &bytes).with_context(|| format!("cannot write `{}`", path.display()))
    })
}

pub fn write_float(path: &Path, format: Format, img: &FloatImage) -> Result<()> {
    match format {
        Format::Exr => write_exr(path, img),
        Format::Npy => write_npy(path, img),
        Format::Png => bail!("`{}`: float buffers are written as .npy or .exr", path.display()),
    }
}
