//! The scene's opaque geometry as meshes with transforms and materials:
//! `[[objects]]` (primitives and mesh files), and the `[floor]` (flat, or a
//! terrain from noise or a heightmap). Relative paths start at the scene
//! file's folder. The renderer uploads this list as it is.

use super::{MaterialDesc, Primitive, Scene, TerrainKind};
use crate::coupling::Shape;
use crate::geometry::load::{AssetError, builtin_mesh, load_heightmap, load_mesh};
use crate::geometry::terrain::{BasinParams, Terrain};
use crate::geometry::{Mesh, primitives};
use glam::{DVec3, Mat4, Vec2, Vec3};

pub struct SceneObject {
    pub name: String,
    pub mesh: Mesh,
    pub transform: Mat4,
    pub material: MaterialDesc,
    /// World-space box that casts shadows (`None`: casts none, e.g. the flat floor).
    pub shadow_bounds: Option<(Vec3, Vec3)>,
    /// Its shape as an ambient occluder (`crate::occlusion`): opaque
    /// spheres, boxes and cylinders; `None` for meshes, planes, the floor,
    /// clear objects.
    pub occluder: Option<crate::occlusion::Shape>,
}

/// Half-side of the flat floor and of the terrain's skirt (m).
pub const FLOOR_EXTENT: f32 = 20_000.0;

/// The flat floor at `depth` below the water level, out to FLOOR_EXTENT:
/// a grid whose lines double their spacing away from the origin (0.25 m
/// cells at the centre), so that no triangle near the scene is kilometres
/// long. Two 40 km triangles rasterise with visible depth and texture
/// coordinate errors on GPUs with less precise interpolation (SwiftShader,
/// many mobile GPUs): the floor came out nearer than it is.
fn flat_floor(depth: f32) -> Mesh {
    let mut lines: Vec<f32> = vec![0.0, FLOOR_EXTENT, -FLOOR_EXTENT];
    let mut step = 0.25;
    while step < FLOOR_EXTENT {
        lines.extend([step, -step]);
        step *= 2.0;
    }
    lines.sort_by(f32::total_cmp);
    let n = lines.len();
    let mut positions = Vec::with_capacity(n * n);
    for &z in &lines {
        for &x in &lines {
            positions.push(Vec3::new(x, -depth, z));
        }
    }
    let mut indices = Vec::with_capacity((n - 1) * (n - 1) * 6);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
            // Counter-clockwise seen from above, as the two-triangle floor was.
            indices.extend([a, c, d, a, d, b]);
        }
    }
    Mesh {
        uvs: positions.iter().map(|p| Vec2::new(p.x, p.z)).collect(),
        normals: vec![Vec3::Y; positions.len()],
        positions,
        indices,
    }
}

impl Scene {
    /// An object's shape as an ambient occluder (`crate::occlusion`):
    /// opaque spheres, boxes and cylinders; not meshes, planes or clear
    /// objects.
    pub fn occluder_shape(o: &super::ObjectDesc) -> Option<crate::occlusion::Shape> {
        use crate::occlusion::Shape;
        match o.primitive {
            _ if !o.mesh.is_empty() || o.material.ior > 0.0 => None,
            Primitive::Box => Some(Shape::Box),
            Primitive::Sphere => Some(Shape::Sphere),
            Primitive::Cylinder => Some(Shape::Cylinder),
            Primitive::Plane => None,
        }
    }

    /// Each object's place among the occluders the GPU holds (the first
    /// `MAX_OCCLUDERS` occluding objects, in order), so that a surface does
    /// not occlude itself; `NO_OCCLUDER` for the rest.
    pub fn occluder_slots(&self) -> Vec<u32> {
        let mut next = 0u32;
        self.objects
            .iter()
            .map(|o| match Scene::occluder_shape(o) {
                Some(_) if (next as usize) < crate::occlusion::MAX_OCCLUDERS => {
                    next += 1;
                    next - 1
                }
                _ => crate::occlusion::NO_OCCLUDER,
            })
            .collect()
    }

    /// The terrain floor, if the floor is one (reads a heightmap file).
    pub fn terrain(&self) -> Result<Option<Terrain>, AssetError> {
        let f = &self.floor;
        Ok(match f.terrain {
            TerrainKind::None => None,
            TerrainKind::Noise => Some(Terrain::basin(&BasinParams {
                size: f.size,
                resolution: f.resolution as usize,
                depth: f.depth,
                shore_radius: f.shore_radius,
                shore_height: f.shore_height,
                relief: f.relief,
                seed: f.seed,
            })),
            TerrainKind::Heightmap => {
                let (w, h, v) = load_heightmap(&self.resolve_path(&f.heightmap))?;
                Some(Terrain::from_heightmap(
                    w,
                    h,
                    &v,
                    f.size,
                    f.depth,
                    f.relief,
                    f.resolution as usize,
                ))
            }
        })
    }

    /// The ground as a heightfield for ray tracing (`water.method =
    /// "raytrace"`): the terrain's samples (beyond its square, the mean of
    /// its edge), or a flat floor that goes on forever; `None` without a
    /// floor (bottomless water).
    pub fn ground_heightfield(&self) -> Result<Option<crate::raytrace::Heightfield>, AssetError> {
        use crate::raytrace::Heightfield;
        let f = &self.floor;
        if let Some(t) = self.terrain()? {
            let n = t.n;
            let edge: Vec<f32> = (0..n)
                .flat_map(|k| {
                    [
                        t.heights[k],
                        t.heights[(n - 1) * n + k],
                        t.heights[k * n],
                        t.heights[k * n + n - 1],
                    ]
                })
                .collect();
            let outside = edge.iter().sum::<f32>() / edge.len() as f32;
            let half = 0.5 * t.size;
            return Ok(Some(Heightfield {
                origin: [-half, -half],
                cell: t.size / (n - 1) as f32,
                n,
                heights: t.heights,
                outside,
            }));
        }
        if f.depth > 0.0 {
            return Ok(Some(Heightfield::sampled([-1.0, -1.0], 2.0, 2, -f.depth, |_, _| -f.depth)));
        }
        Ok(None)
    }

    /// The mesh an object names (`mesh`): a built-in (`builtin:NAME`) or a
    /// file beside the scene.
    pub fn object_mesh_file(
        &self,
        o: &super::ObjectDesc,
    ) -> Result<crate::geometry::Mesh, AssetError> {
        match o.mesh.strip_prefix("builtin:") {
            Some(name) => builtin_mesh(name),
            None => load_mesh(&self.resolve_path(&o.mesh)),
        }
    }

    /// Load and build every mesh of the scene (reads mesh and image files).
    pub fn build_geometry(&self) -> Result<Vec<SceneObject>, AssetError> {
        let mut out = Vec::new();
        let f = &self.floor;
        match f.terrain {
            TerrainKind::None if f.depth > 0.0 => {
                let mesh = flat_floor(f.depth);
                out.push(SceneObject {
                    name: "floor".into(),
                    mesh,
                    transform: Mat4::IDENTITY,
                    material: f.material.clone(),
                    shadow_bounds: None,
                    occluder: None,
                });
            }
            TerrainKind::None => {}
            TerrainKind::Noise | TerrainKind::Heightmap => {
                let terrain = self.terrain()?.expect("a terrain floor");
                let (lo, hi) = terrain
                    .heights
                    .iter()
                    .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
                let half = 0.5 * f.size;
                let bounds = (Vec3::new(-half, lo, -half), Vec3::new(half, hi, half));
                out.push(SceneObject {
                    name: "terrain".into(),
                    mesh: terrain.to_mesh(FLOOR_EXTENT),
                    transform: Mat4::IDENTITY,
                    material: f.material.clone(),
                    shadow_bounds: Some(bounds),
                    occluder: None,
                });
            }
        }
        for (i, o) in self.objects.iter().enumerate() {
            let mesh = if o.mesh.is_empty() {
                match o.primitive {
                    Primitive::Box => primitives::cube(),
                    Primitive::Sphere => primitives::sphere(64, 32),
                    Primitive::Cylinder => primitives::cylinder(64),
                    Primitive::Plane => primitives::plane(),
                }
            } else {
                self.object_mesh_file(o)?
            };
            let transform = Scene::object_transform(o);
            let shadow_bounds = mesh.bounds(&transform);
            let name = if o.name.is_empty() { format!("objects[{i}]") } else { o.name.clone() };
            let occluder = Scene::occluder_shape(o);
            out.push(SceneObject {
                name,
                mesh,
                transform,
                material: o.material.clone(),
                shadow_bounds,
                occluder,
            });
        }
        Ok(out)
    }
}

/// A primitive object as a rigid body's shape (`bodies`, `coupling`).
impl super::Scene {
    /// The scene's floor and objects as a body world takes them, every
    /// moving one (`surface_bodies` and `liquid_bodies` share them out).
    pub fn bodies(&self) -> crate::bodies::BodiesDesc {
        crate::bodies::BodiesDesc {
            floor_depth: self.floor.depth,
            objects: self
                .objects
                .iter()
                .map(|o| crate::bodies::BodyDesc {
                    transform: Self::object_transform(o),
                    shape: Shape::of(o),
                    scale: o.scale,
                    velocity: o.velocity,
                    path: o.path.as_ref().and_then(|p| p.build().ok()),
                    dynamic: o.dynamic,
                    density: o.density,
                    elsewhere: false,
                })
                .collect(),
        }
    }
}

impl Shape {
    /// The shape of a primitive object (`None` for meshes, planes and
    /// scalings a shape cannot follow, e.g. a squashed sphere).
    pub fn of(o: &super::ObjectDesc) -> Option<Shape> {
        if !o.mesh.is_empty() {
            return None;
        }
        let s = o.scale.map(|c| c.abs() as f64);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.max(b);
        match o.primitive {
            Primitive::Sphere if close(s[0], s[1]) && close(s[1], s[2]) => {
                Some(Shape::Sphere { radius: 0.5 * s[0] })
            }
            Primitive::Box => Some(Shape::Box { half: DVec3::from(s) * 0.5 }),
            Primitive::Cylinder if close(s[0], s[2]) => {
                Some(Shape::Cylinder { radius: 0.5 * s[0], half_height: 0.5 * s[1] })
            }
            _ => None,
        }
    }
}
