//! The typed header of an `.iso` file: each `#@ key: value` line checked
//! and turned into typed values once ([`apply`]), and the value parsers the
//! command line shares (`parse_eps`, `parse_box`, `parse_vec3`).

use super::{Bound, Method, DEFAULT_BOX};

/// The typed header of an `.iso` file. Every key is optional.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// `title`: a human-readable name.
    pub title: Option<String>,
    /// `box`: `[x0, x1, y0, y1, z0, z1]`; [`DEFAULT_BOX`] when not given.
    pub bbox: [f64; 6],
    /// `t`: the time value.
    pub t: Option<f64>,
    /// `eye`: camera position.
    pub eye: Option<[f64; 3]>,
    /// `target`: the point the camera looks at.
    pub target: Option<[f64; 3]>,
    /// `up`: the camera's approximate up direction.
    pub up: Option<[f64; 3]>,
    /// `fov`: vertical field of view in degrees, in (0, 180).
    pub fov: Option<f64>,
    /// `eps`: the traversal's length tolerance, > 0.
    pub eps: Option<f64>,
    /// `algebra`: the inclusion algebra to use.
    pub algebra: Option<Algebra>,
    /// `param` lines: parameter values, in file order.
    pub params: Vec<(String, f64)>,
    /// `degree`: free text (`4`, `12 (the table lists 4)`, `non-algebraic`).
    pub degree: Option<String>,
    /// `status`: whether the formula is a published one or a reconstruction.
    pub status: Option<Status>,
    /// `source`: provenance.
    pub source: Option<String>,
    /// `notes`: free text.
    pub notes: Option<String>,
    /// `animate`: the `[t0, t1]` range of an animated (4D) surface, t0 < t1.
    pub animate: Option<[f64; 2]>,
    /// `clip`: a clipping hint for unbounded surfaces.
    pub clip: Option<Clip>,
    /// `method`: the traversal to render with (`sphere` for distance fields).
    pub method: Option<Method>,
    /// `field`: the field source to render with (`render --field`'s
    /// default for this file: compiled, tape, scene or auto).
    pub field: Option<crate::field::FieldKind>,
    /// `lipschitz`: a Lipschitz bound L >= 1 of the formula (sphere tracing
    /// divides the field by it).
    pub lipschitz: Option<f64>,
    /// `bound`: a convex volume holding a convex object (sphere tracing's
    /// technique 5).
    pub bound: Option<Bound>,
    /// Modality keys (`shadows`, `light`, `shadow-eps`, `opacity`,
    /// `layers`, `iso`, `reflect`, `reflectivity`, `env`): the defaults of
    /// the `render` flags of the same names.
    pub modalities: crate::render::ModalitySpec,
    /// `color`: the default colouring (`--color`), checked.
    pub color: Option<String>,
    /// File paths of this header (the `env` image) that lead out of the
    /// `.iso` file's directory: absolute, up through `..`, or through a
    /// symbolic link. Filled in by [`super::load_file`]; a caller that reads
    /// files for an untrusted header refuses these unless told otherwise.
    pub outside_paths: Vec<std::path::PathBuf>,
}

impl Default for Header {
    fn default() -> Self {
        Header {
            title: None,
            bbox: DEFAULT_BOX,
            t: None,
            eye: None,
            target: None,
            up: None,
            fov: None,
            eps: None,
            algebra: None,
            params: Vec::new(),
            degree: None,
            status: None,
            source: None,
            notes: None,
            animate: None,
            clip: None,
            method: None,
            field: None,
            lipschitz: None,
            bound: None,
            modalities: Default::default(),
            color: None,
            outside_paths: Vec::new(),
        }
    }
}

impl Header {
    /// The view the header describes (box, camera, eps, time, parameters,
    /// clip ball): the defaults that flags override.
    pub fn view(&self) -> crate::render::View {
        let v3 = |v: Option<[f64; 3]>| v.map(glam::DVec3::from_array);
        crate::render::View {
            bbox: self.bbox,
            eye: v3(self.eye),
            target: v3(self.target),
            up: v3(self.up),
            fov: self.fov,
            eps: self.eps,
            time: self.t,
            params: self.params.clone(),
            clip: self.clip.map(|Clip::Sphere(r)| r),
        }
    }

    /// The value of parameter `name`, if the header sets it.
    #[cfg(test)]
    pub fn param(&self, name: &str) -> Option<f64> {
        self.params.iter().find(|(n, _)| n == name).map(|&(_, v)| v)
    }
}

/// The `algebra` key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algebra {
    /// `ia`: interval arithmetic.
    Ia,
    /// `raa`: reduced affine arithmetic.
    Raa,
    /// `auto`: chosen per formula.
    Auto,
}

impl Algebra {
    /// The number domain this algebra stands for with formula `ir` (auto:
    /// [`crate::choose_algebra`]).
    #[cfg(any(test, feature = "internals"))]
    pub fn domain(self, ir: &crate::ir::Ir) -> crate::ir::Domain {
        match self {
            Algebra::Ia => crate::ir::Domain::Interval,
            Algebra::Raa => crate::ir::Domain::Affine,
            Algebra::Auto => crate::choose_algebra(ir),
        }
    }
}

/// The `status` key: where the formula comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// The standard published form of the named surface.
    Published,
    /// A reconstruction: the original formula is not known.
    Reconstruction,
}

/// The `clip` key: a region to intersect an unbounded surface with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clip {
    /// `sphere:R`: the ball of radius R around the box centre.
    Sphere(f64),
}

/// Stores one `key: value` in the header; the error says why the value is bad.
pub(super) fn apply(h: &mut Header, name: &mut Option<String>, key: &str, value: &str) -> Result<(), String> {
    let known = describe(h, name, key, value)? || view_key(h, key, value)? || render_key(h, key, value)? || modality_key(&mut h.modalities, key, value)?;
    if !known {
        unreachable!("key {key} checked against KEYS");
    }
    Ok(())
}

/// The keys that say what the surface is (`name`, `title`, `degree`,
/// `status`, `source`, `notes`); `Ok(false)` for another key.
fn describe(h: &mut Header, name: &mut Option<String>, key: &str, value: &str) -> Result<bool, String> {
    let text = || Some(value.to_string());
    match key {
        "name" => *name = Some(parse_name(value)?),
        "title" => h.title = text(),
        "degree" => h.degree = text(),
        "status" => {
            h.status = Some(match value {
                "published" => Status::Published,
                "reconstruction" => Status::Reconstruction,
                _ => return Err("expected 'published' or 'reconstruction'".into()),
            })
        }
        "source" => h.source = text(),
        "notes" => h.notes = text(),
        _ => return Ok(false),
    }
    Ok(true)
}

/// The keys of the view: box, camera, eps, time, parameters, animation and
/// clip; `Ok(false)` for another key.
fn view_key(h: &mut Header, key: &str, value: &str) -> Result<bool, String> {
    match key {
        "box" => h.bbox = parse_box(value)?,
        "t" => h.t = Some(number(value).ok_or("expected a number")?),
        "eye" => h.eye = Some(parse_vec3(value)?),
        "target" => h.target = Some(parse_vec3(value)?),
        "up" => {
            let v = parse_vec3(value)?;
            if v == [0.0; 3] {
                return Err("the up vector must not be zero".into());
            }
            h.up = Some(v);
        }
        "fov" => match number(value) {
            Some(f) if f > 0.0 && f < 180.0 => h.fov = Some(f),
            _ => return Err("expected an angle in degrees between 0 and 180 (exclusive)".into()),
        },
        "eps" => h.eps = Some(parse_eps(value)?),
        "param" => h.params.push(parse_param(value)?),
        "animate" => match numbers(value).as_deref() {
            Some(&[t0, t1]) if t0 < t1 => h.animate = Some([t0, t1]),
            _ => return Err("expected 't0,t1' with t0 < t1".into()),
        },
        "clip" => match value.strip_prefix("sphere:").and_then(number) {
            Some(r) if r > 0.0 => h.clip = Some(Clip::Sphere(r)),
            _ => return Err("expected 'sphere:R' with a radius R > 0".into()),
        },
        _ => return Ok(false),
    }
    Ok(true)
}

/// The keys of how to render: algebra, method, field source, Lipschitz
/// bound, bounding volume and colouring; `Ok(false)` for another key.
fn render_key(h: &mut Header, key: &str, value: &str) -> Result<bool, String> {
    match key {
        "algebra" => {
            h.algebra = Some(match value {
                "ia" => Algebra::Ia,
                "raa" => Algebra::Raa,
                "auto" => Algebra::Auto,
                _ => return Err("expected 'ia', 'raa' or 'auto'".into()),
            })
        }
        "method" => h.method = Some(Method::parse(value)?),
        "field" => match crate::field::FieldKind::parse(value) {
            Some(k) => h.field = Some(k),
            None => return Err("expected 'compiled', 'tape', 'scene' or 'auto'".into()),
        },
        "lipschitz" => match number(value) {
            Some(l) if l >= 1.0 => h.lipschitz = Some(l),
            _ => return Err("expected a Lipschitz bound L >= 1".into()),
        },
        "bound" => h.bound = Some(Bound::parse(value)?),
        "color" => {
            crate::output::parse_color(value)?;
            h.color = Some(value.to_string());
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// The modality keys, the defaults of the `render` flags of the same
/// names; `Ok(false)` for another key.
fn modality_key(m: &mut crate::render::ModalitySpec, key: &str, value: &str) -> Result<bool, String> {
    match key {
        "shadows" => match value {
            "true" | "false" => m.shadows = Some(value == "true"),
            _ => return Err("expected true or false".into()),
        },
        "light" => m.light = Some(glam::DVec3::from_array(parse_vec3(value)?)),
        "shadow-eps" => m.shadow_eps = Some(parse_eps(value)?),
        "opacity" | "reflectivity" => match number(value) {
            Some(v) if v > 0.0 && v <= 1.0 && key == "opacity" => m.opacity = Some(v),
            Some(v) if v > 0.0 && v <= 1.0 => m.reflectivity = Some(v),
            _ => return Err("expected a number in (0, 1]".into()),
        },
        "layers" | "reflect" => match value.parse::<u32>() {
            Ok(n) if n <= 8 && key == "layers" => m.layers = Some(n),
            Ok(n) if n <= 8 => m.reflect = Some(n),
            _ => return Err("expected a whole number from 0 to 8".into()),
        },
        "iso" => match numbers(value) {
            Some(v) if !v.is_empty() && v.len() <= 8 => m.iso = Some(v),
            _ => return Err("expected 1 to 8 comma-separated numbers".into()),
        },
        "env" => m.env = Some(crate::render::EnvSpec::parse(value)),
        _ => return Ok(false),
    }
    Ok(true)
}

fn parse_name(s: &str) -> Result<String, String> {
    let ok = !s.starts_with(['-', '.']) && s.bytes().all(|c| c.is_ascii_alphanumeric() || matches!(c, b'-' | b'_' | b'.'));
    if ok { Ok(s.to_string()) } else { Err("a name uses letters, digits, '-', '_' and '.' only".into()) }
}

fn parse_param(s: &str) -> Result<(String, f64), String> {
    let (n, v) = s.split_once('=').ok_or("expected 'name=value'")?;
    let n = n.trim();
    let is_ident = n.bytes().next().is_some_and(|c| c.is_ascii_alphabetic() || c == b'_')
        && n.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_');
    if !is_ident {
        return Err(format!("'{n}' is not a parameter name"));
    }
    let v = parse_number(v).map_err(|_| format!("'{}' is not a number", v.trim()))?;
    Ok((n.to_string(), v))
}


/// A finite number (Rust float syntax, surrounding whitespace allowed).
fn number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Comma-separated finite numbers.
fn numbers(s: &str) -> Option<Vec<f64>> {
    s.split(',').map(number).collect()
}

/// Parses a tolerance: `0.001`, `1e-3` or a power `2^-11` (`b^k` with an
/// integer k). It must be finite and > 0.
pub fn parse_eps(s: &str) -> Result<f64, String> {
    let value = parse_number(s)?;
    if value <= 0.0 {
        Err("must be greater than 0".into())
    } else {
        Ok(value)
    }
}

/// Parses a finite number as `--eps` and `--param` take it: Rust float
/// syntax (`0.001`, `1e-3`) or a power `b^k` with an integer k (`2^-11`).
/// One syntax for every number a user writes as a power of two.
pub fn parse_number(s: &str) -> Result<f64, String> {
    let s = s.trim();
    let value = match s.split_once('^') {
        Some((b, k)) => match (number(b), k.trim().parse::<i32>()) {
            (Some(b), Ok(k)) => b.powi(k),
            _ => return Err("expected a number such as 0.001, 1e-3 or 2^-11".into()),
        },
        None => s.parse::<f64>().map_err(|_| "expected a number such as 0.001, 1e-3 or 2^-11".to_string())?,
    };
    if value.is_finite() { Ok(value) } else { Err("must be a finite number".into()) }
}

/// Parses a box: `lo,hi` (the same range on every axis) or
/// `x0,x1,y0,y1,z0,z1`, with lo < hi on every axis.
pub fn parse_box(s: &str) -> Result<[f64; 6], String> {
    let b = match numbers(s).as_deref() {
        Some(&[lo, hi]) => [lo, hi, lo, hi, lo, hi],
        Some(&[x0, x1, y0, y1, z0, z1]) => [x0, x1, y0, y1, z0, z1],
        _ => return Err("expected 2 or 6 numbers".into()),
    };
    for (axis, k) in [("x", 0), ("y", 2), ("z", 4)] {
        if b[k] >= b[k + 1] {
            return Err(format!("empty {axis} range: {} is not below {}", b[k], b[k + 1]));
        }
    }
    Ok(b)
}

/// Parses a vector `x,y,z` of three finite numbers.
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    match numbers(s).as_deref() {
        Some(&[x, y, z]) => Ok([x, y, z]),
        _ => Err("expected 3 numbers 'x,y,z'".into()),
    }
}
