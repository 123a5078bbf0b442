//! Fuzz targets: every parser of user input, fed arbitrary bytes, must
//! return (an error is fine) without a panic, a hang or an unbounded
//! allocation. The same functions are driven by cargo-fuzz on nightly
//! (`fuzz/`, coverage-guided, millions of runs) and by a short
//! deterministic mutation run on stable in the test suite
//! (`tests/fuzz_smoke.rs`).

use crate::geometry::load::{image_from_bytes, mesh_from_bytes};
use crate::scene::Scene;
use std::path::Path;

/// A fuzz target: arbitrary bytes in, no panic out.
pub type Target = fn(&[u8]);

/// The targets by name, for drivers that pick one.
pub const TARGETS: &[(&str, Target)] =
    &[("scene", scene), ("npy", npy), ("obj", obj), ("gltf", gltf), ("glb", glb), ("image", image)];

/// A scene file and `--set` overrides: the bytes up to the first NUL are
/// the TOML text, each further NUL-separated part one override. A scene
/// that loads must also yield its derived values without panicking.
pub fn scene(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let mut parts = text.split('\0');
    let toml = parts.next().unwrap_or_default();
    let sets: Vec<String> = parts.map(str::to_string).collect();
    if let Ok(s) = Scene::from_toml(toml, "fuzz.toml", &sets) {
        let _ = (s.camera(), s.sun_direction(), s.sea_state(), s.medium(), s.surface_patch());
        let _ = s.ocean_settings().cascades();
        let _ = s.to_table();
    }
}

/// A `.npy` heightfield.
pub fn npy(data: &[u8]) {
    let _ = crate::npy::decode_f32_2d(data);
}

/// A Wavefront OBJ mesh.
pub fn obj(data: &[u8]) {
    let _ = mesh_from_bytes(Path::new("/nonexistent/fuzz.obj"), data);
}

/// A glTF (JSON) mesh; external buffers are not there.
pub fn gltf(data: &[u8]) {
    let _ = mesh_from_bytes(Path::new("/nonexistent/fuzz.gltf"), data);
}

/// A binary glTF mesh.
pub fn glb(data: &[u8]) {
    let _ = mesh_from_bytes(Path::new("/nonexistent/fuzz.glb"), data);
}

/// A texture or heightmap image (PNG, JPEG).
pub fn image(data: &[u8]) {
    if let Ok(img) = image_from_bytes("texture", Path::new("fuzz.png"), data) {
        let _ = img.to_luma16();
    }
}

/// Valid inputs of each target to mutate from (the corpus seeds).
pub fn seeds(target: &str) -> Vec<Vec<u8>> {
    match target {
        "scene" => {
            let mut v: Vec<Vec<u8>> =
                crate::scene::BUILTIN_SCENES.iter().map(|b| b.toml.as_bytes().to_vec()).collect();
            v.push(
                b"[ocean]\nwind_speed = 9.5\n\0camera.position=[1, 2, 3]\0water.model=sines"
                    .to_vec(),
            );
            v
        }
        "npy" => vec![
            crate::npy::encode_f32(&[3, 4], &[0.5; 12]),
            crate::npy::encode_f32(&[2, 2], &[1.0, -1.0, 2.0, 0.0]),
        ],
        "obj" => vec![
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1\n".to_vec(),
            include_bytes!("../../../assets/bunny.obj")[..4096].to_vec(),
        ],
        "gltf" => vec![triangle_gltf().into_bytes()],
        "glb" => vec![triangle_glb()],
        "image" => vec![tiny_png()],
        _ => Vec::new(),
    }
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0];

fn gltf_json(buffer: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"translation":[0,2,0]}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,-1],"max":[1,0,0]}},{{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}],"bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],"buffers":[{{"byteLength":42{buffer}}}]}}"#
    )
}

fn triangle_bytes() -> Vec<u8> {
    let mut bin: Vec<u8> = TRIANGLE.iter().flat_map(|v| v.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
    bin
}

/// Standard base64 with padding (for data URIs in the glTF seeds and tests).
pub(crate) fn base64(data: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut b64 = String::new();
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            b64.push(if i <= c.len() { A[(n >> (18 - 6 * i) & 63) as usize] as char } else { '=' });
        }
    }
    b64
}

fn triangle_gltf() -> String {
    let b64 = base64(&triangle_bytes());
    gltf_json(&format!(r#","uri":"data:application/octet-stream;base64,{b64}""#))
}

fn triangle_glb() -> Vec<u8> {
    let mut json = gltf_json("").into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = triangle_bytes();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

fn tiny_png() -> Vec<u8> {
    let img = image::GrayImage::from_fn(4, 3, |x, y| image::Luma([(x * 40 + y * 10) as u8]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).expect("encode a PNG in memory");
    out.into_inner()
}

/// A small, fast, deterministic generator (SplitMix64) for the mutations.
pub struct Mutator(crate::rng::SplitMix64);

impl Mutator {
    pub fn new(seed: u64) -> Self {
        Mutator(crate::rng::SplitMix64::new(seed))
    }

    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// A mutant of `input`: a few byte flips, interesting values,
    /// insertions, deletions, truncations or copied runs.
    pub fn mutate(&mut self, input: &[u8]) -> Vec<u8> {
        const INTERESTING: &[&[u8]] = &[
            b"0",
            b"-1",
            b"1e400",
            b"nan",
            b"inf",
            b"18446744073709551615",
            b"\"\"",
            b"[",
            b"]",
            b"{",
            b"}",
            b"=",
            b"\0",
            b"\xff\xff\xff\xff",
            b"\x00\x00\x00\x80",
            b"[[objects]]\n",
        ];
        let mut v = input.to_vec();
        for _ in 0..1 + self.below(4) {
            let at = self.below(v.len() + 1);
            match self.below(7) {
                0 if !v.is_empty() => {
                    let i = self.below(v.len());
                    v[i] ^= 1 << self.below(8);
                }
                1 if !v.is_empty() => {
                    let i = self.below(v.len());
                    v[i] = self.next() as u8;
                }
                2 => {
                    let word = INTERESTING[self.below(INTERESTING.len())];
                    v.splice(at..at, word.iter().copied());
                }
                3 if !v.is_empty() => {
                    let end = (at + 1 + self.below(16)).min(v.len());
                    v.drain(at.min(end)..end);
                }
                4 => v.truncate(at),
                5 if !v.is_empty() => {
                    let from = self.below(v.len());
                    let run: Vec<u8> = v[from..(from + 1 + self.below(32)).min(v.len())].to_vec();
                    v.splice(at..at, run);
                }
                _ => {
                    let word = INTERESTING[self.below(INTERESTING.len())];
                    let end = (at + word.len()).min(v.len());
                    v.splice(at..end, word.iter().copied());
                }
            }
        }
        v
    }
}

/// Run `target` on its seeds and `runs` mutants of them; returns the
/// number of executions. A panic propagates with the input in the message.
pub fn run_mutations(name: &str, target: Target, runs: u64, seed: u64) -> u64 {
    let seeds = seeds(name);
    let mut m = Mutator::new(seed);
    for s in &seeds {
        target(s);
    }
    let mut corpus = seeds.clone();
    for i in 0..runs {
        let base = &corpus[m.below(corpus.len())];
        let input = m.mutate(base);
        let outcome = std::panic::catch_unwind(|| target(&input));
        if let Err(e) = outcome {
            let msg = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!(
                "fuzz target `{name}` panicked on mutant {i} ({} bytes, {:?}…): {msg}",
                input.len(),
                String::from_utf8_lossy(&input[..input.len().min(200)])
            );
        }
        // Keep some mutants as new bases, so mutations compound.
        if i % 64 == 0 && corpus.len() < 256 {
            corpus.push(input);
        }
    }
    seeds.len() as u64 + runs
}
