//! Parsers of the options' numbers, each refusing a bad value in the
//! option's own terms (clap alone quotes the integer type's range, and
//! reads `-inf` as a flag).

use hydrolux::core::clock::MAX_TIME_S;

/// A whole number from `lo` to `hi` (`what` names the unit).
fn whole(text: &str, lo: u32, hi: u32, what: &str) -> Result<u32, String> {
    match text.trim().parse::<i128>() {
        Ok(v) if (lo as i128..=hi as i128).contains(&v) => Ok(v as u32),
        _ => Err(format!("must be a whole number from {lo} to {hi} {what}")),
    }
}

/// A number of seconds (any spelling Rust reads: `-1.5`, `1e3`, `-inf`).
fn number(text: &str) -> Result<f64, String> {
    text.trim().parse::<f64>().map_err(|_| "must be a number of seconds".to_string())
}

/// `--width`, `--height`.
pub fn pixels(text: &str) -> Result<u32, String> {
    whole(text, 1, 16384, "pixels")
}

/// `--frames` of `render`.
pub fn frame_count(text: &str) -> Result<u32, String> {
    whole(text, 1, u32::MAX - 1, "frames")
}

/// `--frames` of `bench` (each one is rendered and timed).
pub fn bench_frames(text: &str) -> Result<u32, String> {
    whole(text, 1, 1_000_000, "frames")
}

/// `--crf`: x264's and VP9's constant rate factor.
pub fn crf(text: &str) -> Result<u32, String> {
    whole(text, 0, 51, "")
        .map_err(|_| "must be a whole number from 0 (lossless) to 51 (the smallest file)".into())
}

/// `--samples`: anti-aliasing samples per written frame.
pub fn samples(text: &str) -> Result<u32, String> {
    whole(text, 1, 64, "").map_err(|_| "must be a whole number from 1 to 64".into())
}

/// `--time`: a simulation time either side of 0.
pub fn time(text: &str) -> Result<f64, String> {
    let t = number(text)?;
    if t.is_finite() && t.abs() <= MAX_TIME_S {
        Ok(t)
    } else {
        Err(format!("must be a time from -{MAX_TIME_S:e} to {MAX_TIME_S:e} s (about 31 years)"))
    }
}

/// `--start` of `bench`: the simulations' time, from 0.
pub fn start(text: &str) -> Result<f64, String> {
    let t = number(text)?;
    if t.is_finite() && (0.0..=MAX_TIME_S).contains(&t) {
        Ok(t)
    } else {
        Err(format!("must be a time from 0 to {MAX_TIME_S:e} s (about 31 years)"))
    }
}

/// `--fps`: frames per second of simulated time.
pub fn fps(text: &str) -> Result<f64, String> {
    let f = text.trim().parse::<f64>().unwrap_or(f64::NAN);
    if (1e-3..=1e4).contains(&f) {
        Ok(f)
    } else {
        Err("must be 0.001 to 10000 frames per second".to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_option_states_its_own_range() {
        assert_eq!(pixels("64"), Ok(64));
        assert_eq!(pixels("-1").unwrap_err(), "must be a whole number from 1 to 16384 pixels");
        assert!(pixels("99999999999999999999").is_err());
        assert_eq!(
            crf("-1").unwrap_err(),
            "must be a whole number from 0 (lossless) to 51 (the smallest file)"
        );
        assert_eq!(
            frame_count("0").unwrap_err(),
            "must be a whole number from 1 to 4294967294 frames"
        );
        assert_eq!(time("-1.5"), Ok(-1.5));
        assert!(time("-inf").unwrap_err().contains("from -1e9 to 1e9 s"));
        assert!(time("1e30").is_err() && time("NaN").is_err());
        assert_eq!(time("1e9"), Ok(1e9));
        assert!(start("-1").is_err() && start("1e9").is_ok());
        assert!(fps("1e-30").is_err() && fps("0").is_err() && fps("24").is_ok());
    }
}
