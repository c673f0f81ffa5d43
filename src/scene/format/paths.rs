//! Which grid files a scene may make isotrace read.
//!
//! A scene file is data, and may come from anyone: its grid nodes name
//! files, and a file named `/home/me/.ssh/id_rsa.npy` or `../../x.npy`
//! would be read as samples (and shown: a grid's samples are the field).
//! So by default a grid `file` must stay inside the scene file's directory
//! ([`GridPaths::InsideSceneDir`], the rule of an `.iso` header's `env:`
//! image); the user can vouch for a scene ([`GridPaths::Any`]); and a
//! server that edits a scene it loaded reads no file at all
//! ([`GridPaths::Only`]: the grids already in memory).

use crate::bounded;
use crate::scene::grid::{self, Grid, GridError, Placement};
use crate::scene::primitive::GridRef;
use crate::scene::{Node, Scene, Shape};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The grid files a scene may name.
#[derive(Debug, Clone, Default)]
pub enum GridPaths {
    /// Files inside the scene file's directory (for text without a file,
    /// the directory given to [`super::parse_with`]): no absolute path, no
    /// `..` above it, no symbolic link leading out.
    #[default]
    InsideSceneDir,
    /// Any path: the user trusts the scene.
    Any,
    /// No file is read: only these grids, found by the `file` string as the
    /// scene names it. A `.npy` grid may be placed anew (its samples are
    /// reused with another `spacing` and `origin`).
    Only(Vec<GridRef>),
}

/// A grid `file` the policy refuses.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GridPathError {
    /// Outside the scene file's directory under [`GridPaths::InsideSceneDir`].
    #[error("{json_path}: the grid file '{}' is outside the directory of the scene file", file.display())]
    OutsideSceneDir {
        /// `nodes[3].file`.
        json_path: String,
        /// The file as it would be opened (the scene's directory joined
        /// with the name).
        file: PathBuf,
    },
    /// Not one of the grids of [`GridPaths::Only`]. The message does not
    /// repeat the name, and nothing was looked up on disk, so it tells
    /// nothing about which files exist.
    #[error("{json_path}: not a grid file of the loaded scene; an edit may use only the grids its scene file names")]
    NotLoaded {
        /// `nodes[3].file`.
        json_path: String,
    },
}

/// Why a grid node has no grid.
pub(super) enum Refused {
    /// Outside the scene file's directory: the file as it would be opened.
    Outside(PathBuf),
    /// Not one of [`GridPaths::Only`]'s grids.
    NotLoaded,
    /// The samples of [`GridPaths::Only`] cannot be placed as asked.
    Grid(GridError),
}

impl Refused {
    /// The policy's refusal at `json_path`, or the grid's error.
    pub(super) fn at(self, json_path: String) -> Result<GridPathError, GridError> {
        match self {
            Refused::Outside(file) => Ok(GridPathError::OutsideSceneDir { json_path, file }),
            Refused::NotLoaded => Ok(GridPathError::NotLoaded { json_path }),
            Refused::Grid(e) => Err(e),
        }
    }
}

/// Where a grid comes from under a policy.
pub(super) enum Source {
    /// Read this file.
    File(PathBuf),
    /// Already in memory.
    Loaded(Arc<Grid>),
}

impl GridPaths {
    /// [`GridPaths::Only`] the grids of `scene`.
    pub fn loaded_by(scene: &Scene) -> GridPaths {
        let grids = scene.nodes().iter().filter_map(|n| match n {
            Node::Primitive(p) => match &p.shape {
                Shape::Grid(g) => Some(g.clone()),
                _ => None,
            },
            _ => None,
        });
        GridPaths::Only(grids.collect())
    }

    /// Where the grid of a node naming `file` (with `placement`) in a scene
    /// whose grid files are relative to `base` comes from.
    pub(super) fn source(&self, base: &Path, file: &str, placement: Option<Placement>) -> Result<Source, Refused> {
        let path = base.join(file);
        match self {
            GridPaths::Any => Ok(Source::File(path)),
            GridPaths::InsideSceneDir if bounded::leaves_dir(base, Path::new(file)) => Err(Refused::Outside(path)),
            GridPaths::InsideSceneDir => Ok(Source::File(path)),
            GridPaths::Only(grids) => {
                let named = || grids.iter().filter(|g| g.file == file);
                if let Some(g) = named().find(|g| g.placement == placement) {
                    return Ok(Source::Loaded(g.grid.clone()));
                }
                let Some(g) = named().next() else {
                    return Err(Refused::NotLoaded);
                };
                grid::check_kind(&path, placement).map_err(Refused::Grid)?;
                // check_kind passed: a grid placed anew is a .npy, which has a placement.
                let Some(placement) = placement else { return Err(Refused::NotLoaded) };
                let err = |kind| Refused::Grid(GridError { file: path.display().to_string(), kind });
                Ok(Source::Loaded(Arc::new(g.grid.placed(placement).map_err(err)?)))
            }
        }
    }
}
