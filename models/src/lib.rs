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
//! | [`HUMANOID`] | yes | yes (the tree under the free base) | a floating-base humanoid: waist, neck, 7-DOF arms, 6-DOF legs; 37 velocity coordinates |
//! | [`CHAIN50`] | yes | yes | a 50-body serial chain, for scale |
//! | [`FALLING_CAT`] | yes | no | the falling cat: two cylinders joined at the waist (spherical), the front one on a free base |
//! | [`BIPED`] | yes | no | a free-floating walker from de Leva's (1996) segments: hips, knees, shoulders about y |
//! | [`TWO_LINK_FOOT`] | yes | no | Hemami's two-link system on a free foot, which a six-dimensional contact on its `sole` holds on the ground |
//! | [`FOUR_BAR`] | yes | no | a four-bar linkage: an open chain whose frames `tip` and `ground` a loop constraint closes |
//! | [`BLOCK`] | yes | no | a 1 kg cube on a free base: the box of the contact simulation, its corners as contact points |
//!
//! The two models for scale are written by `models/make_scale_models.py` (the numbers and their
//! sources are documented there). `humanoid.chain` puts the pelvis on a free base with a
//! quaternion; `humanoid.urdf` describes the tree under it, so it matches the `.chain` file
//! only with a free base added ([`ModelFiles::free_base`]). The two free-floating models of the
//! examples `falling_cat` and `walking_rotation` have no URDF: their roots are on a free base with
//! a quaternion, and the URDF import adds a free base only in Euler angles (`floating`).
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
    /// The `.chain` file puts the root on a free base (`free(quaternion)`) that the URDF leaves
    /// out: the URDF describes the tree under it (load it with `floating`).
    pub free_base: bool,
}

macro_rules! model {
    ($name:literal) => {
        ModelFiles {
            name: $name,
            chain: concat!(env!("CARGO_MANIFEST_DIR"), "/", $name, ".chain"),
            urdf: None,
            free_base: false,
        }
    };
    ($name:literal, urdf) => {
        ModelFiles {
            name: $name,
            chain: concat!(env!("CARGO_MANIFEST_DIR"), "/", $name, ".chain"),
            urdf: Some(concat!(env!("CARGO_MANIFEST_DIR"), "/", $name, ".urdf")),
            free_base: false,
        }
    };
    ($name:literal, urdf, free_base) => {
        ModelFiles {
            free_base: true,
            ..model!($name, urdf)
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

/// A floating-base humanoid, 38 positions and 37 velocities.
pub const HUMANOID: ModelFiles = model!("humanoid", urdf, free_base);
/// A 50-body serial chain.
pub const CHAIN50: ModelFiles = model!("chain50", urdf);

/// The falling cat (Wieber 2005, §4.2): 10 positions, 9 velocities.
pub const FALLING_CAT: ModelFiles = model!("falling_cat");
/// A free-floating walker (Wieber 2005, §5.1): 13 positions, 12 velocities.
pub const BIPED: ModelFiles = model!("biped");
/// Hemami's two-link system on a free foot (`free(quaternion)`) whose frame `sole` a
/// six-dimensional contact holds on the ground: 13 positions, 12 velocities.
pub const TWO_LINK_FOOT: ModelFiles = model!("two_link_foot");
/// A four-bar linkage (a closed loop: `articulated::constraint::Loop` on its frames `tip` and
/// `ground`): 3 positions, 3 velocities, one degree of freedom once closed.
pub const FOUR_BAR: ModelFiles = model!("four_bar");

/// A 1 kg cube of side 0.2 m on a free base: the box of the contact simulation
/// (`articulated::contact`), 7 positions, 6 velocities.
pub const BLOCK: ModelFiles = model!("block");

/// The small models: Hemami's, the pendulums, the arm and the tree. Tests that compile the
/// generated code of every model take these; the models for scale ([`HUMANOID`], [`CHAIN50`])
/// have tests of their own.
pub const SMALL: [ModelFiles; 5] = [TWO_LINK, INVERTED_PENDULUM, DOUBLE_PENDULUM, ARM7, TREE];

/// Every model of this crate.
pub const ALL: [ModelFiles; 12] = [
    TWO_LINK,
    INVERTED_PENDULUM,
    DOUBLE_PENDULUM,
    ARM7,
    TREE,
    HUMANOID,
    CHAIN50,
    FALLING_CAT,
    BIPED,
    TWO_LINK_FOOT,
    FOUR_BAR,
    BLOCK,
];
