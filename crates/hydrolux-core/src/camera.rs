//! Camera matrices shared by the renderer and CPU code (picking, tests):
//! right-handed, y up, reversed-Z with an infinite far plane so the sea keeps
//! depth precision out to the horizon.

use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
}

/// Near plane distance (m).
pub const NEAR: f32 = 0.05;

impl Camera {
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.position, self.look_at, self.up)
    }

    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective_infinite_reverse(
            self.fov_y_deg.to_radians(),
            aspect,
            NEAR,
        )
    }

    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// The view-projection of the same camera with its field of view widened
    /// so that tan(fov/2) grows by `1 + margin` (projective textures that
    /// waves must be able to look slightly beyond the screen in).
    pub fn view_projection_widened(&self, aspect: f32, margin: f32) -> Mat4 {
        let half = (0.5 * self.fov_y_deg.to_radians()).tan() * (1.0 + margin);
        let fov = 2.0 * half.atan();
        glam::camera::rh::proj::directx::perspective_infinite_reverse(fov, aspect, NEAR)
            * self.view()
    }

    /// Unit direction the camera looks along.
    pub fn forward(&self) -> Vec3 {
        (self.look_at - self.position).normalize()
    }
}
