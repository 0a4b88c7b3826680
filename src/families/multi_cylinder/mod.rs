//! Several slider-cranks on one crankshaft — inline, V, boxer, any bank and phase — whole:
//! its physics (`model`: the force in the plane of motion, the couple about the two axes
//! normal to the shaft, the harmonics of every order), its problem file (`file`), its solve
//! (`solve`: the crank-web counterweights and balance shafts certified by the minimax engine),
//! its numbers, documents and motion, and its study ladder (`study`), behind the `Family` and
//! `Machine` traits (issue 39; `shared/domain/multi-cylinder.md`).

pub mod articulated;
pub mod file;
pub mod firing;
pub mod model;
pub mod motion;
pub mod mounts;
pub mod numbers;
pub mod phases;
pub mod report;
pub mod solve;
pub mod study;

crate::family_folder!(
    /// Several slider-cranks on one crankshaft.
    MultiCylinder,
    file::MultiCylinderProblem
);
