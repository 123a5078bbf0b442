//! Mesh and image files: Wavefront OBJ (tobj), glTF 2.0 (.gltf/.glb), and
//! PNG/JPEG images for textures and heightmaps. Every failure names the file.
//! Meshes without normals get area-weighted normals; degenerate triangles
//! are dropped.

use super::Mesh;
use crate::files::limits;
use glam::{Mat4, Vec2, Vec3};
use std::path::Path;

#[derive(Debug, thiserror::Error, PartialEq)]
#[error("cannot load {what} {path}: {reason}")]
pub struct AssetError {
    pub what: &'static str,
    pub path: String,
    pub reason: String,
}

/// Read an input file boundedly (a regular file, at most `limit` bytes),
/// or say plainly why not.
fn read(what: &'static str, path: &Path, limit: u64) -> Result<Vec<u8>, AssetError> {
    crate::files::read_bounded(path, limit).map_err(|r| err(what, path, r))
}

fn err(what: &'static str, path: &Path, reason: impl ToString) -> AssetError {
    AssetError {
        what,
        path: path.display().to_string(),
        reason: reason.to_string().lines().next().unwrap_or_default().to_string(),
    }
}

/// Load a mesh file by extension (`.obj`, `.gltf`, `.glb`).
pub fn load_mesh(path: &Path) -> Result<Mesh, AssetError> {
    check_mesh_format(path)?;
    mesh_from_bytes(path, &read("mesh", path, limits::MESH)?)
}

fn mesh_extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default()
}

fn check_mesh_format(path: &Path) -> Result<(), AssetError> {
    match mesh_extension(path).as_str() {
        "obj" | "gltf" | "glb" => Ok(()),
        _ => Err(err("mesh", path, "unsupported format: use .obj, .gltf or .glb")),
    }
}

/// A mesh from the bytes of a file named `path` (its extension gives the
/// format; a glTF's external buffers are looked for beside it).
pub fn mesh_from_bytes(path: &Path, bytes: &[u8]) -> Result<Mesh, AssetError> {
    check_mesh_format(path)?;
    let mesh = match mesh_extension(path).as_str() {
        "obj" => load_obj(path, bytes)?,
        _ => load_gltf(path, bytes)?,
    };
    finish_mesh(mesh, path)
}

/// Meshes compiled into the library, by name: "bunny" (the Stanford bunny,
/// public domain, closed, unit height, resting on y = 0; assets/bunny.obj).
pub fn builtin_mesh(name: &str) -> Result<Mesh, AssetError> {
    let path = Path::new(name);
    let text = match name {
        "bunny" => include_str!("../../../../assets/bunny.obj"),
        _ => {
            return Err(err(
                "mesh",
                Path::new(&format!("builtin:{name}")),
                "unknown built-in mesh: use builtin:bunny",
            ));
        }
    };
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| err("mesh", path, e))?;
    finish_mesh(obj_models_to_mesh(&models, path)?, path)
}

fn finish_mesh(mut mesh: Mesh, path: &Path) -> Result<Mesh, AssetError> {
    if mesh.normals.len() != mesh.positions.len() {
        mesh.compute_normals();
    }
    if mesh.uvs.len() != mesh.positions.len() {
        mesh.uvs = vec![Vec2::ZERO; mesh.positions.len()];
    }
    if !mesh.positions.iter().all(|p| p.is_finite()) {
        return Err(err("mesh", path, "it has non-finite vertex positions"));
    }
    mesh.remove_degenerate_triangles();
    if mesh.triangle_count() == 0 {
        return Err(err("mesh", path, "it has no (non-degenerate) triangles"));
    }
    Ok(mesh)
}

fn load_obj(path: &Path, bytes: &[u8]) -> Result<Mesh, AssetError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        err("mesh", path, format!("it is not an OBJ file: not text (invalid bytes at offset {at})"))
    })?;
    check_obj_faces(text)
        .map_err(|r| err("mesh", path, format!("it is not a valid OBJ file: {r}")))?;
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    // Materials (.mtl) are not used: the scene gives each object its material.
    let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| err("mesh", path, obj_reason(e)))?;
    obj_models_to_mesh(&models, path)
}

/// Every face index refers to an element defined before it (1-based, or
/// negative counting back): tobj overflows on indices that do not.
fn check_obj_faces(text: &str) -> Result<(), String> {
    let mut counts = [0i64; 3]; // v, vt, vn
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => {
                for corner in words {
                    for (k, part) in corner.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        let what = ["vertex", "texture coordinate", "normal"][k];
                        let i: i64 = part.parse().map_err(|_| {
                            format!("line {}: face index `{part}` is not a whole number", n + 1)
                        })?;
                        let ok = (1..=counts[k]).contains(&i) || (-counts[k]..=-1).contains(&i);
                        if !ok {
                            return Err(format!(
                                "line {}: a face refers to {what} {i}, of {} defined before it",
                                n + 1,
                                counts[k]
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// What is wrong with an OBJ file, in the words of its format.
fn obj_reason(e: tobj::LoadError) -> String {
    use tobj::LoadError as E;
    let what = match e {
        E::PositionParseError => "a vertex (`v`) line does not hold 3 or 4 numbers".into(),
        E::NormalParseError => "a normal (`vn`) line does not hold 3 numbers".into(),
        E::TexcoordParseError => "a texture coordinate (`vt`) line does not hold numbers".into(),
        E::FaceParseError | E::InvalidPolygon => {
            "a face (`f`) line is malformed (indices must be integers, at least 3 per face)".into()
        }
        E::FaceVertexOutOfBounds => "a face refers to a vertex that does not exist".into(),
        E::FaceTexCoordOutOfBounds => {
            "a face refers to a texture coordinate that does not exist".into()
        }
        E::FaceNormalOutOfBounds => "a face refers to a normal that does not exist".into(),
        E::ReadError => "a line cannot be read".into(),
        other => other.to_string(),
    };
    format!("it is not a valid OBJ file: {what}")
}

fn obj_models_to_mesh(models: &[tobj::Model], path: &Path) -> Result<Mesh, AssetError> {
    let mut out = Mesh::default();
    let mut all_have_normals = true;
    for model in models {
        let m = &model.mesh;
        let n = m.positions.len() / 3;
        let has_normals = m.normals.len() == m.positions.len();
        all_have_normals &= has_normals;
        let part = Mesh {
            positions: m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
            normals: if has_normals {
                m.normals.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect()
            } else {
                vec![Vec3::ZERO; n]
            },
            uvs: if m.texcoords.len() == 2 * n {
                m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], 1.0 - t[1])).collect()
            } else {
                vec![Vec2::ZERO; n]
            },
            indices: m.indices.clone(),
        };
        if part.indices.iter().any(|&i| i as usize >= n) {
            return Err(err("mesh", path, "a face refers to a vertex that does not exist"));
        }
        out.append(&part);
    }
    if !all_have_normals {
        out.normals.clear();
    }
    Ok(out)
}

/// A glTF file's external buffer URI as a path beside it (percent-decoded).
fn buffer_path(path: &Path, uri: &str) -> std::path::PathBuf {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied().and_then(hex),
            bytes.get(i + 2).copied().and_then(hex),
        ) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    let name = String::from_utf8_lossy(&out).into_owned();
    path.parent().unwrap_or(Path::new("")).join(name)
}

/// What is wrong with a glTF or GLB file.
fn gltf_reason(e: gltf::Error) -> String {
    use gltf::binary::Error as Glb;
    match e {
        gltf::Error::Deserialize(e) => format!("it is not valid glTF JSON ({e})"),
        gltf::Error::Binary(Glb::Magic(_)) => "it is not a GLB file (wrong magic bytes)".into(),
        gltf::Error::Binary(Glb::Version(v)) => {
            format!("GLB version {v} is not supported (only version 2 is)")
        }
        gltf::Error::Binary(Glb::Length { length, length_read }) => {
            format!(
                "it is truncated: its GLB header declares {length} bytes, the file has {length_read}"
            )
        }
        gltf::Error::Binary(Glb::ChunkLength { length, length_read, .. }) => {
            format!("it is truncated: a GLB chunk declares {length} bytes, {length_read} are there")
        }
        gltf::Error::Binary(Glb::Io(_)) => {
            "it is truncated (a GLB header or chunk ends early)".into()
        }
        gltf::Error::Binary(b) => format!("it is not a valid GLB file ({b})"),
        gltf::Error::Validation(list) => match list.first() {
            Some((at, why)) => format!("it breaks the glTF schema at {at}: {why}"),
            None => "it breaks the glTF schema".into(),
        },
        gltf::Error::BufferLength { buffer, expected, actual } => {
            format!("buffer {buffer} holds {actual} bytes, less than the {expected} it declares")
        }
        gltf::Error::MissingBlob => "it refers to a GLB binary chunk it does not have".into(),
        gltf::Error::Io(e) => crate::files::reason(&e),
        other => other.to_string(),
    }
}

/// Whether every accessor the primitive reads has the type the glTF spec
/// allows for its use, at least one element, and lies inside its buffer
/// (the gltf crate's reader panics or silently skips otherwise).
fn accessors_in_bounds(
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    use gltf::Semantic as S;
    use gltf::accessor::{DataType as T, Dimensions as D};
    let mut accessors: Vec<(gltf::Accessor, &str)> = Vec::new();
    for (semantic, a) in prim.attributes() {
        let ok = match semantic {
            S::Positions | S::Normals => (a.dimensions(), a.data_type()) == (D::Vec3, T::F32),
            S::TexCoords(0) => {
                a.dimensions() == D::Vec2 && matches!(a.data_type(), T::F32 | T::U8 | T::U16)
            }
            _ => continue,
        };
        accessors.push((a, if ok { "" } else { "attribute" }));
    }
    if let Some(a) = prim.indices() {
        let ok = a.dimensions() == D::Scalar && matches!(a.data_type(), T::U8 | T::U16 | T::U32);
        accessors.push((a, if ok { "" } else { "index" }));
    }
    for (a, wrong) in accessors {
        if !wrong.is_empty() {
            return Err(format!(
                "accessor {} has a type ({:?} {:?}) the glTF spec does not allow for this {wrong}",
                a.index(),
                a.data_type(),
                a.dimensions()
            ));
        }
        if a.count() == 0 {
            return Err(format!("accessor {} has no elements (count 0)", a.index()));
        }
        if a.sparse().is_some() {
            return Err(format!("accessor {} is sparse, which Hydrolux does not read", a.index()));
        }
        let Some(view) = a.view() else { continue };
        let buffer_len = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
        let view_end = view.offset().checked_add(view.length());
        if view_end.is_none_or(|end| end > buffer_len) {
            return Err(format!(
                "buffer view {} reaches past the end of buffer {}",
                view.index(),
                view.buffer().index()
            ));
        }
        let stride = view.stride().unwrap_or(a.size());
        let needed = match a.count() {
            0 => Some(0),
            n => (n - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(a.offset()))
                .and_then(|x| x.checked_add(a.size())),
        };
        if needed.is_none_or(|n| n > view.length()) {
            return Err(format!("accessor {} reads past the end of its buffer view", a.index()));
        }
    }
    Ok(())
}

/// Check what gltf-json's validation indexes without checking (a
/// primitive's POSITION accessor: it panics on a missing one).
fn position_accessors_exist(bytes: &[u8]) -> Result<(), gltf::Error> {
    let json = if bytes.starts_with(b"glTF") {
        gltf::Glb::from_slice(bytes)?.json
    } else {
        std::borrow::Cow::Borrowed(bytes)
    };
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(&json).map_err(gltf::Error::Deserialize)?;
    let position = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(i) = primitive.attributes.get(&position)
                && i.value() >= root.accessors.len()
            {
                let at = gltf::json::Path::new()
                    .field("meshes")
                    .index(m)
                    .field("primitives")
                    .index(p)
                    .field("attributes")
                    .key("POSITION");
                let missing = gltf::json::validation::Error::IndexOutOfBounds;
                return Err(gltf::Error::Validation(vec![(at, missing)]));
            }
        }
    }
    Ok(())
}

fn load_gltf(path: &Path, bytes: &[u8]) -> Result<Mesh, AssetError> {
    let fail = |e: gltf::Error| err("mesh", path, gltf_reason(e));
    // A .glb that is not one (empty, random bytes) is said so in GLB's own
    // terms: the gltf crate would read it as JSON and say that is invalid.
    let glb = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    if glb && !bytes.starts_with(b"glTF") {
        let what = if bytes.is_empty() { "it is empty" } else { "it does not start with one" };
        return Err(err(
            "mesh",
            path,
            format!(
                "it is not a GLB file: a GLB starts with the 12-byte header `glTF`, version, length; {what}"
            ),
        ));
    }
    // A GLB header declaring fewer bytes than itself underflows in the
    // gltf crate's reader (a panic where overflow checks are on).
    if bytes.starts_with(b"glTF") {
        let declared = bytes.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if declared.is_none_or(|n| n < 12) {
            return Err(err("mesh", path, "it is not a valid GLB file (its header is cut short)"));
        }
    }
    position_accessors_exist(bytes).map_err(fail)?;
    let gltf::Gltf { document: doc, blob } = gltf::Gltf::from_slice(bytes).map_err(fail)?;
    // External buffers: each a bounded regular file, named when it is not.
    for buffer in doc.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source()
            && !uri.starts_with("data:")
        {
            let file = buffer_path(path, uri);
            let len = crate::files::check_regular(&file, limits::MESH).map_err(|r| {
                err("mesh buffer", &file, format!("{r} (used by {})", path.display()))
            })?;
            if (len as usize) < buffer.length() {
                return Err(err(
                    "mesh buffer",
                    &file,
                    format!(
                        "it holds {len} bytes, less than the {} {} declares",
                        buffer.length(),
                        path.display()
                    ),
                ));
            }
        }
    }
    let buffers = gltf::import_buffers(&doc, path.parent(), blob).map_err(fail)?;
    let mut out = Mesh::default();
    let mut all_have_normals = true;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| err("mesh", path, "it has no scene"))?;
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let normal_matrix = world.inverse().transpose();
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                accessors_in_bounds(&prim, &buffers).map_err(|r| err("mesh", path, r))?;
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let Some(positions) = reader.read_positions() else { continue };
                let positions: Vec<Vec3> =
                    positions.map(|p| world.transform_point3(Vec3::from(p))).collect();
                let n = positions.len();
                let normals: Vec<Vec3> = match reader.read_normals() {
                    Some(ns) => ns
                        .map(|v| normal_matrix.transform_vector3(Vec3::from(v)).normalize_or_zero())
                        .collect(),
                    None => {
                        all_have_normals = false;
                        vec![Vec3::ZERO; n]
                    }
                };
                let uvs = reader.read_tex_coords(0).map_or_else(
                    || vec![Vec2::ZERO; n],
                    |t| t.into_f32().map(Vec2::from).collect(),
                );
                let indices: Vec<u32> = reader
                    .read_indices()
                    .map_or_else(|| (0..n as u32).collect(), |i| i.into_u32().collect());
                if indices.iter().any(|&i| i as usize >= n) || normals.len() != n || uvs.len() != n
                {
                    return Err(err("mesh", path, "a primitive's accessors disagree in length"));
                }
                let mut part = Mesh { positions, normals, uvs, indices };
                if world.determinant() < 0.0 {
                    for t in part.indices.chunks_exact_mut(3) {
                        t.swap(1, 2);
                    }
                }
                out.append(&part);
            }
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    if !all_have_normals {
        out.normals.clear();
    }
    Ok(out)
}

/// An 8-bit sRGB RGBA image, rows top to bottom.
#[derive(Debug)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// Decode a PNG or JPEG read boundedly, within the size limits.
fn decode_image(what: &'static str, path: &Path) -> Result<image::DynamicImage, AssetError> {
    image_from_bytes(what, path, &read(what, path, limits::IMAGE)?)
}

/// Decode the bytes of a PNG or JPEG file named `path`, within the size limits.
pub fn image_from_bytes(
    what: &'static str,
    path: &Path,
    bytes: &[u8],
) -> Result<image::DynamicImage, AssetError> {
    let format = image::guess_format(bytes)
        .ok()
        .filter(|f| matches!(f, image::ImageFormat::Png | image::ImageFormat::Jpeg))
        .ok_or_else(|| err(what, path, "it is not a PNG or JPEG image"))?;
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut bounds = image::Limits::default();
    bounds.max_image_width = Some(limits::IMAGE_SIDE);
    bounds.max_image_height = Some(limits::IMAGE_SIDE);
    bounds.max_alloc = Some(limits::IMAGE_DECODED);
    reader.limits(bounds);
    let name = format!("{format:?}").to_uppercase();
    reader.decode().map_err(|e| {
        err(
            what,
            path,
            match e {
                image::ImageError::Limits(_) => format!(
                    "it is too large: at most {} pixels a side and {} decoded",
                    limits::IMAGE_SIDE,
                    crate::files::show_size(limits::IMAGE_DECODED)
                ),
                image::ImageError::Decoding(d) => format!("it is a corrupt {name} image ({d})"),
                other => other.to_string(),
            },
        )
    })
}

/// Load a PNG or JPEG texture.
pub fn load_texture(path: &Path) -> Result<Image, AssetError> {
    let img = decode_image("texture", path)?.to_rgba8();
    Ok(Image { width: img.width(), height: img.height(), rgba: img.into_raw() })
}

/// Load a grey heightmap (8 or 16 bit PNG, or JPEG) as values in [0, 1],
/// rows top to bottom; returns (width, height, values).
pub fn load_heightmap(path: &Path) -> Result<(u32, u32, Vec<f32>), AssetError> {
    let img = decode_image("heightmap", path)?.to_luma16();
    if img.width() < 2 || img.height() < 2 {
        return Err(err("heightmap", path, "it must be at least 2×2 pixels"));
    }
    Ok((img.width(), img.height(), img.pixels().map(|p| p.0[0] as f32 / 65535.0).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, contents: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("hydrolux-load-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, contents).unwrap();
        p
    }

    #[test]
    fn obj_without_normals_gets_them_and_drops_degenerates() {
        let p =
            temp("quad.obj", b"v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 3 2\nf 1 4 3\nf 1 1 2\n");
        let m = load_mesh(&p).unwrap();
        assert_eq!(m.triangle_count(), 2);
        for n in &m.normals {
            assert!((*n - Vec3::Y).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn bad_files_name_themselves() {
        let e = load_mesh(Path::new("/nonexistent/teapot.obj")).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/teapot.obj"), "{e}");
        let p = temp("junk.glb", b"this is not a glb file");
        let e = load_mesh(&p).unwrap_err().to_string();
        assert!(
            e.starts_with("cannot load mesh") && e.contains("junk.glb") && !e.contains('\n'),
            "{e}"
        );
        let p = temp("empty.obj", b"# nothing\n");
        assert!(load_mesh(&p).unwrap_err().to_string().contains("no (non-degenerate) triangles"));
        let p = temp("model.stl", b"solid");
        let e = load_mesh(&p).unwrap_err().to_string();
        assert!(e.contains("use .obj, .gltf or .glb"), "{e}");
        let p = temp("bad.png", b"\x89PNG garbage");
        let e = load_texture(&p).unwrap_err().to_string();
        assert!(e.starts_with("cannot load texture") && e.contains("bad.png"), "{e}");
    }

    /// A one-triangle glTF whose buffer is `uri` (36 bytes declared) and
    /// whose position accessor holds `count` vertices.
    fn triangle_gltf(uri: &str, count: u32) -> String {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3","min":[0,0,-1],"max":[1,0,0]}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "buffers":[{{"byteLength":36,"uri":"{uri}"}}]}}"#
        )
    }

    #[test]
    fn what_is_wrong_with_a_file_is_said_in_its_own_terms() {
        let reason = |p: &Path| load_mesh(p).unwrap_err().reason;
        // Not files at all.
        let dir = temp("x", b"").parent().unwrap().to_path_buf();
        assert_eq!(reason(&dir.join("sub.obj")), "no such file");
        std::fs::create_dir_all(dir.join("folder.obj")).unwrap();
        assert_eq!(reason(&dir.join("folder.obj")), "it is a folder, not a file");
        #[cfg(unix)]
        {
            let link = dir.join("zero.obj");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            assert!(reason(&link).contains("not a regular file"));
            let e = load_texture(&link.with_extension("png")).unwrap_err().reason;
            assert_eq!(e, "no such file");
        }
        // Corrupt OBJ, glTF and GLB.
        assert!(reason(&temp("bin.obj", &[0xff, 0xfe, 0x00])).contains("not text"));
        let e = reason(&temp("bad_v.obj", b"v 1 x 2\nv 0 0 0\nv 1 1 1\nf 1 2 3\n"));
        assert!(e.contains("vertex (`v`) line"), "{e}");
        assert!(reason(&temp("junk.gltf", b"not json")).contains("not valid glTF JSON"));
        assert!(
            reason(&temp("empty.glb", b"")).contains("not a GLB file")
                && reason(&temp("empty.glb", b"")).contains("it is empty")
        );
        assert!(
            reason(&temp("junk.glb", b"\x01\x02 random")).contains("it does not start with one")
        );
        let mut glb = b"glTF\x02\x00\x00\x00\xff\x00\x00\x00".to_vec();
        glb.extend_from_slice(&[0; 8]);
        let e = reason(&temp("short.glb", &glb));
        assert!(e.contains("truncated"), "{e}");
        // A missing buffer names the buffer's file, and who wanted it.
        let p = temp("needs_bin.gltf", triangle_gltf("missing%20part.bin", 3).as_bytes());
        let e = load_mesh(&p).unwrap_err();
        assert!(e.path.ends_with("missing part.bin") && e.what == "mesh buffer", "{e}");
        assert!(e.reason.contains("no such file") && e.reason.contains("needs_bin.gltf"), "{e}");
        // A buffer shorter than it says, and an accessor past its view's end.
        temp("short.bin", &[0; 12]);
        let e = load_mesh(&temp("short_bin.gltf", triangle_gltf("short.bin", 3).as_bytes()));
        assert!(e.unwrap_err().reason.contains("12 bytes, less than the 36"));
        temp("full.bin", &[0; 36]);
        let e = reason(&temp("past_end.gltf", triangle_gltf("full.bin", 4).as_bytes()));
        assert!(e.contains("accessor 0") && e.contains("past the end"), "{e}");
        // Found by fuzzing: signed 16-bit indices (the gltf crate's reader
        // panics on them), no elements, a missing POSITION accessor.
        let seed = String::from_utf8(crate::fuzz::seeds("gltf")[0].clone()).unwrap();
        assert!(mesh_from_bytes(Path::new("t.gltf"), seed.as_bytes()).is_ok());
        let bad = seed.replace("5123", "5122");
        let e = mesh_from_bytes(Path::new("t.gltf"), bad.as_bytes()).unwrap_err().reason;
        assert!(e.contains("accessor 1 has a type"), "{e}");
        let bad =
            seed.replace("\"count\":3,\"type\":\"SCALAR\"", "\"count\":0,\"type\":\"SCALAR\"");
        let e = mesh_from_bytes(Path::new("t.gltf"), bad.as_bytes()).unwrap_err().reason;
        assert!(e.contains("count 0"), "{e}");
        let bad = seed.replace("\"POSITION\":0", "\"POSITION\":7");
        let e = mesh_from_bytes(Path::new("t.gltf"), bad.as_bytes()).unwrap_err().reason;
        assert!(e.contains("POSITION"), "{e}");
        // Images that are not images, or too large.
        let e = load_heightmap(&temp("text.png", b"hello")).unwrap_err().reason;
        assert_eq!(e, "it is not a PNG or JPEG image");
    }

    #[test]
    fn gltf_triangle_loads_with_node_transform() {
        // A minimal glTF with one triangle in an embedded buffer, translated by +2 in y.
        let mut bin = Vec::new();
        for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        let b64 = crate::fuzz::base64(&bin);
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0,"translation":[0,2,0]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,-1],"max":[1,0,0]}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
        );
        let p = temp("tri.gltf", json.as_bytes());
        let m = load_mesh(&p).unwrap();
        assert_eq!(m.triangle_count(), 1);
        assert!(m.positions.iter().all(|p| p.y == 2.0));
        assert!((m.normals[0] - Vec3::Y).length() < 1e-6, "{}", m.normals[0]);
    }
}
