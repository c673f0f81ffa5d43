//! The uniforms of a dispatch: the frame block (camera, box, size, flags,
//! parameters), then the traversal's own block.

use super::binding::Binder;
use super::dispatch::Rect;
use super::renderer::RenderError;
use crate::layout::{FrameBlock, FLAG_UNRESOLVED_GUESS, FLAG_UNRESOLVED_SOLID};
use crate::render::{CameraBasis, Settings, SettingsError, Traversal, Unresolved};

/// The uniform bytes of a whole-frame dispatch of `traversal` (frame
/// block, then the traversal's block), device-free: what the viewer's page
/// starts from before it writes the camera and the sliders' values.
pub fn uniform_bytes(traversal: &Traversal, s: &Settings) -> Result<Vec<u8>, SettingsError> {
    let cam = s.camera.frame()?;
    let (flags, trav) = match traversal {
        Traversal::Bisect(b) => (super::bisect::flags(b), bytemuck::bytes_of(&super::bisect::block(b, s, &cam)).to_vec()),
        Traversal::Sphere(o) => (super::sphere::flags(o), bytemuck::bytes_of(&super::sphere::block(o, s, &cam)).to_vec()),
    };
    let mut fb = frame_block(s, &cam, flags);
    fb.tile_size = [s.width, s.height];
    let mut bytes = bytemuck::bytes_of(&fb).to_vec();
    bytes.extend_from_slice(&trav);
    Ok(bytes)
}

/// The uniforms of a dispatch of a frame over `rect`: the frame block, then
/// the traversal's block.
pub(super) fn uniforms(binder: &Binder<'_>, s: &Settings, rect: Rect) -> Result<Vec<u8>, RenderError> {
    let cam = s.camera.frame()?;
    let mut fb = frame_block(s, &cam, binder.host.flags() | binder.field.flags());
    fb.tile_origin = [rect.x, rect.y];
    fb.tile_size = [rect.w, rect.h];
    let mut bytes = bytemuck::bytes_of(&fb).to_vec();
    bytes.extend_from_slice(&binder.host.block(s, &cam));
    Ok(bytes)
}

/// The frame block of a frame (the tile fields are filled per dispatch).
fn frame_block(s: &Settings, cam: &CameraBasis, flags: u32) -> FrameBlock {
    let v4 = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let mut params = [0.0f32; crate::layout::MAX_PARAMS];
    params[..s.params.len()].copy_from_slice(&s.params);
    FrameBlock {
        eye: v4(s.camera.eye),
        forward: v4(cam.forward),
        right: v4(cam.right),
        up: v4(cam.up),
        box_min: [s.bbox[0] as f32, s.bbox[2] as f32, s.bbox[4] as f32, 0.0],
        box_max: [s.bbox[1] as f32, s.bbox[3] as f32, s.bbox[5] as f32, s.clip_sphere.unwrap_or(0.0) as f32],
        size: [s.width, s.height],
        tile_origin: [0, 0],
        tile_size: [0, 0],
        flags: match s.unresolved {
            Unresolved::Hatch => 0,
            Unresolved::Magenta => FLAG_UNRESOLVED_SOLID,
            Unresolved::Guess => FLAG_UNRESOLVED_GUESS,
        } | flags,
        tan_half_fov: cam.tan_half_fov as f32,
        eps: s.eps as f32,
        inf: f32::INFINITY,
        time: s.time as f32,
        pad0: 0,
        params,
    }
}
