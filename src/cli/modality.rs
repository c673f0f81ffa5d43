//! Flags of Knoll et al.'s visualisation modalities (`render`):
//! shadows, transparency, isovalues, reflections, colouring. They become a
//! [`Modalities`] value; the structural parts are compiled into the shader
//! only when asked for.

use super::CliError;
use clap::Args;
use crate::catalog;
use crate::layout::KernelColor;
use crate::render::{EnvImage, EnvSpec, ModalitySpec, Modalities};

/// Modality flags.
#[derive(Args, Debug, Clone, Default)]
pub struct ModalityArgs {
    /// Point light position x,y,z (default: above and left of the eye).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub light: Option<String>,
    /// eps of shadow rays, absolute or 2^-k like --eps (default 4 × eps: shadows need less precision).
    #[arg(long, value_name = "EPS")]
    pub shadow_eps: Option<String>,
    /// Per-layer opacity in (0, 1] for transparency (default 0.5 when --layers > 1).
    #[arg(long, value_name = "A")]
    pub opacity: Option<f64>,
    /// Surface layers per pixel, front to back, 1..8 (default 4 when --opacity < 1).
    #[arg(long, value_name = "N")]
    pub layers: Option<u32>,
    /// Isovalues drawn in one traversal, comma-separated, up to 8 (e.g. 0,0.5,1); each gets its colour.
    #[arg(long, value_name = "C,...", allow_hyphen_values = true)]
    pub iso: Option<String>,
    /// Reflection bounces (0..8).
    #[arg(long, value_name = "N")]
    pub reflect: Option<u32>,
    /// Weight of each reflection in [0, 1] (default 0.35).
    #[arg(long, value_name = "K")]
    pub reflectivity: Option<f64>,
    /// Environment seen by reflections and the background: sky, checker, or an equirectangular PNG.
    #[arg(long, value_name = "sky|checker|FILE")]
    pub env: Option<String>,
    /// Let an .iso header's env: image lie outside the .iso file's directory (absolute, '..', or a symbolic link leading out); only for files you trust.
    #[arg(long)]
    pub allow_header_paths: bool,
}


/// Reads an environment PNG as rgba8 texels.
fn load_env(path: &std::path::Path) -> Result<EnvImage, CliError> {
    let img = crate::output::read_image(path).map_err(|e| CliError::input(format!("cannot read --env image '{}': {e}", path.display())))?;
    let rgba = img.to_rgba8();
    let (width, height) = rgba.dimensions();
    let texels = rgba.pixels().map(|p| u32::from_le_bytes(p.0)).collect();
    Ok(EnvImage { width, height, texels })
}

/// The modality flags as a typed spec (parse errors name the flag; range
/// checks come with [`ModalitySpec::resolve`]).
fn spec(a: &ModalityArgs, shadows: bool) -> Result<ModalitySpec, CliError> {
    let mut s = ModalitySpec { shadows: shadows.then_some(true), opacity: a.opacity, layers: a.layers, reflect: a.reflect, reflectivity: a.reflectivity, ..Default::default() };
    if let Some(l) = &a.light {
        let v = catalog::parse_vec3(l).map_err(|e| CliError::input(format!("invalid --light '{l}': {e}")))?;
        s.light = Some(glam::DVec3::from_array(v));
    }
    if let Some(e) = &a.shadow_eps {
        s.shadow_eps = Some(catalog::parse_eps(e).map_err(|x| CliError::input(format!("invalid --shadow-eps '{e}': {x}")))?);
    }
    if let Some(list) = &a.iso {
        let v: Result<Vec<f64>, _> = list.split(',').map(|x| x.trim().parse::<f64>()).collect();
        match v {
            Ok(v) if !v.is_empty() && v.len() <= 8 && v.iter().all(|x| x.is_finite()) => s.iso = Some(v),
            _ => return Err(CliError::input(format!("invalid --iso '{list}': expected 1 to 8 comma-separated numbers"))),
        }
    }
    s.env = a.env.as_deref().map(EnvSpec::parse);
    Ok(s)
}

/// The modalities from the flags (`--shadows` is shared with sphere
/// tracing, the kernel colour comes from `--color`), with an `.iso`
/// header's modality keys as defaults; validated before any GPU work.
pub fn modalities(a: &ModalityArgs, shadows: bool, color: KernelColor, header: Option<&catalog::Header>) -> Result<Modalities, CliError> {
    let defaults = header.map(|h| h.modalities.clone()).unwrap_or_default();
    let s = spec(a, shadows)?.or(&defaults);
    refuse_outside_paths(a, &s, header)?;
    if s.shadow_eps.is_some() && a.shadow_eps.is_some() && s.shadows != Some(true) {
        return Err(CliError::input("--shadow-eps needs --shadows"));
    }
    s.resolve(color, load_env)?.map_err(|e| CliError::input(super::error::settings_message(&e)))
}

/// The trust rule for `.iso` headers: a header may make isotrace read an
/// `env:` image only inside its own file's directory, unless the user says
/// `--allow-header-paths`. A flag's `--env` is the user's own and is read as
/// given.
fn refuse_outside_paths(a: &ModalityArgs, s: &ModalitySpec, header: Option<&catalog::Header>) -> Result<(), CliError> {
    let (Some(h), Some(EnvSpec::File(p))) = (header, &s.env) else { return Ok(()) };
    if a.env.is_none() && !a.allow_header_paths && h.outside_paths.contains(p) {
        return Err(CliError::input(format!(
            "the .iso header's env: image '{}' is outside the directory of the .iso file; give --allow-header-paths to read it (only for files you trust)",
            p.display()
        )));
    }
    Ok(())
}

impl ModalityArgs {
    /// The bisection-only flags that were given.
    pub fn given(&self) -> Vec<&'static str> {
        [
            ("--light", self.light.is_some()),
            ("--shadow-eps", self.shadow_eps.is_some()),
            ("--opacity", self.opacity.is_some()),
            ("--layers", self.layers.is_some()),
            ("--iso", self.iso.is_some()),
            ("--reflect", self.reflect.is_some()),
            ("--reflectivity", self.reflectivity.is_some()),
            ("--env", self.env.is_some()),
        ]
        .into_iter()
        .filter(|(_, on)| *on)
        .map(|(n, _)| n)
        .collect()
    }
}
