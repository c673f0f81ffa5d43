//! Sphere tracing's part of the render pipeline on the host: its uniform
//! block (Keinert et al.'s techniques as values, so switching one on or off
//! for a measurement never recompiles) and its per-ray statistics word in
//! the pass group. A pixel's work is its marching steps (of its primary,
//! shadow and refraction rays; the fixed-point iterations and the normal
//! are a fixed cost per hit and not counted), and `Unresolved` means
//! "unconverged".

use super::dispatch::Rect;
use super::renderer::{PassBuffers, TraversalHost};
use super::{slot_entry, Gpu};
use crate::kernel::bindings::{RAY_STATS, TILE_IDS, TILE_LIST};
use crate::layout::{BoundKind, KernelColor, SphereBlock, FLAG_DYNAMIC_EPS, FLAG_GLASS, FLAG_SCREEN, FLAG_SHADOWS};
use crate::render::record::RayStats;
use crate::render::{Bound, CameraBasis, Optimizations, Settings, Shading, SphereOptions, Stats, Traversal};

/// Sphere tracing on the host.
pub(crate) struct Host {
    options: SphereOptions,
    /// Whether the kernel has a tile pass (`FieldSource::lists_tiles`,
    /// a scene): `main` then runs by indirect dispatch over the tiles it
    /// queues.
    tiles: bool,
}

impl Host {
    /// With these options, and with or without the tile pass.
    pub fn new(options: SphereOptions, tiles: bool) -> Host {
        Host { options, tiles }
    }
}

/// Sphere tracing's uniform block for a frame (device-free: the viewer's
/// page gets the same bytes).
pub(crate) fn block(o: &SphereOptions, s: &Settings, cam: &CameraBasis) -> SphereBlock {
    let f4 = |a: f64, b: f64, c: f64, d: f64| [a as f32, b as f32, c as f32, d as f32];
    let (bound_kind, bound_a, bound_b) = match o.bound {
        None => (BoundKind::None, [0.0; 4], [0.0; 4]),
        Some(Bound::Sphere { center: c, radius }) => (BoundKind::Sphere, f4(c[0], c[1], c[2], radius), [0.0; 4]),
        Some(Bound::Box(b)) => (BoundKind::Box, f4(b[0], b[2], b[4], 0.0), f4(b[1], b[3], b[5], 0.0)),
    };
    // A key light from the upper left and in front, so that shadows fall
    // visibly behind and beside the objects.
    let l = (0.8 * cam.up - 0.2 * cam.forward - 0.7 * cam.right).normalize();
    SphereBlock {
        bound_a,
        bound_b,
        light: f4(l.x, l.y, l.z, 0.0),
        max_steps: o.max_steps,
        fixpoint: o.fixpoint,
        bound_kind: bound_kind as u32,
        color_mode: match o.shading {
            Shading::Shade => KernelColor::Phong,
            Shading::Field => KernelColor::Field,
        } as u32,
        omega: o.omega as f32,
        inv_lipschitz: (1.0 / o.lipschitz) as f32,
        // Half a pixel at unit distance: the screen-space error bound.
        pixel_radius: (cam.tan_half_fov / s.height as f64) as f32,
        min_step: o.min_step as f32,
        eps_min: o.eps_min.unwrap_or(s.eps) as f32,
        pad0: 0,
        pad1: 0,
        pad2: 0,
    }
}

/// Sphere tracing's frame flags.
pub(crate) fn flags(o: &SphereOptions) -> u32 {
    let flag = |on: bool, bit: u32| if on { bit } else { 0 };
    flag(o.screen_space, FLAG_SCREEN) | flag(o.dynamic_eps, FLAG_DYNAMIC_EPS) | flag(o.shadows, FLAG_SHADOWS) | flag(o.glass, FLAG_GLASS)
}

impl TraversalHost for Host {
    fn block(&self, s: &Settings, cam: &CameraBasis) -> Vec<u8> {
        bytemuck::bytes_of(&block(&self.options, s, cam)).to_vec()
    }

    fn flags(&self) -> u32 {
        flags(&self.options)
    }

    fn frame_resources(&self) -> Vec<(wgpu::BindGroupLayoutEntry, &wgpu::Buffer)> {
        vec![]
    }

    /// The per-ray statistics words; with the tile pass, its tile list
    /// (with the indirect dispatch counts of `main`) and tile ids.
    fn pass_layout(&self) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut v = vec![slot_entry(&RAY_STATS)];
        if self.tiles {
            v.extend([slot_entry(&TILE_LIST), slot_entry(&TILE_IDS)]);
        }
        v
    }

    fn pass_buffers(&self, gpu: &Gpu, rect: Rect, _resumable: bool) -> PassBuffers {
        if !self.tiles {
            return PassBuffers { entries: vec![], list: None };
        }
        let (list, ids) = super::tile_list_buffers(gpu, rect);
        PassBuffers { entries: vec![(TILE_LIST.binding, list.clone()), (TILE_IDS.binding, ids)], list: Some(list) }
    }

    /// One 8×8 tile per workgroup (the kernel's `@workgroup_size(8, 8)`).
    fn tiles_per_group(&self) -> u32 {
        1
    }

    fn pre_pass(&self) -> bool {
        self.tiles
    }

    fn ray_stats_binding(&self) -> Option<u32> {
        Some(RAY_STATS.binding)
    }

    fn finish(&self, _s: &Settings, rays: &RayStats, stats: &mut Stats) {
        stats.sphere.sor_fallbacks = rays.fallbacks;
        stats.sphere.lipschitz_violations = rays.violations;
        stats.sphere.lipschitz_seen = rays.ratio * self.options.lipschitz;
    }

    fn options(&self) -> Traversal {
        Traversal::Sphere(self.options.clone())
    }

    fn method(&self) -> crate::render::Method {
        crate::render::Method::Sphere
    }

    fn optimizations_mut(&mut self) -> Option<&mut Optimizations> {
        None
    }

    fn sphere_options_mut(&mut self) -> Option<&mut SphereOptions> {
        Some(&mut self.options)
    }
}
