//! Scene objects: `[[objects]]`, primitives and meshes, static, moving or floating.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Primitive {
    Box,
    Sphere,
    Cylinder,
    Plane,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObjectDesc {
    pub name: String,
    /// Unit-size primitive (box of side 1, sphere and cylinder of diameter 1,
    /// plane of side 1 facing +y), scaled by `scale`.
    pub primitive: Primitive,
    /// An .obj, .gltf or .glb file, or a built-in mesh ("builtin:bunny");
    /// when given it replaces `primitive`.
    pub mesh: String,
    pub position: [f32; 3],
    /// Rotation about x, then y, then z (degrees).
    pub rotation_deg: [f32; 3],
    pub scale: [f32; 3],
    pub material: MaterialDesc,
    /// Moved by rigid-body physics (a sphere, box or cylinder primitive):
    /// gravity, contacts, and buoyancy and drag from the water it is in.
    pub dynamic: bool,
    /// Density (kg/m³) of a dynamic object (water: 1000).
    pub density: f32,
    /// Velocity (m/s): a dynamic object's at the start; any other object
    /// keeps it, moving steadily through the scene (a boat crossing).
    pub velocity: [f32; 3],
    /// A scripted path (`[objects.path]`, not with `dynamic` or `velocity`):
    /// the object follows its waypoints (world positions of its centre; its
    /// `position` is the path's at time 0) and turns with its heading.
    pub path: Option<crate::path::PathDesc>,
}

impl ObjectDesc {
    /// Whether it moves: dynamic, kinematic with a velocity, or on a path.
    pub fn moving(&self) -> bool {
        self.dynamic || self.velocity.iter().any(|&v| v != 0.0) || self.path.is_some()
    }

    /// Where its centre is at time 0: its path's first point, or `position`.
    pub fn start_position(&self) -> [f32; 3] {
        match &self.path {
            Some(p) if !p.points.is_empty() => p.points[0],
            _ => self.position,
        }
    }
}

impl Default for ObjectDesc {
    fn default() -> Self {
        ObjectDesc {
            name: String::new(),
            primitive: Primitive::Box,
            mesh: String::new(),
            position: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: [1.0; 3],
            material: MaterialDesc::default(),
            dynamic: false,
            density: 500.0,
            velocity: [0.0; 3],
            path: None,
        }
    }
}
