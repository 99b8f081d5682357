//! Ready-made chains for `articulated`, each as a `.chain` file and, where URDF can express it, a
//! `.urdf` file with the same dynamics (the tests check that they agree).
//!
//! | model | `.chain` | `.urdf` | what it is |
//! |---|---|---|---|
//! | [`TWO_LINK`] | yes | yes | Hemami, Dariush & Barin (2005): legs and trunk of a standing person, two spherical roll-pitch-yaw joints |
//! | [`INVERTED_PENDULUM`] | yes | yes | one body on a spherical joint at a fixed point (Hemami §2.2) |
//! | [`DOUBLE_PENDULUM`] | yes | yes | planar, two revolute joints about y (closed form known) |
//! | [`ARM7`] | yes | yes | a 7-DOF serial arm, iiwa-like kinematics, full inertia tensors |
//! | [`TREE`] | yes | yes | a torso, two three-link arms and a head on a fixed joint |
#![no_std]

/// A model shipped in this crate: its name and the paths of its files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelFiles {
    /// Short name, also the file stem.
    pub name: &'static str,
    /// Absolute path of the `.chain` file.
    pub chain: &'static str,
    /// Absolute path of the `.urdf` file, where URDF can express the model.
    pub urdf: Option<&'static str>,
}

macro_rules! model {
    ($name:literal, urdf) => {
        ModelFiles {
            name: $name,
            chain: concat!(env!("CARGO_MANIFEST_DIR"), "/", $name, ".chain"),
            urdf: Some(concat!(env!("CARGO_MANIFEST_DIR"), "/", $name, ".urdf")),
        }
    };
}

/// Hemami's three-dimensional two-link system (legs and trunk).
pub const TWO_LINK: ModelFiles = model!("two_link", urdf);
/// A single three-dimensional inverted pendulum.
pub const INVERTED_PENDULUM: ModelFiles = model!("inverted_pendulum", urdf);
/// A planar double pendulum.
pub const DOUBLE_PENDULUM: ModelFiles = model!("double_pendulum", urdf);
/// A 7-DOF arm.
pub const ARM7: ModelFiles = model!("arm7", urdf);
/// A branching tree: torso, two arms, head.
pub const TREE: ModelFiles = model!("tree", urdf);

/// Every model of this crate.
pub const ALL: [ModelFiles; 5] = [TWO_LINK, INVERTED_PENDULUM, DOUBLE_PENDULUM, ARM7, TREE];
