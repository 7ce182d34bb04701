//! StarCages viewport: what the artist sees. A wgpu renderer of the deformed mesh, cages and
//! influence maps, independent of egui (the editor embeds it through egui-wgpu paint callbacks;
//! the CLI renders offscreen), GPU deformation with the compiled operator, and the camera and
//! picking maths as pure functions.
//!
//! * [`camera`], [`picking`]: orbit camera, rays, projection, vertex picking, rectangle
//!   selection — no GPU.
//! * [`colors`], [`layers`], [`influence`], [`matcap`]: the colour code, line and dot geometry
//!   of cages, influence-map values with their legend, the built-in matcaps — no GPU.
//! * [`gpu`]: device, shaders (WGSL in `shaders/`), [`gpu::SceneRenderer`],
//!   [`gpu::GpuDeformer`].
//! * [`offscreen`]: images without a window, `render_to_image`.

pub mod camera;
pub mod colors;
pub mod gpu;
pub mod influence;
pub mod layers;
pub mod matcap;
pub mod offscreen;
pub mod picking;

pub use camera::{OrbitCamera, View};
pub use gpu::{GpuContext, GpuError, Layers, SceneRenderer, Shading};
pub use matcap::Matcap;
pub use offscreen::{RenderOptions, framing_camera, render_to_image};
