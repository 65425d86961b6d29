//! CPU renderer of the UniPhys service: the face-ID renders of the decomposition stage
//! (reference §2) and the images shown to the LVLM (part composites, candidate axes and pivots,
//! reference §5 and §8). Synchronous, single-threaded, deterministic, no GPU.
//!
//! - [`Camera`]: pinhole camera (symmetric vertical field of view, square pixels);
//!   [`orbit_cameras`] (the reference's 8-view rig) and [`camera_from_direction`] frame a box.
//! - [`render_face_ids`] (or [`render_face_ids_into`], reusing buffers): z-buffered
//!   rasterisation into a [`FaceIdImage`] (triangle id, view depth and facing normal per pixel;
//!   triangles crossing the near plane are clipped).
//! - [`RgbaImage`], [`shade`] (Lambert), [`hstack`]/[`vstack`], [`draw`] (lines, discs,
//!   arrows, rectangles, 5x7 text), [`encode_png`]/[`decode_png`].
//! - [`lvlm_views`]: the part composites and the candidate-axis and pivot views for the LVLM.
//!
//! World coordinates are metres (Z up); image x grows to the right and y downwards.

mod camera;
pub mod draw;
mod error;
mod face_ids;
pub mod lvlm_views;
mod png_io;
mod raster;
mod rgba;
mod rig;
mod shade;

pub use camera::{Camera, DEFAULT_FOV_Y_RAD, NEAR_FRACTION, Projected};
pub use error::{RenderError, RenderResult};
pub use face_ids::{FaceIdImage, render_face_ids, render_face_ids_into};
pub use lvlm_views::{
    AXIS_COLOURS, PIVOT_COLOURS, PartScene, ViewOptions, axis_candidate_views, part_composite,
    pivot_candidate_views,
};
pub use png_io::{decode_png, encode_png};
pub use rgba::{RgbaImage, hstack, over, vstack};
pub use rig::{REFERENCE_RIG_DIRECTIONS, camera_from_direction, orbit_cameras, orbit_directions};
pub use shade::{AMBIENT, lambert, light_direction, shade};
