//! The mechanism over one turn as the designer draws it (`cwsynth serve`, issue 35): the
//! data every family with a drawing fills the same way — the moving links as segments per
//! crank angle, the counterweights' centroids, the frame's fixed lines, and the handles a
//! user drags, each with the key of the problem file it edits. SI (m, rad), the world frame.

use serde::Serialize;

/// Frames of one turn the designer animates.
pub const FRAMES: usize = 72;

/// One crank angle: the links' segments and the counterweights' centroids.
#[derive(Debug, Clone, Serialize)]
pub struct Frame {
    /// θ (rad).
    pub theta: f64,
    /// Each link's [reference joint, tip] (a link without a tip: both ends equal).
    pub links: Vec<[[f64; 2]; 2]>,
    /// Each counterweight with a mass: its centroid.
    pub counterweights: Vec<[f64; 2]>,
}

/// A frame point the file gives by value: dragging it edits `key` (a point `[x, y]`).
#[derive(Debug, Clone, Serialize)]
pub struct Handle {
    /// The dotted key (`mechanism.crank_pivot`, `mechanism.dyads[1].q`, …).
    pub key: String,
    /// Where it is.
    pub at: [f64; 2],
}

/// The mechanism over one turn: the frames (angles where it does not assemble left out).
#[derive(Debug, Clone, Serialize)]
pub struct Motion {
    /// The links' names, in the frames' order.
    pub names: Vec<String>,
    /// The frames.
    pub frames: Vec<Frame>,
    /// Fixed lines of the frame (a slider's guide), as segments.
    pub guides: Vec<[[f64; 2]; 2]>,
    /// The frame points to drag.
    pub handles: Vec<Handle>,
}

/// A point as the frames write it.
pub fn xy(p: crate::geom::P2) -> [f64; 2] {
    [p.x, p.y]
}
