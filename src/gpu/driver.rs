//! How much the driver optimises the kernels it compiles.
//!
//! Mesa's CPU drivers (lavapipe, on llvmpipe's gallivm) compile a kernel
//! with LLVM at its first dispatch, and most of that time is LLVM's
//! optimisation passes. gallivm can skip them (`GALLIVM_PERF=nopt`): a
//! kernel then compiles a few times sooner and a generated field's frames
//! run markedly slower (the tape interpreter's about as fast, its cost
//! being register-file traffic the passes do not remove);
//! the pictures are the same bit for bit. For a job of one frame the
//! compile is most of the wait, so [`auto_shader_opt`] skips them for small
//! jobs. gallivm reads the setting once, when the driver first starts in a
//! process: the first device opened fixes it for every later one, and
//! [`ShaderOpt`] in effect is what [`in_effect`] reports. Other drivers
//! ignore it.

use std::sync::OnceLock;

/// Whether the driver runs its optimisation passes over the kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShaderOpt {
    /// The driver's full optimisation (its default): the fastest frames.
    Full,
    /// No optimisation passes: the soonest first frame.
    None,
}

impl ShaderOpt {
    /// The name the CLI and the statistics use.
    pub fn name(self) -> &'static str {
        match self {
            ShaderOpt::Full => "full",
            ShaderOpt::None => "none",
        }
    }
}

/// Work (pixels × frames) up to which [`auto_shader_opt`] skips the passes:
/// one 1024² frame. A single frame of that size or smaller comes sooner
/// without them, compiled or tape, small formula or large; compiled
/// kernels' frames then take markedly longer, so past about one such frame
/// the passes pay for themselves (chosen by measurement on lavapipe,
/// docs/benchmarks.md).
pub const SHADER_OPT_NONE_UP_TO: u64 = 1 << 20;

/// The optimisation for a job of `pixel_frames` (pixels of a frame times
/// the frames it renders): none up to [`SHADER_OPT_NONE_UP_TO`], full past it.
pub fn auto_shader_opt(pixel_frames: u64) -> ShaderOpt {
    if pixel_frames <= SHADER_OPT_NONE_UP_TO { ShaderOpt::None } else { ShaderOpt::Full }
}

/// The environment variable gallivm reads its performance flags from.
const ENV: &str = "GALLIVM_PERF";
/// gallivm's flag that skips the optimisation passes.
const NO_OPT: &str = "nopt";

/// The flags of a `GALLIVM_PERF` value (gallivm splits on anything but
/// letters, digits and underscores).
fn flags(v: &str) -> impl Iterator<Item = &str> {
    v.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).filter(|f| !f.is_empty())
}

/// What `GALLIVM_PERF = v` asks for.
fn from_env(v: Option<&str>) -> ShaderOpt {
    match v {
        Some(v) if flags(v).any(|f| f == NO_OPT || f == "all") => ShaderOpt::None,
        _ => ShaderOpt::Full,
    }
}

/// `v` with the no-optimisation flag added or taken out, its other flags kept.
fn with_opt(v: Option<&str>, opt: ShaderOpt) -> String {
    let mut kept: Vec<&str> = v.map(|v| flags(v).filter(|f| *f != NO_OPT).collect()).unwrap_or_default();
    if opt == ShaderOpt::None {
        kept.push(NO_OPT);
    }
    kept.join(",")
}

/// The setting the driver started with in this process (latched by the
/// first device opened).
static LATCHED: OnceLock<ShaderOpt> = OnceLock::new();

/// Before the first device of the process: asks for `opt` (`None`: leaves
/// the environment as it is), and latches what the driver will start with.
/// Later calls change nothing: the driver has read its setting already.
pub(crate) fn start(opt: Option<ShaderOpt>) {
    LATCHED.get_or_init(|| {
        if let Some(opt) = opt {
            let v = with_opt(std::env::var(ENV).ok().as_deref(), opt);
            // SAFETY: called while opening the process's first device, before
            // the driver (which reads it) starts; isotrace's own threads
            // (the signal watcher) do not read the environment.
            unsafe {
                if v.is_empty() { std::env::remove_var(ENV) } else { std::env::set_var(ENV, v) }
            };
        }
        from_env(std::env::var(ENV).ok().as_deref())
    });
}

/// The optimisation the CPU driver runs with, on a device it applies to
/// (Mesa's llvmpipe-based drivers); `None` elsewhere.
pub fn in_effect(device_name: &str, cpu: bool) -> Option<ShaderOpt> {
    (cpu && device_name.starts_with("llvmpipe")).then(|| *LATCHED.get().unwrap_or(&ShaderOpt::Full))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flag_is_added_and_removed_keeping_the_others() {
        assert_eq!(with_opt(None, ShaderOpt::None), "nopt");
        assert_eq!(with_opt(None, ShaderOpt::Full), "");
        assert_eq!(with_opt(Some("no_filter_hacks"), ShaderOpt::None), "no_filter_hacks,nopt");
        assert_eq!(with_opt(Some("nopt,no_filter_hacks"), ShaderOpt::Full), "no_filter_hacks");
        assert_eq!(from_env(Some("brilinear:nopt")), ShaderOpt::None);
        assert_eq!(from_env(Some("noptx")), ShaderOpt::Full);
        assert_eq!(from_env(None), ShaderOpt::Full);
    }

    #[test]
    fn auto_skips_the_passes_up_to_one_1024_frame() {
        assert_eq!(auto_shader_opt(512 * 512), ShaderOpt::None);
        assert_eq!(auto_shader_opt(1024 * 1024), ShaderOpt::None);
        assert_eq!(auto_shader_opt(1024 * 1024 + 1), ShaderOpt::Full);
        assert_eq!(auto_shader_opt(5 * 512 * 512), ShaderOpt::Full);
    }
}
