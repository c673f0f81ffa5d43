//! A view as a user describes it, partially: an `.iso` header gives some
//! values, command-line flags override some, and [`View::settings`] turns
//! the result into the [`Settings`] of a frame once, with the documented
//! defaults. The CLI, `bench`, the benches and the peer harness all
//! go through here, so a header means the same everywhere.

use super::settings::{SettingsError, SettingsField};
use super::{box_diagonal, Camera, Settings};
use crate::diag::Diagnostic;
use crate::{Formula, FormulaError};
use glam::DVec3;

/// The default box: `[-2, 2]³`.
pub const DEFAULT_BOX: [f64; 6] = [-2.0, 2.0, -2.0, 2.0, -2.0, 2.0];
/// The default vertical field of view, degrees.
pub const DEFAULT_FOV: f64 = 40.0;

/// The view values given so far; `None` takes the default.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Domain box.
    pub bbox: [f64; 6],
    /// Eye position (default: azimuth 35°, elevation 25° from the target,
    /// far enough that the whole box is in view).
    pub eye: Option<DVec3>,
    /// Point looked at (default: the box centre). Moving the target alone
    /// moves the default eye with it.
    pub target: Option<DVec3>,
    /// Up direction (default +z).
    pub up: Option<DVec3>,
    /// Vertical field of view in degrees.
    pub fov: Option<f64>,
    /// Termination width (default 2^-11 × the box diagonal).
    pub eps: Option<f64>,
    /// Time value (default 0).
    pub time: Option<f64>,
    /// Parameter values by name, in the order given; a later value of the
    /// same name wins.
    pub params: Vec<(String, f64)>,
    /// Clip-ball radius around the box centre.
    pub clip: Option<f64>,
}

impl Default for View {
    fn default() -> Self {
        View { bbox: DEFAULT_BOX, eye: None, target: None, up: None, fov: None, eps: None, time: None, params: vec![], clip: None }
    }
}

/// Why a view cannot become settings.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ViewError {
    /// A value out of range.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// A parameter the formula does not have, or one it lacks a value for.
    #[error(transparent)]
    Param(#[from] FormulaError),
}

impl View {
    /// The settings of a `width × height` frame of a field without
    /// parameters (a scene): parameters given are an error.
    pub fn settings_without_params(&self, width: u32, height: u32) -> Result<Settings, ViewError> {
        if let Some((name, _)) = self.params.first() {
            return Err(SettingsError::new(SettingsField::Params, name.clone(), "this field has no parameters").into());
        }
        let s = Settings { params: vec![], ..self.frame(width, height)? };
        s.check()?;
        Ok(s)
    }

    /// The settings of a `width × height` frame of `f`, and warnings about
    /// the parameters (values for names the formula does not use).
    pub fn settings(&self, f: &Formula, width: u32, height: u32) -> Result<(Settings, Vec<Diagnostic>), ViewError> {
        let (params, warnings) = crate::sema::bind_params(&f.ir, &self.params)
            .map_err(|diagnostic| FormulaError { origin: f.origin.clone(), text: f.source.clone(), diagnostic })?;
        let s = Settings { params, ..self.frame(width, height)? };
        s.check()?;
        Ok((s, warnings))
    }

    /// Everything but the parameters.
    fn frame(&self, width: u32, height: u32) -> Result<Settings, ViewError> {
        let fov = self.fov.unwrap_or(DEFAULT_FOV);
        let mut camera = Camera::default_for(&self.bbox, fov, width as f64 / height.max(1) as f64);
        if let Some(t) = self.target {
            let off = camera.eye - camera.target;
            camera.target = t;
            camera.eye = t + off;
        }
        if let Some(e) = self.eye {
            camera.eye = e;
        }
        if let Some(u) = self.up {
            camera.up = u;
        }
        if let Some(e) = self.eps.filter(|e| !(*e > 0.0 && e.is_finite())) {
            return Err(SettingsError::new(SettingsField::Eps, e.to_string(), "it must be a positive width").into());
        }
        Ok(Settings {
            camera,
            eps: self.eps.unwrap_or(box_diagonal(&self.bbox) * 2f64.powi(-11)),
            time: self.time.unwrap_or(0.0),
            clip_sphere: self.clip,
            ..Settings::for_box(self.bbox, width, height)
        })
    }
}
