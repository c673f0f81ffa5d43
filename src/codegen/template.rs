//! Kernel templates: real `.wgsl` files with splice markers. A marker is a
//! line holding only `//!splice:NAME`; [`splice`] replaces each with generated
//! code and fails (an isotrace bug) if a marker is missing or left over.

/// The `isotrace eval` kernel: one invocation per box.
pub const EVAL: &str = include_str!("../../templates/kernels/eval.wgsl");
/// The render kernel: stackless interval bisection per pixel.
pub const BISECT: &str = include_str!("../../templates/kernels/bisect.wgsl");
#[doc = "The sphere tracing kernel for distance bounds (Keinert et al.'s five techniques)."] pub const SPHERE: &str = include_str!("../../templates/kernels/sphere.wgsl");

/// The render kernel's tile pass (entry point `tiles`).
pub const TILES: &str = include_str!("../../templates/kernels/tiles.wgsl");
/// Shading, colour modes and the environment of the render kernel.
pub const SHADE: &str = include_str!("../../templates/kernels/shade.wgsl");
/// The optional modalities (shadows, reflections) and their stubs.
pub const MODALITIES: &str = include_str!("../../templates/kernels/modalities.wgsl");

/// The section of a parts file that starts at the line `//!part:NAME` and
/// runs to the next `//!part:` line (empty if there is none such).
pub fn part<'a>(text: &'a str, name: &str) -> &'a str {
    let marker = format!("//!part:{name}\n");
    let Some(start) = text.find(&marker).map(|i| i + marker.len()) else { return "" };
    let end = text[start..].find("//!part:").map_or(text.len(), |i| start + i);
    &text[start..end]
}

/// Replaces every `//!splice:NAME` line of `template` by its value.
pub fn splice(template: &str, parts: &[(&str, &str)]) -> Result<String, String> {
    let mut out = String::with_capacity(template.len() + parts.iter().map(|p| p.1.len()).sum::<usize>());
    let mut used = vec![false; parts.len()];
    for line in template.lines() {
        match line.trim().strip_prefix("//!splice:") {
            Some(name) => {
                let Some(i) = parts.iter().position(|(n, _)| *n == name) else {
                    return Err(format!("template marker '{name}' has no content"));
                };
                used[i] = true;
                out.push_str(&format!("// ---- begin {name} ----\n"));
                out.push_str(parts[i].1);
                if !parts[i].1.ends_with('\n') {
                    out.push('\n');
                }
                out.push_str(&format!("// ---- end {name} ----\n"));
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    if let Some(i) = used.iter().position(|u| !u) {
        return Err(format!("no marker '//!splice:{}' in the template", parts[i].0));
    }
    Ok(out)
}
