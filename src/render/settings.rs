//! The settings of one frame, independent of the traversal, and the one
//! typed error every settings check returns. The library names the setting
//! that is wrong ([`SettingsField`]) and why; only the command line knows
//! which flag or header key the user spelled it with.

use super::Camera;

/// Largest image side accepted.
pub const MAX_SIZE: u32 = 16384;
/// Default iteration budget of bisection.
pub const DEFAULT_MAX_ITER: u32 = 8192;
/// Largest iteration budget: lavapipe silently stops a shader loop after
/// 65,535 iterations, so every budget stays well below.
pub const MAX_ITER_LIMIT: u32 = 60_000;

/// Everything one frame needs besides the field and the traversal.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Domain box `x0, x1, y0, y1, z0, z1`.
    pub bbox: [f64; 6],
    /// The camera.
    pub camera: Camera,
    /// Absolute termination width along the ray.
    pub eps: f64,
    /// Time value `t`.
    pub time: f64,
    /// Parameter values in the formula's parameter order.
    pub params: Vec<f32>,
    /// Iteration budget per pixel of bisection (well below lavapipe's
    /// 65,535 loop cap).
    pub max_iter: u32,
    /// Largest tile side per dispatch.
    pub tile: u32,
    /// How pixels whose traversal ran out of budget are drawn.
    pub unresolved: Unresolved,
    /// Also clip rays to the ball of this radius around the box centre.
    pub clip_sphere: Option<f64>,
}

/// How a pixel whose traversal ran out of budget (bisection: unresolved;
/// sphere tracing: unconverged) is drawn. Its position is only the nearest
/// cell that may hold the surface (or the best candidate of the march), so
/// by default it must not look like a hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Unresolved {
    /// The best guess, shaded, under diagonal magenta stripes: visibly not
    /// a hit, yet it still shows where the surface probably is.
    #[default]
    Hatch,
    /// Solid magenta (for finding them in a picture).
    Magenta,
    /// The best guess, shaded like a hit (the warning is still printed).
    Guess,
}

impl Settings {
    /// The CLI's defaults for a box and an image size: the default camera,
    /// eps = 2^-11 × the box diagonal, t = 0, no parameters, no clip ball.
    pub fn for_box(bbox: [f64; 6], width: u32, height: u32) -> Settings {
        Settings {
            width,
            height,
            bbox,
            camera: Camera::default_for(&bbox, 40.0, width as f64 / height as f64),
            eps: super::box_diagonal(&bbox) * 2f64.powi(-11),
            time: 0.0,
            params: vec![],
            max_iter: DEFAULT_MAX_ITER,
            tile: 1024,
            unresolved: Unresolved::Hatch,
            clip_sphere: None,
        }
    }

    /// Checks size, box, camera, eps, time, clip ball and budget before any
    /// GPU work (shared by every traversal).
    pub fn check(&self) -> Result<(), SettingsError> {
        use SettingsField as F;
        if self.width == 0 || self.height == 0 || self.width > MAX_SIZE || self.height > MAX_SIZE {
            return Err(SettingsError::new(F::Size, format!("{}x{}", self.width, self.height), format!("each side must be between 1 and {MAX_SIZE}")));
        }
        for a in 0..3 {
            let (lo, hi) = (self.bbox[2 * a], self.bbox[2 * a + 1]);
            if !(lo < hi) || !lo.is_finite() || !hi.is_finite() {
                let axis = ["x", "y", "z"][a];
                return Err(SettingsError::new(F::Box, format!("{lo},{hi}"), format!("axis {axis} has [{lo}, {hi}]; each axis needs lo < hi")));
            }
        }
        self.camera.frame()?;
        if self.clip_sphere.is_some_and(|r| !(r > 0.0 && r.is_finite())) {
            return Err(SettingsError::new(F::Clip, format!("{:?}", self.clip_sphere.unwrap_or(0.0)), "the radius must be positive"));
        }
        if !(self.eps > 0.0 && self.eps.is_finite()) {
            return Err(SettingsError::new(F::Eps, self.eps.to_string(), "it must be a positive width"));
        }
        let diag = super::box_diagonal(&self.bbox);
        if self.eps >= diag {
            return Err(SettingsError::new(F::Eps, format!("{:e}", self.eps), format!("it must be below the box diagonal ({diag:.4}): a cell that wide holds the whole domain")));
        }
        if !self.time.is_finite() {
            return Err(SettingsError::new(F::Time, self.time.to_string(), "it must be a finite number"));
        }
        if let Some(p) = self.params.iter().find(|p| !p.is_finite()) {
            return Err(SettingsError::new(F::Params, p.to_string(), "parameter values must be finite numbers"));
        }
        if self.params.len() > crate::layout::MAX_PARAMS {
            return Err(SettingsError::new(F::Params, self.params.len().to_string(), format!("at most {} parameters", crate::layout::MAX_PARAMS)));
        }
        if self.max_iter == 0 || self.max_iter > MAX_ITER_LIMIT {
            return Err(SettingsError::new(F::MaxIter, self.max_iter.to_string(), format!("it must be between 1 and {MAX_ITER_LIMIT}")));
        }
        Ok(())
    }
}

/// Which setting a [`SettingsError`] is about. The command line maps each
/// to its flag (`--fov`, `--param`, …), a header reader to its key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettingsField {
    /// Image size.
    Size,
    /// Domain box.
    Box,
    /// Camera position.
    Eye,
    /// Camera target.
    Target,
    /// Camera up direction.
    Up,
    /// Field of view.
    Fov,
    /// Termination width.
    Eps,
    /// Time value.
    Time,
    /// Parameter values.
    Params,
    /// Clip ball.
    Clip,
    /// Bisection's iteration budget.
    MaxIter,
    /// Number of isovalues.
    Isovalues,
    /// Transparency layers.
    Layers,
    /// Per-layer opacity.
    Opacity,
    /// Reflection bounces.
    Reflect,
    /// Reflection weight.
    Reflectivity,
    /// Sphere tracing's Lipschitz bound.
    Lipschitz,
    /// Over-relaxation factor.
    Omega,
    /// Sphere tracing's step budget.
    MaxSteps,
    /// Fixed-point iterations.
    Fixpoint,
    /// Smallest step.
    MinStep,
    /// Secondary rays' eps.
    EpsMin,
    /// A traversal option the compiled kernel lacks (shadow or glass rays).
    Features,
}

/// A setting with a value that cannot be rendered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {field:?} {value}: {reason}")]
pub struct SettingsError {
    /// Which setting.
    pub field: SettingsField,
    /// Its value as given (for the message).
    pub value: String,
    /// Why it is wrong.
    pub reason: String,
}

impl SettingsError {
    /// An error about `field`.
    pub fn new(field: SettingsField, value: impl Into<String>, reason: impl Into<String>) -> SettingsError {
        SettingsError { field, value: value.into(), reason: reason.into() }
    }
}
