//! Any one-degree-of-freedom planar linkage (issue 17): a crank and a chain of Assur dyads,
//! with the shaking force, shaking moment, input torque and joint reactions as linear maps in
//! the links' inertial parameters. For now only its physics (`model`); the problem file, the
//! synthesis and the registry entry come with the family.

pub mod file;
pub mod model;
