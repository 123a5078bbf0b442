//! NumPy `.npy` float32 buffers: the writer of the `--dump` format, and a
//! reader for 2-D inputs (user heightfields).

/// Encode a C-ordered little-endian float32 array of `shape`.
pub fn encode_f32(shape: &[usize], data: &[f32]) -> Vec<u8> {
    assert_eq!(shape.iter().product::<usize>(), data.len(), "npy shape does not match data");
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_txt =
        if dims.len() == 1 { format!("({},)", dims[0]) } else { format!("({})", dims.join(", ")) };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {shape_txt}, }}");
    // Magic (6) + version (2) + header length (2) + header + '\n' is a multiple of 64.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len() * 4);
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// The largest array [`decode_f32_2d`] accepts, in elements (8192²).
pub const MAX_ELEMENTS: usize = 8192 * 8192;

/// The value of `key` in a `.npy` header dictionary (`{'key': value, …}`):
/// the text up to the next top-level comma or closing brace.
fn header_value<'a>(header: &'a str, key: &str) -> Option<&'a str> {
    let rest = header.split_once(&format!("'{key}':"))?.1.trim_start();
    let mut depth = 0;
    for (i, c) in rest.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' | '}' if depth == 0 => return Some(rest[..i].trim()),
            _ => {}
        }
    }
    None
}

/// Decode a 2-D C-ordered float32 (`<f4`, or `<f8` converted) array:
/// (rows, cols, data). The header is checked against the file's length and
/// [`MAX_ELEMENTS`] before anything is allocated. Errors are short reasons,
/// for the caller to put the file's name on.
pub fn decode_f32_2d(bytes: &[u8]) -> Result<(usize, usize, Vec<f32>), String> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err("not a .npy file (it does not start with the NumPy magic bytes)".into());
    }
    let (header_len, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10usize),
        2 | 3 if bytes.len() >= 12 => {
            (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12)
        }
        v => return Err(format!("unsupported .npy version {v} (1, 2 and 3 are)")),
    };
    let header = bytes
        .get(start..start.saturating_add(header_len))
        .ok_or("its header is truncated (the file ends inside it)")?;
    let header = std::str::from_utf8(header).map_err(|_| "its header is not text")?.trim();
    let bad_header = || {
        "its header is not a NumPy header dictionary ({'descr': …, 'fortran_order': …, 'shape': (…)})"
            .to_string()
    };
    if !header.starts_with('{') || !header.ends_with('}') {
        return Err(bad_header());
    }
    let descr = header_value(header, "descr").ok_or_else(bad_header)?;
    let order = header_value(header, "fortran_order").ok_or_else(bad_header)?;
    let shape_txt = header_value(header, "shape").ok_or_else(bad_header)?;
    let wide = match descr.trim_matches(|c| c == '\'' || c == '"') {
        "<f4" => false,
        "<f8" => true,
        other => {
            return Err(format!(
                "the array's type is `{other}`; it must be float32 ('<f4') or float64 ('<f8'), little-endian"
            ));
        }
    };
    match order {
        "False" => {}
        "True" => return Err("the array must be C-ordered (fortran_order False)".into()),
        _ => return Err(bad_header()),
    }
    let inner =
        shape_txt.strip_prefix('(').and_then(|t| t.strip_suffix(')')).ok_or_else(bad_header)?;
    let dims: Vec<usize> = inner
        .split(',')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .map(|d| d.parse::<usize>().map_err(|_| format!("its shape has a bad entry `{d}`")))
        .collect::<Result<_, _>>()?;
    let [rows, cols] = dims[..] else {
        return Err(format!("the array must be 2-D (rows = z, cols = x), not {}-D", dims.len()));
    };
    let count = rows.checked_mul(cols).filter(|&n| n <= MAX_ELEMENTS).ok_or_else(|| {
        format!("its shape ({rows}, {cols}) is larger than the 8192 × 8192 allowed")
    })?;
    let body = &bytes[start + header_len..];
    let size = if wide { 8 } else { 4 };
    if body.len() < count * size {
        return Err(format!(
            "the data is shorter than the shape ({rows}, {cols}) needs: {} bytes of {}",
            body.len(),
            count * size
        ));
    }
    let data: Vec<f32> = if wide {
        body.chunks_exact(8)
            .take(count)
            .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")) as f32)
            .collect()
    } else {
        body.chunks_exact(4)
            .take(count)
            .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
            .collect()
    };
    if data.iter().any(|v| !v.is_finite()) {
        return Err("it contains NaN or infinite heights".into());
    }
    Ok((rows, cols, data))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_bad_inputs() {
        let data: Vec<f32> = (0..6).map(|i| i as f32 * 0.5).collect();
        let (r, c, back) = decode_f32_2d(&encode_f32(&[2, 3], &data)).unwrap();
        assert_eq!((r, c), (2, 3));
        assert_eq!(back, data);
        assert!(decode_f32_2d(b"garbage").unwrap_err().contains("not a .npy"));
        // A header that is no dictionary, a wrong type, a shape that does not fit.
        let with_header = |h: &str| {
            let mut b = b"\x93NUMPY\x01\x00".to_vec();
            b.extend_from_slice(&(h.len() as u16).to_le_bytes());
            b.extend_from_slice(h.as_bytes());
            b
        };
        assert!(decode_f32_2d(&with_header("garbage")).unwrap_err().contains("header dictionary"));
        let int = "{'descr': '<i4', 'fortran_order': False, 'shape': (2, 3), }";
        assert!(decode_f32_2d(&with_header(int)).unwrap_err().contains("`<i4`"));
        let huge = "{'descr': '<f4', 'fortran_order': False, 'shape': (4294967296, 4294967296), }";
        assert!(decode_f32_2d(&with_header(huge)).unwrap_err().contains("larger than"));
        let big = "{'descr': '<f4', 'fortran_order': False, 'shape': (100000, 100000), }";
        assert!(decode_f32_2d(&with_header(big)).unwrap_err().contains("larger than"));
        let short = "{'descr': '<f8', 'fortran_order': False, 'shape': (64, 64), }";
        assert!(decode_f32_2d(&with_header(short)).unwrap_err().contains("0 bytes of 32768"));
        assert!(decode_f32_2d(b"\x93NUMPY\x01\x00\xff\x00{").unwrap_err().contains("truncated"));
        assert!(decode_f32_2d(&encode_f32(&[6], &data)).unwrap_err().contains("2-D"));
        let mut short = encode_f32(&[2, 3], &data);
        short.truncate(short.len() - 4);
        assert!(decode_f32_2d(&short).unwrap_err().contains("shorter"));
    }

    #[test]
    fn header_is_aligned_and_data_follows() {
        let b = super::encode_f32(&[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(&b[..6], b"\x93NUMPY");
        let hlen = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hlen) % 64, 0);
        let header = std::str::from_utf8(&b[10..10 + hlen]).unwrap();
        assert!(header.contains("'shape': (2, 3)") && header.ends_with('\n'));
        assert_eq!(b.len(), 10 + hlen + 24);
        assert_eq!(f32::from_le_bytes(b[10 + hlen..14 + hlen].try_into().unwrap()), 1.0);
    }
}
