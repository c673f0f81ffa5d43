//! The traversals and their typed options. A [`Traversal`] is one axis of
//! the render pipeline (the field source is the other): its structural
//! choices are compiled into the kernel (which modalities or secondary rays
//! exist), its values are uniforms, so changing them never recompiles.

use super::settings::{SettingsError, SettingsField as F};
use super::Bound;
use crate::ir::Domain;
use crate::layout::KernelColor;

/// How rays find the surface.
#[derive(Debug, Clone, PartialEq)]
pub enum Traversal {
    /// Knoll et al.'s stackless interval / affine bisection with the tile
    /// pass: robust for any formula.
    Bisect(BisectOptions),
    /// Keinert et al.'s enhanced sphere tracing: for distance bounds only.
    Sphere(SphereOptions),
}

impl Traversal {
    /// The method name of this traversal.
    pub fn method(&self) -> super::Method {
        match self {
            Traversal::Bisect(_) => super::Method::Bisect,
            Traversal::Sphere(_) => super::Method::Sphere,
        }
    }

    /// Checks the options a user can get wrong.
    pub fn check(&self) -> Result<(), SettingsError> {
        match self {
            Traversal::Bisect(b) => b.modalities.check(),
            Traversal::Sphere(s) => s.check(),
        }
    }
}

/// Bisection's options.
#[derive(Debug, Clone, PartialEq)]
pub struct BisectOptions {
    /// The inclusion algebra (interval or affine).
    pub algebra: Domain,
    /// Knoll et al.'s visualisation modalities.
    pub modalities: Modalities,
    /// The traversal's optimisations (uniforms).
    pub optimizations: Optimizations,
    /// How a root bracket is closed in on (compiled into the kernel).
    pub root_search: RootSearch,
}

impl BisectOptions {
    /// Bisection in `algebra` without modalities, every optimisation on.
    pub fn new(algebra: Domain) -> BisectOptions {
        BisectOptions { algebra, modalities: Modalities::default(), optimizations: Optimizations::default(), root_search: RootSearch::Auto }
    }
}

/// How bisection closes in on the root of a bracket it found (a monotone
/// cell whose ends differ in sign, or a leaf's sign change): structural,
/// so a kernel has one of them. Both stop at the same eps width, so the
/// hits agree to eps (src/tests/render.rs compares them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RootSearch {
    /// Two points for a compiled formula of up to
    /// `field::compiled::source::PAIR_MAX_NODES` nodes, else one (a bigger f keeps
    /// the core busy on its own, and its second point costs what it saves).
    #[default]
    Auto,
    /// One point of f a step: the ITP method (templates/traverse/bisect/root_search_one_point.wgsl).
    OnePoint,
    /// Two independent points of f a step, a secant pair or the bracket's
    /// thirds (root_search_two_points.wgsl): on a CPU device the second point runs in
    /// the time a cheap f's chain of dependent operations leaves idle.
    /// Only for a compiled field: an interpreted one keeps one point.
    TwoPoints,
}

/// Switches for bisection's optimisations, so their effect can be measured
/// and their results compared (every combination is exact: each only skips
/// work that is proven unnecessary).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Optimizations {
    /// Tile pass: enclose f over depth slabs of each 8×8 tile's frustum and
    /// let rays skip the slabs proven empty.
    pub tile_culling: bool,
    /// Derivative enclosures from depth [`Optimizations::monotone_depth`] on:
    /// monotone cells are rejected or solved by scalar root finding, the
    /// others are also bounded by the mean-value form.
    pub monotone: bool,
    /// First bisection depth at which the derivative is evaluated. 0 (the
    /// whole segment) is the default, chosen by measurement on the Knoll
    /// surfaces (docs/benchmarks.md): faster than a deeper start on their
    /// geometric mean, and most on cloth.
    pub monotone_depth: u32,
    /// A tape field with min or max runs, in each tile, only the
    /// instructions that can reach f over the tile's candidate slabs (the
    /// tile pass notes which operand each min and max can take there).
    pub tape_shortening: bool,
}

impl Default for Optimizations {
    fn default() -> Self {
        Optimizations { tile_culling: true, monotone: true, monotone_depth: 0, tape_shortening: true }
    }
}

/// An environment image (equirectangular), rgba8 packed per texel.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major rgba8 texels (`u32::from_le_bytes([r, g, b, a])`).
    pub texels: Vec<u32>,
}

/// What reflections and the background see.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Environment {
    /// A sky gradient above a dark horizon.
    #[default]
    Sky,
    /// The sky above a checkered ground.
    Checker,
    /// An equirectangular image.
    Image(EnvImage),
}

impl Environment {
    /// The kernel's `ENV_MODE`: 0 sky, 1 checker, 2 image.
    pub fn mode(&self) -> u32 {
        match self {
            Environment::Sky => 0,
            Environment::Checker => 1,
            Environment::Image(_) => 2,
        }
    }
}

/// Most isovalues, transparency layers and reflection bounces a kernel has.
pub const MAX_MODALITY_COUNT: u32 = 8;

/// Knoll et al.'s visualisation modalities. Structural choices (which code
/// exists) are compiled in; values are uniforms.
#[derive(Debug, Clone, PartialEq)]
pub struct Modalities {
    /// Shadow rays from the point light.
    pub shadows: bool,
    /// Point light (default: above and left of the eye).
    pub light: Option<glam::DVec3>,
    /// eps of shadow rays (default 4 × eps).
    pub shadow_eps: Option<f64>,
    /// Surface layers per pixel (1: opaque).
    pub layers: u32,
    /// Per-layer opacity when layers > 1.
    pub opacity: f64,
    /// Isovalues (empty: just 0). At most 8.
    pub isovalues: Vec<f64>,
    /// Reflection bounces.
    pub reflect: u32,
    /// Weight of each reflection.
    pub reflectivity: f64,
    /// What the kernel draws: Phong, |grad f| or depth.
    pub color: KernelColor,
    /// The environment.
    pub env: Environment,
    /// User WGSL (`--inline`): functions and hooks.
    pub inline: Option<crate::inline::InlineWgsl>,
}

impl Default for Modalities {
    fn default() -> Self {
        Modalities {
            shadows: false,
            light: None,
            shadow_eps: None,
            layers: 1,
            opacity: 1.0,
            isovalues: vec![],
            reflect: 0,
            reflectivity: 0.35,
            color: KernelColor::Phong,
            env: Environment::Sky,
            inline: None,
        }
    }
}

impl Modalities {
    /// Checks counts and weights.
    pub fn check(&self) -> Result<(), SettingsError> {
        let max = MAX_MODALITY_COUNT;
        if self.isovalues.len() > max as usize {
            return Err(SettingsError::new(F::Isovalues, self.isovalues.len().to_string(), format!("at most {max} isovalues")));
        }
        if let Some(v) = self.isovalues.iter().find(|v| !v.is_finite()) {
            return Err(SettingsError::new(F::Isovalues, v.to_string(), "isovalues must be finite numbers"));
        }
        if self.layers == 0 || self.layers > max {
            return Err(SettingsError::new(F::Layers, self.layers.to_string(), format!("it must be between 1 and {max}")));
        }
        if !(self.opacity > 0.0 && self.opacity <= 1.0) {
            return Err(SettingsError::new(F::Opacity, self.opacity.to_string(), "it must be in (0, 1]"));
        }
        if self.reflect > max {
            return Err(SettingsError::new(F::Reflect, self.reflect.to_string(), format!("at most {max} bounces")));
        }
        if !(0.0..=1.0).contains(&self.reflectivity) {
            return Err(SettingsError::new(F::Reflectivity, self.reflectivity.to_string(), "it must be in [0, 1]"));
        }
        if self.color == KernelColor::Field {
            return Err(SettingsError::new(F::Features, "field", "the field colouring belongs to sphere tracing"));
        }
        Ok(())
    }
}

/// Largest `max_steps`: the primary, shadow and refraction rays each get
/// the budget, and lavapipe silently stops any invocation after 65,535 loop
/// iterations in total.
pub const MAX_STEPS_LIMIT: u32 = 16_000;
/// Default step budget per ray.
pub const DEFAULT_MAX_STEPS: u32 = 512;
/// Default over-relaxation factor (Keinert et al.: ω ≈ 1.2 was best).
pub const DEFAULT_OMEGA: f64 = 1.2;
/// Default fixed-point iterations of the discontinuity reduction (the
/// paper's final renders use 3).
pub const DEFAULT_FIXPOINT: u32 = 3;
/// Largest `fixpoint`.
pub const MAX_FIXPOINT: u32 = 64;

/// What a sphere traced pixel's colour shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shading {
    /// Phong shading (with shadows or glass when asked for).
    #[default]
    Shade,
    /// f(p) / err(t) at the hit point as a heat map: technique 4 makes it flat.
    Field,
}

/// Sphere tracing settings; every technique can be switched off so its
/// effect can be measured.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereOptions {
    /// The field is divided by this (≥ 1) to make it 1-Lipschitz.
    pub lipschitz: f64,
    /// Technique 1: over-relaxation factor in [1, 2); 1 is off.
    pub omega: f64,
    /// Technique 2: half-pixel termination and best-candidate choice; off:
    /// terminate at |f| < eps and keep the last point.
    pub screen_space: bool,
    /// Technique 3: secondary rays start 2·max(eps_min, |f(p)|) off the
    /// surface; off: eps_min.
    pub dynamic_eps: bool,
    /// Technique 3's minimum offset and the secondary rays' threshold
    /// (default: the frame's eps).
    pub eps_min: Option<f64>,
    /// Technique 4: fixed-point iterations after a hit; 0 is off.
    pub fixpoint: u32,
    /// Technique 5: a convex bound of a convex object; `None` is off.
    pub bound: Option<Bound>,
    /// Step budget per ray.
    pub max_steps: u32,
    /// Smallest forward step (world units; 0: none).
    pub min_step: f64,
    /// Cast a shadow ray towards the key light.
    pub shadows: bool,
    /// Render the object as absorbing glass (one refraction through it).
    pub glass: bool,
    /// What the colour shows.
    pub shading: Shading,
    /// A scene's primary rays: the rays of an 8×8 tile walk its depth slabs
    /// together, each slab's view copied into workgroup memory (Zanni et
    /// al.'s Algorithm 3); off: each ray walks them on its own, reading the
    /// views where the views pass wrote them (faster on lavapipe:
    /// docs/benchmarks.md). Part of the kernel; other fields ignore it.
    pub synchronized: bool,
}

impl Default for SphereOptions {
    fn default() -> Self {
        SphereOptions {
            lipschitz: 1.0,
            omega: DEFAULT_OMEGA,
            screen_space: true,
            dynamic_eps: true,
            eps_min: None,
            fixpoint: DEFAULT_FIXPOINT,
            bound: None,
            max_steps: DEFAULT_MAX_STEPS,
            min_step: 0.0,
            shadows: false,
            glass: false,
            shading: Shading::Shade,
            synchronized: false,
        }
    }
}

/// The secondary rays compiled into a sphere tracing kernel. They are
/// code, not uniforms: lavapipe inlines every call and pays for the unused
/// ray loops (the city renders several times slower with both compiled in
/// but switched off).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SphereFeatures {
    /// Shadow rays.
    pub shadows: bool,
    /// Refraction rays (glass).
    pub glass: bool,
    /// A scene's synchronised tile walk (`SphereOptions::synchronized`).
    pub synchronized: bool,
}

impl SphereOptions {
    /// The code these options need.
    pub fn features(&self) -> SphereFeatures {
        SphereFeatures { shadows: self.shadows, glass: self.glass, synchronized: self.synchronized }
    }

    /// Checks the values a user can get wrong.
    pub fn check(&self) -> Result<(), SettingsError> {
        if !(self.lipschitz >= 1.0 && self.lipschitz.is_finite()) {
            return Err(SettingsError::new(
                F::Lipschitz,
                self.lipschitz.to_string(),
                "a Lipschitz bound must be at least 1 (sphere tracing divides the field by it; \
                 a smaller value would step further than a distance field allows)",
            ));
        }
        if !(self.omega >= 1.0 && self.omega < 2.0) {
            return Err(SettingsError::new(F::Omega, self.omega.to_string(), "the over-relaxation factor must be in [1, 2) (1 switches it off)"));
        }
        if self.max_steps == 0 || self.max_steps > MAX_STEPS_LIMIT {
            return Err(SettingsError::new(F::MaxSteps, self.max_steps.to_string(), format!("it must be between 1 and {MAX_STEPS_LIMIT}")));
        }
        if self.fixpoint > MAX_FIXPOINT {
            return Err(SettingsError::new(F::Fixpoint, self.fixpoint.to_string(), format!("at most {MAX_FIXPOINT} iterations")));
        }
        if !(self.min_step >= 0.0 && self.min_step.is_finite()) {
            return Err(SettingsError::new(F::MinStep, self.min_step.to_string(), "it must be a width >= 0"));
        }
        if let Some(e) = self.eps_min.filter(|e| !(*e > 0.0 && e.is_finite())) {
            return Err(SettingsError::new(F::EpsMin, e.to_string(), "it must be a positive width"));
        }
        Ok(())
    }
}

/// Where a `--env` / `env:` environment comes from, before loading.
#[derive(Debug, Clone, PartialEq)]
pub enum EnvSpec {
    /// The procedural sky.
    Sky,
    /// The sky above a checkered ground.
    Checker,
    /// An equirectangular PNG (a header's relative path is resolved against
    /// the header's file when it is loaded).
    File(std::path::PathBuf),
}

impl EnvSpec {
    /// `sky`, `checker` or a file path.
    pub fn parse(s: &str) -> EnvSpec {
        match s.trim() {
            "sky" => EnvSpec::Sky,
            "checker" => EnvSpec::Checker,
            path => EnvSpec::File(path.into()),
        }
    }
}

/// Modalities as a header or flags give them: each value optional, so a
/// header's values can be defaults that flags override
/// ([`ModalitySpec::or`]); [`ModalitySpec::resolve`] applies the documented
/// defaults once and checks the result.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModalitySpec {
    /// Shadow rays.
    pub shadows: Option<bool>,
    /// Point light.
    pub light: Option<glam::DVec3>,
    /// eps of shadow rays.
    pub shadow_eps: Option<f64>,
    /// Per-layer opacity (default 0.5 with several layers, else 1).
    pub opacity: Option<f64>,
    /// Layers (default 4 when the opacity is below 1, else 1).
    pub layers: Option<u32>,
    /// Isovalues.
    pub iso: Option<Vec<f64>>,
    /// Reflection bounces.
    pub reflect: Option<u32>,
    /// Reflection weight.
    pub reflectivity: Option<f64>,
    /// Environment.
    pub env: Option<EnvSpec>,
}

impl ModalitySpec {
    /// These values, with `defaults` where these give none.
    pub fn or(&self, defaults: &ModalitySpec) -> ModalitySpec {
        ModalitySpec {
            shadows: self.shadows.or(defaults.shadows),
            light: self.light.or(defaults.light),
            shadow_eps: self.shadow_eps.or(defaults.shadow_eps),
            opacity: self.opacity.or(defaults.opacity),
            layers: self.layers.or(defaults.layers),
            iso: self.iso.clone().or_else(|| defaults.iso.clone()),
            reflect: self.reflect.or(defaults.reflect),
            reflectivity: self.reflectivity.or(defaults.reflectivity),
            env: self.env.clone().or_else(|| defaults.env.clone()),
        }
    }

    /// The modalities with the kernel colour `color`; `load` reads an
    /// environment image (the caller decides how files are read and how a
    /// failure is reported).
    pub fn resolve<E>(&self, color: KernelColor, load: impl Fn(&std::path::Path) -> Result<EnvImage, E>) -> Result<Result<Modalities, SettingsError>, E> {
        let d = Modalities::default();
        let layers = self.layers.unwrap_or(if self.opacity.is_some_and(|o| o < 1.0) { 4 } else { 1 });
        let env = match &self.env {
            None | Some(EnvSpec::Sky) => Environment::Sky,
            Some(EnvSpec::Checker) => Environment::Checker,
            Some(EnvSpec::File(p)) => Environment::Image(load(p)?),
        };
        let m = Modalities {
            shadows: self.shadows.unwrap_or(false),
            light: self.light,
            shadow_eps: self.shadow_eps,
            layers,
            opacity: self.opacity.unwrap_or(if layers > 1 { 0.5 } else { 1.0 }),
            isovalues: self.iso.clone().unwrap_or_default(),
            reflect: self.reflect.unwrap_or(0),
            reflectivity: self.reflectivity.unwrap_or(d.reflectivity),
            color,
            env,
            inline: None,
        };
        Ok(m.check().map(|()| m))
    }
}
