//! `isotrace view`: an interactive page that renders with WebGPU in the
//! browser, running the same generated WGSL kernels as `render`.
//!
//! The compiler stays here (no wasm target): the server compiles a formula
//! (front end, codegen, naga) and sends the page a [`program::Program`],
//! the kernel with its uniform layouts, bind groups and dispatch stages as
//! data. The page's host (`web/app.js`) only follows that description: it
//! writes uniforms by field name, creates the buffers by their size rules
//! and runs the stages in order, then draws the pixel records with the
//! present shader (`templates/view/present.wgsl`). Parameters, t, the
//! camera and a scene's buffers change no pipeline.
//!
//! - [`program`](mod@program): the kernel and its description;
//! - [`present`]: the present pass's shader and bind group;
//! - [`server`]: the HTTP server and its JSON API;
//! - [`http`]: its wire layer (limits and deadlines);
//! - [`access`]: who may call it (Host, Origin, the session token);
//! - [`page`]: the embedded assets and the `--export` page.

pub mod access;
pub mod http;
pub mod page;
pub mod present;
pub mod program;
pub mod server;

pub use present::present_shader;
pub use program::{field_buffers, program};
pub use server::{Api, ApiError, Reply, Route, Server};
