//! Mesh and image files: Wavefront OBJ (tobj), glTF 2.0 (.gltf/.glb), and
//! PNG/JPEG images for textures and heightmaps. Every failure names the file.
//! Meshes without normals get area-weighted normals; degenerate triangles
//! are dropped.

use super::Mesh;
use glam::{Mat4, Vec2, Vec3};
use std::path::Path;

#[derive(Debug, thiserror::Error, PartialEq)]
#[error("cannot load {what} {path}: {reason}")]
pub struct AssetError {
    pub what: &'static str,
    pub path: String,
    pub reason: String,
}

/// Fail early and plainly when the file is not there (the decoders' own
/// messages for that are vague).
fn exists(what: &'static str, path: &Path) -> Result<(), AssetError> {
    if path.is_file() { Ok(()) } else { Err(err(what, path, "no such file")) }
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
    exists("mesh", path)?;
    let ext =
        path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    let mesh = match ext.as_str() {
        "obj" => load_obj(path)?,
        "gltf" | "glb" => load_gltf(path)?,
        _ => return Err(err("mesh", path, "unsupported format: use .obj, .gltf or .glb")),
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

fn load_obj(path: &Path) -> Result<Mesh, AssetError> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    // Materials (.mtl) are not used: the scene gives each object its material.
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| err("mesh", path, e))?;
    obj_models_to_mesh(&models, path)
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

fn load_gltf(path: &Path) -> Result<Mesh, AssetError> {
    let (doc, buffers, _images) = gltf::import(path).map_err(|e| err("mesh", path, e))?;
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

/// Load a PNG or JPEG texture.
pub fn load_texture(path: &Path) -> Result<Image, AssetError> {
    exists("texture", path)?;
    let img = image::open(path).map_err(|e| err("texture", path, e))?.to_rgba8();
    Ok(Image { width: img.width(), height: img.height(), rgba: img.into_raw() })
}

/// Load a grey heightmap (8 or 16 bit PNG, or JPEG) as values in [0, 1],
/// rows top to bottom; returns (width, height, values).
pub fn load_heightmap(path: &Path) -> Result<(u32, u32, Vec<f32>), AssetError> {
    exists("heightmap", path)?;
    let img = image::open(path).map_err(|e| err("heightmap", path, e))?.to_luma16();
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

    #[test]
    fn gltf_triangle_loads_with_node_transform() {
        // A minimal glTF with one triangle in an embedded buffer, translated by +2 in y.
        let mut bin = Vec::new();
        for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        let b64 = base64_encode(&bin);
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

    fn base64_encode(data: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for c in data.chunks(3) {
            let n = (c[0] as u32) << 16
                | (*c.get(1).unwrap_or(&0) as u32) << 8
                | *c.get(2).unwrap_or(&0) as u32;
            for i in 0..4 {
                if i <= c.len() {
                    s.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
                } else {
                    s.push('=');
                }
            }
        }
        s
    }
}
