//! Reading input files boundedly: only regular files (not folders, devices,
//! pipes or sockets, whatever a link points to), never more than a limit
//! per kind, so a link to `/dev/zero`, a FIFO or a giant file is refused in
//! a moment with a message saying which and why, before anything is
//! allocated for it.

use std::io::Read;
use std::path::Path;

/// The largest file Hydrolux reads for each kind of input (bytes).
pub mod limits {
    /// A scene: 1,024 objects take about 300 KB of TOML.
    pub const SCENE: u64 = 4 << 20;
    /// A mesh (.obj, .gltf, .glb and a glTF's .bin buffers).
    pub const MESH: u64 = 1 << 30;
    /// A texture or heightmap image (PNG, JPEG).
    pub const IMAGE: u64 = 256 << 20;
    /// A `.npy` heightfield: 8192 × 8192 float64.
    pub const NPY: u64 = (8192 * 8192 * 8) + (1 << 16);
    /// Pixels per side of a decoded image (as for the GPU's textures).
    pub const IMAGE_SIDE: u32 = 16384;
    /// Bytes a decoded image may take in memory.
    pub const IMAGE_DECODED: u64 = 1 << 30;
}

/// Why a file was not read: a short reason, for the caller to put the
/// file's kind and name on.
pub fn reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ if e.raw_os_error() == Some(40) => "a loop of symbolic links".into(),
        _ if e.raw_os_error() == Some(20) => "a part of its path is not a folder".into(),
        _ => {
            let s = e.to_string();
            // "… (os error N)" says nothing more to a user.
            s.split(" (os error").next().unwrap_or(&s).to_string()
        }
    }
}

/// Human-readable size: "3.5 MB", "12 KB", "7 bytes".
pub fn show_size(bytes: u64) -> String {
    if bytes >= 1 << 30 {
        format!("{:.1} GB", bytes as f64 / (1u64 << 30) as f64)
    } else if bytes >= 1 << 20 {
        format!("{:.1} MB", bytes as f64 / (1u64 << 20) as f64)
    } else if bytes >= 1 << 10 {
        format!("{} KB", bytes >> 10)
    } else {
        format!("{bytes} bytes")
    }
}

/// Check that `path` is a regular file (following links) of at most
/// `limit` bytes; its size.
pub fn check_regular(path: &Path, limit: u64) -> Result<u64, String> {
    let meta = std::fs::metadata(path).map_err(|e| reason(&e))?;
    let kind = meta.file_type();
    if kind.is_dir() {
        return Err("it is a folder, not a file".into());
    }
    if !kind.is_file() {
        return Err("it is not a regular file (a device, pipe or socket)".into());
    }
    if meta.len() > limit {
        return Err(format!(
            "it is {}, more than the {} allowed",
            show_size(meta.len()),
            show_size(limit)
        ));
    }
    Ok(meta.len())
}

/// Read a whole regular file of at most `limit` bytes. The read itself is
/// bounded too, should the file grow while it is read.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let len = check_regular(path, limit)?;
    let file = std::fs::File::open(path).map_err(|e| reason(&e))?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| reason(&e))?;
    if bytes.len() as u64 > limit {
        return Err(format!("it grew past the {} allowed while being read", show_size(limit)));
    }
    Ok(bytes)
}

/// [`read_bounded`] for text: the reason says when it is not UTF-8.
pub fn read_text_bounded(path: &Path, limit: u64) -> Result<String, String> {
    let bytes = read_bounded(path, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        format!("it is not UTF-8 text (invalid bytes at offset {})", e.utf8_error().valid_up_to())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("hydrolux-files-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn regular_files_within_the_limit_are_read() {
        let p = dir().join("ok.txt");
        std::fs::write(&p, "hello").unwrap();
        assert_eq!(read_text_bounded(&p, 5).unwrap(), "hello");
        let e = read_bounded(&p, 4).unwrap_err();
        assert!(e.contains("5 bytes, more than the 4 bytes allowed"), "{e}");
    }

    #[test]
    fn folders_devices_missing_files_and_loops_are_named() {
        let d = dir();
        assert!(read_bounded(&d, 100).unwrap_err().contains("folder"));
        assert!(read_bounded(Path::new("/dev/zero"), 100).unwrap_err().contains("not a regular"));
        assert_eq!(read_bounded(&d.join("absent"), 100).unwrap_err(), "no such file");
        #[cfg(unix)]
        {
            let a = d.join("loop_a");
            let b = d.join("loop_b");
            let _ = std::fs::remove_file(&a);
            let _ = std::fs::remove_file(&b);
            std::os::unix::fs::symlink(&b, &a).unwrap();
            std::os::unix::fs::symlink(&a, &b).unwrap();
            assert_eq!(read_bounded(&a, 100).unwrap_err(), "a loop of symbolic links");
            let z = d.join("zero_link");
            let _ = std::fs::remove_file(&z);
            std::os::unix::fs::symlink("/dev/zero", &z).unwrap();
            assert!(read_bounded(&z, 1 << 30).unwrap_err().contains("not a regular"));
        }
    }

    #[test]
    fn text_that_is_not_utf8_says_so() {
        let p = dir().join("bin.txt");
        std::fs::write(&p, [b'a', 0xff, 0xfe]).unwrap();
        assert!(read_text_bounded(&p, 100).unwrap_err().contains("offset 1"));
    }
}
