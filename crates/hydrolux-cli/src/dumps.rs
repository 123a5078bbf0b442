//! `--dump KIND=FILE`: internal buffers as float arrays (.npy or .exr) or
//! documents (.json). The kinds, what each needs of a scene and how each is
//! read are declared by their owners in the renderer (`hydrolux::dump_kinds`,
//! `Renderer::dump`); this module only parses, checks and writes.

use crate::output::{self, FloatImage, Format};
use anyhow::{Result, bail};
use hydrolux::{DumpData, DumpKind, DumpShape, Renderer};
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct Dump {
    pub kind: &'static DumpKind,
    pub path: PathBuf,
    pub format: Format,
}

/// Every kind's name, in the renderer's order.
pub fn kinds() -> String {
    hydrolux::dump_kinds().iter().map(|k| k.name).collect::<Vec<_>>().join(", ")
}

/// `render --help`'s text for `--dump`, from the same list.
pub fn help() -> String {
    format!(
        "Write an internal buffer: KIND=FILE.npy|FILE.exr (bodies: FILE.json) with KIND one of {}. Repeatable.",
        kinds()
    )
}

pub fn parse(text: &str) -> Result<Dump> {
    let Some((name, file)) = text.split_once('=') else {
        bail!("--dump `{text}`: expected KIND=FILE with KIND one of {}", kinds());
    };
    let Some(kind) = hydrolux::dump_kinds().into_iter().find(|k| k.name == name) else {
        bail!("--dump `{name}`: unknown buffer; choose one of {}", kinds());
    };
    let path = PathBuf::from(file);
    let allowed: &[Format] = match kind.shape {
        DumpShape::Json => &[Format::Json],
        DumpShape::Grid | DumpShape::List => &[Format::Npy, Format::Exr],
    };
    let format = output::format_of(&path, allowed, &format!("--dump {name} file"))?;
    // A list that may be empty: EXR has no image of zero rows.
    if kind.shape == DumpShape::List && format == Format::Exr {
        bail!(
            "--dump {name}={file}: the {name} are a list that is empty when none are alive, which an EXR image cannot hold; write .npy (N rows, 0 rows when none are alive)"
        );
    }
    Ok(Dump { kind, path, format })
}

/// What can be known before rendering: the scene has what the dump reads.
pub fn check(dump: &Dump, scene: &hydrolux::core::scene::Scene) -> Result<()> {
    match (dump.kind.missing)(scene) {
        Some(why) => bail!("--dump {}: {why}", dump.kind.name),
        None => Ok(()),
    }
}

/// Read the buffer back and stage it for writing.
pub fn write(dump: &Dump, renderer: &Renderer, staged: &mut output::Staged) -> Result<()> {
    let name = dump.kind.name;
    match renderer.dump(name) {
        Err(why) => bail!("--dump {name}: {why}"),
        Ok(DumpData::Json(text)) => staged.text(&dump.path, &text),
        Ok(DumpData::Floats { columns, rows, channels, data, note }) => {
            if let Some(note) = note {
                println!("{name}: {note}");
            }
            let image = FloatImage { width: columns, height: rows, channels, data: &data };
            staged.float(&dump.path, dump.format, &image)
        }
    }
}

#[cfg(test)]
mod tests {
    /// Every kind the help names parses, and the help names every kind.
    #[test]
    fn the_help_lists_every_dump_kind() {
        for kind in hydrolux::dump_kinds() {
            let file = if kind.shape == hydrolux::DumpShape::Json { "b.json" } else { "x.npy" };
            super::parse(&format!("{}={file}", kind.name))
                .unwrap_or_else(|e| panic!("{}: {e}", kind.name));
            assert!(super::help().contains(kind.name), "{}", kind.name);
        }
        let names = super::kinds();
        for name in [
            "height",
            "displacement",
            "normals",
            "jacobian",
            "hdr",
            "caustics",
            "godrays",
            "object_caustics",
            "ripples",
            "bodies",
            "foam",
            "particles",
        ] {
            assert!(names.split(", ").any(|n| n == name), "{name} missing from {names}");
        }
    }
}
