//! Input and output: problem files (raw serde layer, resolution into checked scenes),
//! results (JSON, Markdown), plots (SVG) and atomic file writing.

pub mod crane;
pub mod gear;
pub mod hypocycloid;
pub mod limits;
pub mod plot;
pub mod problem;
pub mod result;
pub mod schema;
pub mod slider_crank;
pub mod source;
