//! Flags of Knoll et al.'s visualisation modalities (`render`):
//! shadows, transparency, isovalues, reflections, colouring. They become a
//! [`Modalities`] value; the structural parts are compiled into the shader
//! only when asked for.

use super::CliError;
use clap::Args;
use isotrace::catalog;
use isotrace::layout::KernelColor;
use isotrace::render::{EnvImage, Environment, Modalities};
use std::path::PathBuf;

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
}

fn input(m: impl Into<String>) -> CliError {
    CliError::Input(m.into())
}

/// Reads an environment PNG as rgba8 texels.
fn load_env(path: &PathBuf) -> Result<EnvImage, CliError> {
    let img = image::open(path).map_err(|e| input(format!("cannot read --env image '{}': {e}", path.display())))?;
    let rgba = img.to_rgba8();
    let (width, height) = rgba.dimensions();
    let texels = rgba.pixels().map(|p| u32::from_le_bytes(p.0)).collect();
    Ok(EnvImage { width, height, texels })
}

/// Builds the modalities from the flags (validated before any GPU work);
/// `shadows` and the kernel's colour mode come from the shared flags.
pub fn modalities(a: &ModalityArgs, shadows: bool, color: KernelColor) -> Result<Modalities, CliError> {
    let mut m = Modalities { shadows, color, ..Default::default() };
    if let Some(l) = &a.light {
        let v = catalog::parse_vec3(l).map_err(|e| input(format!("invalid --light '{l}': {e}")))?;
        m.light = Some(glam::DVec3::from_array(v));
    }
    if let Some(e) = &a.shadow_eps {
        m.shadow_eps = Some(catalog::parse_eps(e).map_err(|x| input(format!("invalid --shadow-eps '{e}': {x}")))?);
        if !shadows {
            return Err(input("--shadow-eps needs --shadows"));
        }
    }
    if let Some(o) = a.opacity {
        if !(o > 0.0 && o <= 1.0) {
            return Err(input(format!("invalid --opacity {o}: it must be in (0, 1]")));
        }
    }
    m.layers = a.layers.unwrap_or(if a.opacity.is_some_and(|o| o < 1.0) { 4 } else { 1 });
    if m.layers == 0 || m.layers > 8 {
        return Err(input(format!("invalid --layers {}: it must be between 1 and 8", m.layers)));
    }
    m.opacity = a.opacity.unwrap_or(if m.layers > 1 { 0.5 } else { 1.0 });
    if let Some(list) = &a.iso {
        let v: Result<Vec<f64>, _> = list.split(',').map(|x| x.trim().parse::<f64>()).collect();
        match v {
            Ok(v) if !v.is_empty() && v.len() <= 8 && v.iter().all(|x| x.is_finite()) => m.isovalues = v,
            _ => return Err(input(format!("invalid --iso '{list}': expected 1 to 8 comma-separated numbers"))),
        }
    }
    m.reflect = a.reflect.unwrap_or(0);
    if m.reflect > 8 {
        return Err(input(format!("invalid --reflect {}: at most 8 bounces", m.reflect)));
    }
    if let Some(k) = a.reflectivity {
        if !(0.0..=1.0).contains(&k) {
            return Err(input(format!("invalid --reflectivity {k}: it must be in [0, 1]")));
        }
        m.reflectivity = k;
    }
    match a.env.as_deref() {
        None | Some("sky") => {}
        Some("checker") => m.env = Environment::Checker,
        Some(path) => m.env = Environment::Image(load_env(&PathBuf::from(path))?),
    }
    Ok(m)
}

impl ModalityArgs {
    /// These flags with an `.iso` header's modality keys filling the ones
    /// not given (flags override the header). Also returns the header's
    /// `shadows` and `color` values.
    pub fn with_header(&self, header: Option<&isotrace::catalog::Header>) -> (ModalityArgs, Option<bool>, Option<String>) {
        let mut a = self.clone();
        let (mut shadows, mut color) = (None, None);
        for (k, v) in header.map_or(&[][..], |h| &h.modalities[..]) {
            let v = v.clone();
            match k.as_str() {
                "shadows" => shadows = Some(v == "true"),
                "color" => color = Some(v),
                "light" => a.light = a.light.or(Some(v)),
                "shadow-eps" => a.shadow_eps = a.shadow_eps.or(Some(v)),
                "opacity" => a.opacity = a.opacity.or(v.parse().ok()),
                "layers" => a.layers = a.layers.or(v.parse().ok()),
                "iso" => a.iso = a.iso.or(Some(v)),
                "reflect" => a.reflect = a.reflect.or(v.parse().ok()),
                "reflectivity" => a.reflectivity = a.reflectivity.or(v.parse().ok()),
                "env" => a.env = a.env.or(Some(v)),
                _ => {}
            }
        }
        (a, shadows, color)
    }

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
