//! The `hydrolux` binary as a user meets it: bad input gives one line naming
//! the bad value, exit status 1, no panic and no file; good input writes
//! valid files.

use std::path::PathBuf;
use std::process::Command;

mod dumps;
mod input;
mod render;
mod video;

pub fn hydrolux(args: &[&str], dir: &PathBuf) -> (i32, String) {
    hydrolux_env(args, dir, &[])
}

pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hydrolux-cli-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn write_png(
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

/// Like [`hydrolux`] with extra environment variables (None removes one).
pub fn hydrolux_env(args: &[&str], dir: &PathBuf, env: &[(&str, Option<&str>)]) -> (i32, String) {
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

pub fn files_in(dir: &PathBuf) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}
