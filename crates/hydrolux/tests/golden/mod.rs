//! Golden-image comparison with a perceptual metric: both images are blurred
//! like the eye at normal viewing distance (Gaussian, σ = 1 px, in linear
//! light) and compared as CIE L*a*b* colour differences (ΔE76, in the spirit
//! of S-CIELAB). A pass needs a small mean ΔE and few strongly differing
//! pixels. `HYDROLUX_BLESS=1` rewrites the goldens; a failure writes the
//! actual image and a difference map next to the target directory.

use std::path::PathBuf;

const MEAN_DELTA_E: f32 = 1.5;
const P99_DELTA_E: f32 = 8.0;

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden").join(format!("{name}.png"))
}

fn failure_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/golden-failures")
}

fn read_png(path: &PathBuf) -> Option<(u32, u32, Vec<u8>)> {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).ok()?));
    let mut reader = decoder.read_info().ok()?;
    let mut buf = vec![0; reader.output_buffer_size()?];
    let info = reader.next_frame(&mut buf).ok()?;
    buf.truncate(info.buffer_size());
    (info.color_type == png::ColorType::Rgba).then_some((info.width, info.height, buf))
}

fn write_png(path: &PathBuf, w: u32, h: u32, rgba: &[u8]) {
    let file = std::fs::File::create(path).expect("write png");
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().and_then(|mut wr| wr.write_image_data(rgba)).expect("encode png");
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

fn blur(img: &[[f32; 3]], w: usize, h: usize) -> Vec<[f32; 3]> {
    let k = [0.054f32, 0.244, 0.403, 0.244, 0.054];
    let pass = |src: &[[f32; 3]], dx: i32, dy: i32| -> Vec<[f32; 3]> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as i32, (i / w) as i32);
                let mut acc = [0.0; 3];
                for (j, wt) in k.iter().enumerate() {
                    let o = j as i32 - 2;
                    let sx = (x + o * dx).clamp(0, w as i32 - 1) as usize;
                    let sy = (y + o * dy).clamp(0, h as i32 - 1) as usize;
                    for c in 0..3 {
                        acc[c] += wt * src[sy * w + sx][c];
                    }
                }
                acc
            })
            .collect()
    };
    pass(&pass(img, 1, 0), 0, 1)
}

fn lab(rgb: [f32; 3]) -> [f32; 3] {
    let [r, g, b] = rgb;
    let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.9505;
    let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.089;
    let f = |t: f32| if t > 0.008856 { t.cbrt() } else { 7.787 * t + 16.0 / 116.0 };
    [116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))]
}

/// ΔE per pixel between two RGBA8 sRGB images.
pub fn delta_e(w: usize, h: usize, a: &[u8], b: &[u8]) -> Vec<f32> {
    let lin = |img: &[u8]| -> Vec<[f32; 3]> {
        img.chunks_exact(4)
            .map(|p| [srgb_to_linear(p[0]), srgb_to_linear(p[1]), srgb_to_linear(p[2])])
            .collect()
    };
    let (ba, bb) = (blur(&lin(a), w, h), blur(&lin(b), w, h));
    ba.iter()
        .zip(&bb)
        .map(|(p, q)| {
            let (l1, l2) = (lab(*p), lab(*q));
            ((l1[0] - l2[0]).powi(2) + (l1[1] - l2[1]).powi(2) + (l1[2] - l2[2]).powi(2)).sqrt()
        })
        .collect()
}

/// Mean and 99th percentile of ΔE between two images.
pub fn mean_and_p99(w: u32, h: u32, a: &[u8], b: &[u8]) -> (f32, f32) {
    let de = delta_e(w as usize, h as usize, a, b);
    let mean = de.iter().sum::<f32>() / de.len() as f32;
    let mut sorted = de;
    sorted.sort_by(f32::total_cmp);
    (mean, sorted[(sorted.len() as f32 * 0.99) as usize])
}

pub fn within_tolerance(mean: f32, p99: f32) -> bool {
    mean <= MEAN_DELTA_E && p99 <= P99_DELTA_E
}

/// Write `actual` and its difference map from `expected` for a person to see.
pub fn write_failure(name: &str, w: u32, h: u32, actual: &[u8], expected: &[u8]) {
    let dir = failure_dir();
    std::fs::create_dir_all(&dir).expect("failure dir");
    write_png(&dir.join(format!("{name}.actual.png")), w, h, actual);
    let diff: Vec<u8> = delta_e(w as usize, h as usize, actual, expected)
        .iter()
        .flat_map(|d| {
            let v = (d * 20.0).min(255.0) as u8;
            [v, v, v, 255]
        })
        .collect();
    write_png(&dir.join(format!("{name}.diff.png")), w, h, &diff);
}

#[allow(dead_code)] // tests/backends.rs compares two renders instead
pub fn check(name: &str, w: u32, h: u32, actual: &[u8]) {
    let path = golden_path(name);
    if std::env::var_os("HYDROLUX_BLESS").is_some() {
        write_png(&path, w, h, actual);
        eprintln!("blessed {}", path.display());
        return;
    }
    let Some((gw, gh, golden)) = read_png(&path) else {
        panic!("missing golden {} (run with HYDROLUX_BLESS=1 to create it)", path.display());
    };
    assert_eq!((gw, gh), (w, h), "{name}: golden size differs");
    let (mean, p99) = mean_and_p99(w, h, actual, &golden);
    if !within_tolerance(mean, p99) {
        write_failure(name, w, h, actual, &golden);
        panic!(
            "{name}: mean ΔE {mean:.2} (max {MEAN_DELTA_E}), 99th percentile {p99:.2} (max {P99_DELTA_E}); see {}",
            failure_dir().display()
        );
    }
}

#[test]
fn metric_sees_a_real_change_and_ignores_none() {
    let (w, h) = (16, 16);
    let a: Vec<u8> = (0..w * h).flat_map(|i| [(i % 200) as u8, 90, 140, 255]).collect();
    assert!(delta_e(w, h, &a, &a).iter().all(|d| *d == 0.0));
    let mut b = a.clone();
    for p in b.chunks_exact_mut(4).take(w * h / 2) {
        p[0] = 255;
    }
    let de = delta_e(w, h, &a, &b);
    assert!(de.iter().sum::<f32>() / de.len() as f32 > MEAN_DELTA_E);
}
