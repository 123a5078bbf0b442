//! What `hydrolux view` and the web page (`hydrolux-web`) share, so that
//! both show the same controls: the scene editor ([`SceneEditor`]), an
//! egui panel generated from the scene's TOML table (new scene parameters
//! appear without UI code), and the camera ([`FlyCamera`]) that keys,
//! mouse and touch steer.

pub mod camera;
pub mod editor;

pub use camera::FlyCamera;
pub use editor::SceneEditor;
