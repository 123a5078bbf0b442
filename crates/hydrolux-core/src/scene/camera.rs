//! The camera: `[camera]`.

use super::*;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDesc {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    pub fov_y_deg: f32,
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            position: [0.0, 6.0, 0.0],
            look_at: [0.0, 2.0, -60.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 55.0,
        }
    }
}

impl CameraDesc {
    /// The `[camera]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let c = self;
        range(
            "camera.fov_y_deg",
            c.fov_y_deg,
            c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0,
            "must be in (0, 180)",
        )?;
        // Each vector on its own first, so that the message names the key
        // that is wrong; then how they relate.
        let within = format!("must be finite, each coordinate within ±{WORLD_EXTENT_M} m");
        vec3_range("camera.position", c.position, WORLD_EXTENT_M, &within)?;
        vec3_range("camera.look_at", c.look_at, WORLD_EXTENT_M, &within)?;
        vec3_range("camera.up", c.up, f32::MAX, "must be finite")?;
        let (p, t, up) =
            (glam::Vec3::from(c.position), glam::Vec3::from(c.look_at), glam::Vec3::from(c.up));
        if (t - p).length() < 1e-4 {
            return Err(SceneError::OutOfRange {
                key: "camera.look_at".into(),
                value: format!("{:?}", c.look_at),
                allowed: "must differ from camera.position".into(),
            });
        }
        if up.length() < 1e-6 || (t - p).normalize().cross(up.normalize()).length() < 1e-4 {
            return Err(SceneError::OutOfRange {
                key: "camera.up".into(),
                value: format!("{:?}", c.up),
                allowed: "must be non-zero and not parallel to the view direction".into(),
            });
        }
        Ok(())
    }
}
