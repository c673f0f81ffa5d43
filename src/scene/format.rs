//! The `.scene.json` file: version 1, described in docs/scene-format.md.
//!
//! ```json
//! {"isotrace_scene": 1, "root": 2, "nodes": [
//!   {"type": "sphere", "radius": 1},
//!   {"type": "box", "half": [0.5, 0.5, 2], "rotate": [0, 0, 1, 0.5], "translate": [1, 0, 0]},
//!   {"type": "smooth_union", "left": 0, "right": 1, "beta": 0.2}
//! ]}
//! ```
//!
//! Nodes refer to their operands by index, so a tree of any depth is a flat
//! list (JSON nesting would hit parser recursion limits long before 111,110
//! primitives). The file is read with a stated limit ([`MAX_SCENE_BYTES`]),
//! and nodes are converted one at a time as they are parsed, so memory
//! follows the scene, not a JSON tree of it. Every error names the JSON path
//! of the bad value: `nodes[812].radius: must be > 0`.

use crate::sdf::profile::{self as profile_types, FieldKind, ProfileType};
use super::{Node, Operator, Primitive, Profile, Rotation, Scene, SceneError, Shape, ShapeKind, Transform, Unary, MAX_NODES};
use crate::bounded::{self, ReadError};
use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde_json::Value;
use super::grid::{self, Grid, Placement};
use super::primitive::GridRef;
use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod fields;
mod paths;
mod write;

use fields::{describe, index, key_path, list, quote, Fields};
pub use paths::{GridPathError, GridPaths};
pub use write::to_json;
pub(crate) use write::node_json;

/// The format version this isotrace reads and writes.
pub const VERSION: u64 = 1;

/// How a scene file's name ends: `render` and `view` tell a scene from a
/// formula file by it, so `scene gen` and `scene lower` write no other.
pub const EXTENSION: &str = ".scene.json";

/// The largest scene file read: 64 MiB holds the 111,110-primitive aggregate
/// (30 MB as `isotrace scene gen` writes it) with room to spare.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// Why a scene file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// The file could not be read (or is too large, or not UTF-8).
    #[error("{0}")]
    Read(#[from] ReadError),
    /// Not JSON, or not a JSON object at the top.
    #[error("{message}")]
    Syntax {
        /// serde_json's message, with its line and column.
        message: String,
    },
    /// JSON, but not a valid scene: the path and the reason.
    #[error("{0}")]
    Invalid(#[from] SceneError),
    /// A grid file the [`GridPaths`] policy does not allow.
    #[error("{0}")]
    GridPath(#[from] GridPathError),
}

/// The most grid samples one scene may load, over all its grid files (each
/// file is also limited, `grid::MAX_GRID_VOXELS`): 2²⁶ samples are
/// 256 MiB as f32, and a quarter of the parameter texture's rows.
pub const MAX_SCENE_GRID_VOXELS: u64 = 1 << 26;

/// Reads and validates the scene file at `path`; grid files are found
/// relative to its directory, and must be inside it.
pub fn load(path: &Path) -> Result<Scene, FormatError> {
    load_with(path, &GridPaths::InsideSceneDir)
}

/// [`load`] with the grid files `paths` allows.
pub fn load_with(path: &Path, paths: &GridPaths) -> Result<Scene, FormatError> {
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    parse_with(&bounded::read_file_text(path, MAX_SCENE_BYTES)?, &base, paths)
}

/// Parses and validates scene file text; grid files are found relative to
/// the working directory, and must be inside it.
pub fn parse(text: &str) -> Result<Scene, FormatError> {
    parse_in(text, Path::new(""))
}

/// What parsing keeps besides the nodes: where grid files are, the grids
/// read so far (a file named by several nodes is read once) and their
/// samples in all.
struct Ctx {
    base: PathBuf,
    /// The `repeat` and `mirror` nodes, by index (held as placeholders with
    /// one operand until the tree is checked, then expanded).
    copies: RefCell<HashMap<usize, super::lower::Copies>>,
    grids: RefCell<HashMap<(PathBuf, Option<[u64; 4]>), Arc<Grid>>>,
    voxels: std::cell::Cell<u64>,
    /// Operations of the formula leaves read so far.
    leaf_ops: std::cell::Cell<usize>,
    paths: GridPaths,
    /// The grid file `paths` refused, reported as such.
    refused: RefCell<Option<GridPathError>>,
}

/// Parses and validates scene file text whose grid files are relative to
/// `base`, and must be inside it.
pub fn parse_in(text: &str, base: &Path) -> Result<Scene, FormatError> {
    parse_with(text, base, &GridPaths::InsideSceneDir)
}

/// [`parse_in`] with the grid files `paths` allows.
pub fn parse_with(text: &str, base: &Path, paths: &GridPaths) -> Result<Scene, FormatError> {
    let failure = RefCell::new(None);
    let ctx = Ctx { base: base.to_path_buf(), copies: RefCell::default(), grids: RefCell::default(), voxels: Default::default(), leaf_ops: Default::default(), paths: paths.clone(), refused: RefCell::default() };
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed = de::Deserializer::deserialize_any(&mut de, FileVisitor { failure: &failure, ctx: &ctx }).and_then(|v| de.end().map(|_| v));
    let (nodes, root) = match parsed {
        Ok(v) => v,
        Err(e) => {
            if let Some(refused) = ctx.refused.into_inner() {
                return Err(FormatError::GridPath(refused));
            }
            return Err(match failure.into_inner() {
                Some(s) => FormatError::Invalid(s),
                None => FormatError::Syntax { message: e.to_string() },
            });
        }
    };
    let scene = Scene::new(nodes, root)?;
    let copies = ctx.copies.into_inner();
    if copies.is_empty() {
        return Ok(scene);
    }
    super::lower::expand(&scene, &copies).map_err(|e| FormatError::Invalid(SceneError::new("nodes", e.reason)))
}

/// Records the scene error and returns a placeholder serde error (the
/// recorded one is reported).
fn fail<E: de::Error>(cell: &RefCell<Option<SceneError>>, e: SceneError) -> E {
    *cell.borrow_mut() = Some(e);
    E::custom("invalid scene")
}

struct FileVisitor<'a> {
    failure: &'a RefCell<Option<SceneError>>,
    ctx: &'a Ctx,
}

impl<'de> Visitor<'de> for FileVisitor<'_> {
    type Value = (Vec<Node>, usize);

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a scene object {\"isotrace_scene\": 1, \"nodes\": [...], \"root\": N}")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let cell = self.failure;
        let (mut version, mut nodes, mut root) = (None, None, None);
        while let Some(key) = map.next_key::<String>()? {
            let seen = match key.as_str() {
                "isotrace_scene" => version.replace(check_version(&map.next_value::<Value>()?).map_err(|e| fail(cell, e))?).is_some(),
                "nodes" => nodes.replace(map.next_value_seed(NodesSeed { failure: cell, ctx: self.ctx })?).is_some(),
                "root" => root.replace(index(&map.next_value::<Value>()?).map_err(|r| fail(cell, SceneError::new("root", r)))?).is_some(),
                _ => return Err(fail(cell, SceneError::new(key_path(&key), "unknown field; a scene file has isotrace_scene, nodes and root"))),
            };
            if seen {
                return Err(fail(cell, SceneError::new(key, "given twice")));
            }
        }
        let missing = |f: &str, why: &str| fail(cell, SceneError::new(f, format!("missing: {why}")));
        version.ok_or_else(|| missing("isotrace_scene", "a scene file starts with \"isotrace_scene\": 1"))?;
        let nodes = nodes.ok_or_else(|| missing("nodes", "a scene file lists its nodes"))?;
        let root = root.ok_or_else(|| missing("root", "a scene file names its root node"))?;
        Ok((nodes, root))
    }
}

fn check_version(v: &Value) -> Result<u64, SceneError> {
    match v.as_u64() {
        Some(VERSION) => Ok(VERSION),
        Some(n) => Err(SceneError::new("isotrace_scene", format!("version {n} is not supported (this isotrace reads version {VERSION})"))),
        None => Err(SceneError::new("isotrace_scene", format!("expected the format version {VERSION}, found {}", describe(v)))),
    }
}

struct NodesSeed<'a> {
    failure: &'a RefCell<Option<SceneError>>,
    ctx: &'a Ctx,
}

impl<'de> DeserializeSeed<'de> for NodesSeed<'_> {
    type Value = Vec<Node>;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Vec<Node>, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for NodesSeed<'_> {
    type Value = Vec<Node>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a list of nodes")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<Node>, A::Error> {
        let cell = self.failure;
        let mut nodes = Vec::new();
        loop {
            let i = nodes.len();
            // A syntax error inside a node is reported at that node (but a
            // file that simply ends names no node: there may be none).
            let v = match seq.next_element::<Value>() {
                Ok(Some(v)) => v,
                Ok(None) => return Ok(nodes),
                // (The error type is generic here; serde_json's EOF messages all start so.)
                Err(e) if e.to_string().starts_with("EOF while parsing") => return Err(e),
                Err(e) => return Err(fail(cell, SceneError::at(i, "", e.to_string()))),
            };
            if i >= MAX_NODES {
                return Err(fail(cell, SceneError::new("nodes", format!("more than {MAX_NODES} nodes (the limit)"))));
            }
            nodes.push(node(i, &v, self.ctx).map_err(|e| fail(cell, e))?);
        }
    }
}

const TRANSFORM_FIELDS: [&str; 3] = ["translate", "rotate", "scale"];

/// The fields of each shape, before the transform's.
fn shape_fields(kind: ShapeKind) -> Vec<&'static str> {
    match kind {
        ShapeKind::Analytic(t) => t.fields.iter().map(|f| f.name).collect(),
        ShapeKind::Extrude => vec!["profile", "half_height"],
        ShapeKind::Revolve => vec!["profile", "offset"],
        ShapeKind::Grid => vec!["file", "spacing", "origin"],
        ShapeKind::Formula => vec!["formula", "bounds", "lipschitz"],
    }
}

/// The profile type a scene file calls `name`.
fn profile_type(name: &str) -> Option<&'static ProfileType> {
    profile_types::TYPES.iter().copied().find(|t| t.scene_name == name)
}

/// The JSON keys of a profile type's fields.
fn profile_fields(t: &ProfileType) -> Vec<&'static str> {
    t.fields.iter().map(|f| f.name).collect()
}

/// Converts node `i` from JSON (parameters are checked later, by [`Scene::new`]).
fn node(i: usize, v: &Value, ctx: &Ctx) -> Result<Node, SceneError> {
    let obj = v.as_object().ok_or_else(|| SceneError::at(i, "", format!("expected an object, found {}", describe(v))))?;
    let f = Fields { i, obj, prefix: "" };
    let ty = match obj.get("type") {
        Some(Value::String(s)) => s.as_str(),
        Some(other) => return Err(f.err("type", format!("expected a type name, found {}", describe(other)))),
        None => return Err(f.err("type", "missing")),
    };
    if let Some(kind) = ShapeKind::parse(ty) {
        let fields: Vec<&str> = shape_fields(kind).into_iter().chain(TRANSFORM_FIELDS).chain(["warp"]).collect();
        f.only(ty, &fields)?;
        let shape = match kind {
            ShapeKind::Grid => Shape::Grid(grid_ref(&f, ctx)?),
            ShapeKind::Formula => Shape::Formula(formula_leaf(&f, ctx)?),
            _ => shape(&f, kind)?,
        };
        return Ok(Node::Primitive(Primitive { shape, transform: transform(&f)?, warp: warp(&f)? }));
    }
    if ty == "repeat" || ty == "mirror" {
        return copies_node(&f, ty, ctx);
    }
    if let Some(kind) = super::warp::WarpKind::parse(ty) {
        return warp_node(&f, kind, ctx);
    }
    if let Some(t) = crate::sdf::unary::by_name(ty) {
        let fields: Vec<&str> = ["child"].iter().chain(t.fields).copied().collect();
        f.only(ty, &fields)?;
        let values = t.fields.iter().map(|k| f.number(k)).collect::<Result<Vec<f64>, _>>()?;
        return Ok(Node::Unary { op: Unary::from_values(t, &values), child: f.index("child")? });
    }
    if let Some(op) = operator(&f, ty)? {
        return Ok(Node::Operator { op, left: f.index("left")?, right: f.index("right")? });
    }
    let names: Vec<&str> =
        ShapeKind::all().into_iter().map(|k| k.name()).chain(Operator::names()).chain(crate::sdf::unary::TYPES.iter().map(|t| t.name())).chain(["repeat", "mirror", "twist", "bend"]).collect();
    let near = crate::diag::closest(ty, names.iter().copied());
    let hint = match near.first() {
        Some(n) => format!("did you mean '{n}'?"),
        None => format!("the types are {}", list(&names)),
    };
    Err(f.err("type", format!("unknown type {}; {hint}", quote(ty))))
}

/// The operation of an operator node of type `ty` (a style's or a
/// join's), its parameters read from the fields the type names; `None` for
/// another type.
fn operator(f: &Fields, ty: &str) -> Result<Option<Operator>, SceneError> {
    if let Some((style, kind)) = Operator::style_named(ty) {
        let fields: Vec<&str> = ["left", "right"].into_iter().chain(style.params.iter().map(|p| p.name)).collect();
        f.only(ty, &fields)?;
        let mut v = vec![];
        for p in style.params {
            v.push(match (f.obj.get(p.name), p.default) {
                (None, Some(d)) => d.value(&v),
                _ => f.number(p.name)?,
            });
        }
        return Ok(Some(Operator::styled(kind, style, &v)));
    }
    let Some(op) = Operator::parse(ty, 0.0) else { return Ok(None) };
    let Some(j) = op.join else { return Ok(Some(op)) };
    let name = j.size().0;
    f.only(ty, &["left", "right", name])?;
    Ok(Operator::parse(ty, f.number(name)?))
}

fn shape(f: &Fields, kind: ShapeKind) -> Result<Shape, SceneError> {
    Ok(match kind {
        ShapeKind::Analytic(t) => {
            let mut v = Vec::with_capacity(t.param_count());
            for field in t.fields {
                match (field.len, f.obj.get(field.name), field.default) {
                    (1, Some(x), _) => v.push(f.number_of(field.name, x)?),
                    (_, Some(_), _) => v.extend(f.vec3(field.name)?),
                    (_, None, Some(d)) => v.push(d.value(&v)),
                    (_, None, None) => return Err(f.err(field.name, "missing")),
                }
            }
            Shape::from_analytic(t, &v)
        }
        ShapeKind::Extrude => Shape::Extrude { profile: profile(f)?, half_height: f.number("half_height")? },
        ShapeKind::Revolve => Shape::Revolve { profile: profile(f)?, offset: f.number("offset")? },
        ShapeKind::Grid | ShapeKind::Formula => unreachable!("grids and formula leaves are read by grid_ref and formula_leaf"),
    })
}

/// A grid node's file, read (or shared with an earlier node naming the same
/// file and placement) as `ctx.paths` allows: `file` relative to the scene
/// file, and for a `.npy` its `spacing` and `origin`.
fn grid_ref(f: &Fields, ctx: &Ctx) -> Result<GridRef, SceneError> {
    let file = match f.obj.get("file") {
        Some(Value::String(s)) => s.clone(),
        Some(v) => return Err(f.err("file", format!("expected a file name, found {}", describe(v)))),
        None => return Err(f.err("file", "missing")),
    };
    let placement = match (f.obj.get("spacing"), f.obj.get("origin")) {
        (None, None) => None,
        (Some(_), None) => return Err(f.err("origin", "missing: a grid with a spacing needs its origin too")),
        (None, Some(_)) => return Err(f.err("spacing", "missing: a grid with an origin needs its spacing too")),
        (Some(v), Some(_)) => Some(Placement { spacing: f.number_of("spacing", v)?, origin: f.vec3("origin")? }),
    };
    let path = ctx.base.join(&file);
    let key = (path.clone(), placement.map(|p| [p.spacing.to_bits(), p.origin[0].to_bits(), p.origin[1].to_bits(), p.origin[2].to_bits()]));
    if let Some(g) = ctx.grids.borrow().get(&key) {
        return Ok(GridRef { file, placement, grid: g.clone() });
    }
    let g = match ctx.paths.source(&ctx.base, &file, placement) {
        Ok(paths::Source::File(path)) => Arc::new(grid::load(&path, placement).map_err(|e| f.err("file", e.to_string()))?),
        Ok(paths::Source::Loaded(g)) => g,
        Err(refused) => {
            let e = refused.at(f.err("file", "").path).map_err(|e| f.err("file", e.to_string()))?;
            *ctx.refused.borrow_mut() = Some(e.clone());
            return Err(f.err("file", e.to_string()));
        }
    };
    let total = ctx.voxels.get() + g.values().len() as u64;
    if total > MAX_SCENE_GRID_VOXELS {
        return Err(f.err("file", format!("the scene's grids hold {total} samples with this one, above the limit of {MAX_SCENE_GRID_VOXELS}")));
    }
    ctx.voxels.set(total);
    ctx.grids.borrow_mut().insert(key, g.clone());
    Ok(GridRef { file, placement, grid: g })
}

/// A formula leaf: `formula` (text), `bounds` ([x0, x1, y0, y1, z0, z1]),
/// and optionally `lipschitz`.
fn formula_leaf(f: &Fields, ctx: &Ctx) -> Result<Arc<super::leaf::FormulaLeaf>, SceneError> {
    let source = match f.obj.get("formula") {
        Some(Value::String(s)) => s.as_str(),
        Some(v) => return Err(f.err("formula", format!("expected formula text, found {}", describe(v)))),
        None => return Err(f.err("formula", "missing")),
    };
    if source.len() > crate::syntax::parser::MAX_SOURCE_BYTES {
        return Err(f.err("formula", format!("{} bytes, above the formula language's limit of {}", source.len(), crate::syntax::parser::MAX_SOURCE_BYTES)));
    }
    let bounds = f.numbers::<6>("bounds")?.ok_or_else(|| f.err("bounds", "missing: a formula leaf is held in a box [x0, x1, y0, y1, z0, z1]"))?;
    let lipschitz = f.obj.get("lipschitz").map(|v| f.number_of("lipschitz", v)).transpose()?;
    let leaf = super::leaf::FormulaLeaf::new(source, bounds, lipschitz).map_err(|(field, reason)| f.err(&field, reason))?;
    let total = ctx.leaf_ops.get() + leaf.ir.live().len();
    if total > MAX_SCENE_LEAF_OPS {
        return Err(f.err("formula", format!("the scene's formula leaves compile to {total} operations with this one, above the limit of {MAX_SCENE_LEAF_OPS}")));
    }
    ctx.leaf_ops.set(total);
    Ok(Arc::new(leaf))
}

/// Most operations of all a scene file's formula leaves together: their
/// tapes are one texture the device holds.
pub const MAX_SCENE_LEAF_OPS: usize = 200_000;

/// A `repeat` (`child`, `spacing`: [x, y, z], `count`: [nx, ny, nz]) or
/// `mirror` (`child`, `normal`) node: recorded for expansion, held as a
/// placeholder with one operand so the tree's structure is checked first.
fn copies_node(f: &Fields, ty: &str, ctx: &Ctx) -> Result<Node, SceneError> {
    use super::lower::Copies;
    let c = if ty == "repeat" {
        f.only(ty, &["child", "spacing", "count"])?;
        let spacing = f.vec3("spacing")?;
        let raw = f.vec3("count")?;
        let count = crate::sdf::repeat_counts(|k| Some(raw[k - 3]), |k, m| f.err(&format!("count[{}]", k - 3), m))?;
        Copies::Repeat { spacing, count }
    } else {
        f.only(ty, &["child", "normal"])?;
        let normal = f.vec3("normal")?;
        if normal == [0.0; 3] {
            return Err(f.err("normal", "must not be zero"));
        }
        Copies::Mirror { normal }
    };
    ctx.copies.borrow_mut().insert(f.i, c);
    Ok(Node::Unary { op: Unary::Offset { distance: 0.0 }, child: f.index("child")? })
}

/// The `profile` object of an extrusion or revolution (parameters are
/// checked later, with the shape).
fn profile(f: &Fields) -> Result<Profile, SceneError> {
    let v = f.obj.get("profile").ok_or_else(|| f.err("profile", "missing"))?;
    let obj = v.as_object().ok_or_else(|| f.err("profile", format!("expected a profile object, found {}", describe(v))))?;
    let p = Fields { i: f.i, obj, prefix: "profile." };
    let names: Vec<&str> = profile_types::TYPES.iter().map(|t| t.scene_name).collect();
    let t = match obj.get("type") {
        Some(Value::String(s)) if profile_type(s).is_some() => profile_type(s).expect("found"),
        Some(Value::String(s)) => {
            let hint = match crate::diag::closest(s, names.iter().copied()).first() {
                Some(n) => format!("did you mean '{n}'?"),
                None => format!("the profiles are {}", list(&names)),
            };
            return Err(p.err("type", format!("unknown profile {}; {hint}", quote(s))));
        }
        Some(other) => return Err(p.err("type", format!("expected a profile name, found {}", describe(other)))),
        None => return Err(p.err("type", "missing")),
    };
    p.only(t.scene_name, &profile_fields(t))?;
    let mut v = Vec::new();
    for f in t.fields {
        match f.kind {
            FieldKind::Number => v.push(p.number(f.name)?),
            FieldKind::Pair { .. } => v.extend(p.numbers::<2>(f.name)?.ok_or_else(|| p.err(f.name, "missing"))?),
            FieldKind::Points => v.extend(points(&p, f.name)?.as_flattened()),
        }
    }
    Ok(Profile::from_params(t, &v))
}

/// A list of points (a polygon's `points`): [[x, y], …], 3 to
/// MAX_POLYGON of them.
fn points(p: &Fields, name: &str) -> Result<Vec<[f64; 2]>, SceneError> {
    let v = p.obj.get(name).ok_or_else(|| p.err(name, "missing"))?;
    let a = v.as_array().ok_or_else(|| p.err(name, format!("expected a list of [x, y] points, found {}", describe(v))))?;
    let max = super::profile::MAX_POLYGON;
    if !(3..=max).contains(&a.len()) {
        return Err(p.err(name, format!("a polygon has 3 to {max} vertices, found {}", a.len())));
    }
    let mut out = Vec::with_capacity(a.len());
    for (k, item) in a.iter().enumerate() {
        let field = format!("{name}[{k}]");
        let xy = item.as_array().filter(|xy| xy.len() == 2).ok_or_else(|| p.err(&field, format!("expected [x, y], found {}", describe(item))))?;
        out.push([p.number_of(&format!("{field}[0]"), &xy[0])?, p.number_of(&format!("{field}[1]"), &xy[1])?]);
    }
    Ok(out)
}

/// A primitive's `warp` object: `type` (twist, bend), `rate` and the
/// warp's frame as a transform (the primitive's own is in that frame).
fn warp(f: &Fields) -> Result<Option<super::warp::Warp>, SceneError> {
    use super::warp::{Warp, WarpKind};
    let Some(v) = f.obj.get("warp") else { return Ok(None) };
    let obj = v.as_object().ok_or_else(|| f.err("warp", format!("expected a warp object, found {}", describe(v))))?;
    let w = Fields { i: f.i, obj, prefix: "warp." };
    let kind = match obj.get("type") {
        Some(Value::String(s)) => WarpKind::parse(s).ok_or_else(|| w.err("type", format!("unknown warp {}; the warps are twist and bend", quote(s))))?,
        Some(other) => return Err(w.err("type", format!("expected a warp name, found {}", describe(other)))),
        None => return Err(w.err("type", "missing")),
    };
    w.only(kind.name(), &["rate", "translate", "rotate", "scale"])?;
    Ok(Some(Warp { kind, rate: w.number("rate")?, frame: transform(&w)?, clamp: None }))
}

/// A file's `twist` or `bend` node: its operand warped about the z axis of
/// the node's own frame (`translate`, `rotate`, `scale`), expanded when
/// read into a warp on each of the operand's primitives.
fn warp_node(f: &Fields, kind: super::warp::WarpKind, ctx: &Ctx) -> Result<Node, SceneError> {
    f.only(kind.name(), &["child", "rate", "translate", "rotate", "scale"])?;
    let rate = f.number("rate")?;
    if !rate.is_finite() {
        return Err(f.err("rate", "must be finite"));
    }
    let frame = transform(f)?;
    frame.check().map_err(|(field, reason)| f.err(&field, reason))?;
    ctx.copies.borrow_mut().insert(f.i, super::lower::Copies::Warp { kind, rate, frame });
    Ok(Node::Unary { op: Unary::Offset { distance: 0.0 }, child: f.index("child")? })
}

fn transform(f: &Fields) -> Result<Transform, SceneError> {
    let translate = f.numbers::<3>("translate")?.unwrap_or([0.0; 3]);
    let rotate = f.numbers::<4>("rotate")?.map(|r| Rotation { axis: [r[0], r[1], r[2]], angle: r[3] });
    let scale = match f.obj.get("scale") {
        Some(v) => f.number_of("scale", v)?,
        None => 1.0,
    };
    Ok(Transform { translate, rotate, scale })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let s = crate::scene::generate::generate(crate::scene::generate::Kind::SpherePairs, 0, crate::scene::generate::Blending::Smooth, 3).unwrap();
        assert_eq!(parse(&to_json(&s)).unwrap(), s);
    }

    #[test]
    fn huge_numbers_are_named_at_their_node() {
        let e = parse("{\"isotrace_scene\": 1, \"root\": 0, \"nodes\": [{\"type\": \"sphere\", \"radius\": 1e999}]}").unwrap_err();
        assert_eq!(e.to_string(), "nodes[0]: number out of range at line 1 column 77");
    }
}
