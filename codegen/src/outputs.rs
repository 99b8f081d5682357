//! Every output, described once: its name in `outputs:` (the generated function's), its trait,
//! arguments, result, group, the equation its function's docs open with, and its trait's docs.
//! Everything else is derived from this table: [`Output::ALL`] and the names the grammar, the
//! attribute and the CLI accept, the groups (`outputs: [dynamics, whole_body]`), the generated
//! function's signature and result ([`crate::generate`]), the stand-ins after an error
//! ([`crate::expand`]), and the runtime's traits themselves ([`runtime_traits`], expanded in the
//! `articulated` crate by `articulated_macros::__output_traits!`).
//!
//! Adding an output is one entry in `outputs!` below plus its trace ([`crate::trace`]).

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

/// An argument of an output's function (`q` always first), in the order they are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arg {
    /// `q`: the position coordinates, `NQ`.
    Q,
    /// `v`: the velocities, `NV`.
    V,
    /// `a`: the accelerations, `NV`.
    A,
    /// `tau`: the generalized forces, `NV`.
    Tau,
    /// `base`: the wrench the world exerts on the root body, 6.
    Base,
}

impl Arg {
    /// Its name in the signature.
    pub fn name(self) -> &'static str {
        match self {
            Arg::Q => "q",
            Arg::V => "v",
            Arg::A => "a",
            Arg::Tau => "tau",
            Arg::Base => "base",
        }
    }
}

/// A size in a result's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// `NV`, the velocities.
    Nv,
    /// `NB`, the joints (fixed ones included).
    Nb,
    /// `NF`, the frames the description names (`frames: [...]`).
    Nf,
    /// A number.
    N(usize),
}

/// How the traced values of one part of a result are ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Row by row.
    Rows,
    /// Column by column (nalgebra's storage), or a symmetric matrix.
    Columns,
}

/// What an output gives for each frame it is asked for ([`Part::Frames`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Each {
    /// Its placement in the world: the rotation's 9 values row by row, then the translation's
    /// 3 (`FramePlacement`).
    Placement,
    /// A vector of `n`.
    Vector(usize),
    /// A matrix `rows × cols`, its values in `order`.
    Matrix(usize, Dim, Order),
    /// `n` matrices `rows × cols` (a tuple), each's values in `order`, one after the other.
    Matrices(usize, usize, Dim, Order),
}

/// One part of an output's traced values and what the function makes of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// One value, returned as the scalar.
    Scalar,
    /// A vector.
    Vector(Dim),
    /// A matrix `rows × cols`, its values in `order`.
    Matrix(Dim, Dim, Order),
    /// `NV` values computed on the way and checked, not returned (the accelerations of
    /// forward dynamics' derivatives).
    Hidden,
    /// `M` written into the `kept` argument, whole or (`lower`) its lower triangle: nothing is
    /// returned.
    Kept {
        /// Only the lower triangle.
        lower: bool,
    },
    /// One value per frame named in `frames: [...]`, in that order: an array `[X; NF]`; the
    /// traced values frame by frame.
    Frames(Each),
}

/// A named set of outputs, for `outputs: [dynamics, whole_body]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Group {
    /// The terms of the equations of motion and their combinations.
    Dynamics,
    /// `M` into a matrix the caller keeps.
    Kept,
    /// The wrench each joint transmits.
    Wrenches,
    /// The quantities of the whole system (Wieber 2005, §4).
    WholeBody,
    /// The derivatives of the dynamics.
    Derivatives,
    /// The placements, velocities, accelerations and Jacobians of the frames named in
    /// `frames: [...]`.
    Frames,
}

impl Group {
    /// Every group with its name in `outputs:`.
    pub const ALL: [(Group, &'static str); 6] = [
        (Group::Dynamics, "dynamics"),
        (Group::Kept, "kept"),
        (Group::Wrenches, "wrenches"),
        (Group::WholeBody, "whole_body"),
        (Group::Derivatives, "derivatives"),
        (Group::Frames, "frames"),
    ];

    /// The runtime's trait that bounds a chain by every output of the group (where none needs
    /// `NB`): `DynamicsOutputs`, `WholeBodyOutputs`…
    pub fn trait_name(self) -> &'static str {
        match self {
            Group::Dynamics => "DynamicsOutputs",
            Group::Kept => "KeptOutputs",
            Group::Wrenches => "WrenchOutputs",
            Group::WholeBody => "WholeBodyOutputs",
            Group::Derivatives => "DerivativeOutputs",
            Group::Frames => "FrameOutputs",
        }
    }

    /// The group of that name.
    pub fn from_name(name: &str) -> Option<Group> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(g, _)| *g)
    }

    /// Its outputs, in the order of [`Output::ALL`]. `joint_wrenches_bottom_up` is in no group:
    /// it is for serial chains only.
    pub fn outputs(self) -> impl Iterator<Item = Output> {
        SPECS
            .iter()
            .filter(move |s| s.group == Some(self))
            .map(|s| s.output)
    }
}

/// One output, described once.
#[derive(Debug)]
pub struct Spec {
    /// Which output.
    pub output: Output,
    /// Its name in `outputs:`: the generated function's.
    pub name: &'static str,
    /// The runtime's trait its function belongs to.
    pub trait_name: &'static str,
    /// The group that names it, if any.
    pub group: Option<Group>,
    /// Whether it is generated when a description names no outputs.
    pub default: bool,
    /// Its arguments besides the parameters.
    pub args: &'static [Arg],
    /// Its traced values, part by part, and what the function makes of each.
    pub parts: &'static [Part],
    /// Whether it solves with `M`: a `Result` with `SingularMassMatrix`.
    pub fallible: bool,
    /// Whether it is a quantity of the whole system (`reference::centroidal`).
    pub whole_body: bool,
    /// What it computes: the first paragraph of the generated function's docs.
    pub equation: &'static str,
    /// What its trait's methods give, for their docs ("`M(q)`").
    pub value: &'static str,
    /// The runtime trait's documentation.
    pub trait_doc: &'static str,
}

/// Declares [`Output`] and its [`SPECS`] from one list.
macro_rules! outputs {
    ($(
        $(#[$attr:meta])*
        $variant:ident {
            name: $name:literal,
            trait_name: $trait_name:literal,
            group: $group:expr,
            default: $default:literal,
            args: [$($arg:ident),*],
            parts: [$($part:expr),*],
            fallible: $fallible:literal,
            whole_body: $whole_body:literal,
            value: $value:literal,
            equation: $equation:literal,
            trait_doc: $trait_doc:literal $(,)?
        }
    ),* $(,)?) => {
        /// A function the generator can emit for a chain; its name in `outputs:` is the
        /// function's. Each is described once, in [`SPECS`].
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Output {
            $($(#[$attr])* $variant,)*
        }

        /// Every output's description, in the order the generator emits them (that of
        /// [`Output`]).
        pub const SPECS: &[Spec] = &[$(Spec {
            output: Output::$variant,
            name: $name,
            trait_name: $trait_name,
            group: $group,
            default: $default,
            args: &[$(Arg::$arg),*],
            parts: &[$($part),*],
            fallible: $fallible,
            whole_body: $whole_body,
            value: $value,
            equation: $equation,
            trait_doc: $trait_doc,
        }),*];
    };
}

use Dim::{Nb, Nv, N};
use Order::{Columns, Rows};
use Part::{Frames, Hidden, Kept, Matrix, Scalar, Vector};

outputs! {
    /// `mass_matrix(q)`: `M(q)`.
    MassMatrix {
        name: "mass_matrix",
        trait_name: "MassMatrix",
        group: Some(Group::Dynamics),
        default: true,
        args: [Q],
        parts: [Matrix(Nv, Nv, Columns)],
        fallible: false,
        whole_body: false,
        value: "`M(q)`",
        equation: "`M(q)`, the joint-space mass matrix (Wieber 2005, eq. 6).",
        trait_doc: "`M(q)`: the joint-space mass matrix (Wieber 2005, eq. 6; Featherstone 2008, \
                    RBDA §6.2).",
    },
    /// `mass_matrix_update(q, &mut kept)`: `M(q)` into a `KeptMassMatrix`, only the entries that
    /// can be non-zero written (the others stay zero from one call to the next).
    MassMatrixUpdate {
        name: "mass_matrix_update",
        trait_name: "MassMatrixUpdate",
        group: Some(Group::Kept),
        default: false,
        args: [Q],
        parts: [Kept { lower: false }],
        fallible: false,
        whole_body: false,
        value: "`M(q)`",
        equation: "`M(q)`, the joint-space mass matrix (Wieber 2005, eq. 6), written into `kept`: \
                   only the entries that can be non-zero, the others left as they are, zero \
                   (`articulated::KeptMassMatrix`).",
        trait_doc: "`M(q)` written into a [`KeptMassMatrix`] (the output `mass_matrix_update`): \
                    only the entries that can be non-zero, without zeroing the rest first.",
    },
    /// `mass_matrix_lower(q, &mut kept)`: the lower triangle of `M(q)`, diagonal included, into
    /// a `KeptMassMatrixLower` (the update's entries on and below the diagonal).
    MassMatrixLower {
        name: "mass_matrix_lower",
        trait_name: "MassMatrixLower",
        group: Some(Group::Kept),
        default: false,
        args: [Q],
        parts: [Kept { lower: true }],
        fallible: false,
        whole_body: false,
        value: "The lower triangle of `M(q)`",
        equation: "The lower triangle of `M(q)`, the joint-space mass matrix (Wieber 2005, eq. \
                   6), diagonal included, written into `kept`: the entries on and below the \
                   diagonal that can be non-zero; the strict upper triangle is never written \
                   and stays zero (`articulated::KeptMassMatrixLower`, what nalgebra's \
                   `Cholesky::new` reads).",
        trait_doc: "The lower triangle of `M(q)`, diagonal included, written into a \
                    [`KeptMassMatrixLower`] (the output `mass_matrix_lower`): the entries of \
                    [`MassMatrixUpdate`] on and below the diagonal, the strict upper triangle \
                    never written, so it stays zero.\n\n\
                    That is the half of `M` that nalgebra's `Cholesky::new` and `sygemv` read, \
                    and the half Pinocchio's `crba` leaves out (it fills the upper triangle). \
                    Half the stores of the whole update, so less code: faster where the whole \
                    update's code sits at the size of the instruction cache and the lower \
                    triangle's fits below it, as on the 37-coordinate humanoid. Not everywhere \
                    faster: on a long serial chain LLVM compiles the stores, strided in memory \
                    (one row of `M` is computed at a time, the storage is by column), into more \
                    code than the whole update's. `BENCHMARKS.md` times both on four models; \
                    measure it on your chain.",
    },
    /// `bias(q, v)`: `N(q, q̇)·q̇` without gravity.
    Bias {
        name: "bias",
        trait_name: "Bias",
        group: Some(Group::Dynamics),
        default: true,
        args: [Q, V],
        parts: [Vector(Nv)],
        fallible: false,
        whole_body: false,
        value: "`N(q, q̇)·q̇`",
        equation: "`N(q, q̇)·q̇`, the velocity-product terms without gravity (Wieber 2005, eq. 7).",
        trait_doc: "`N(q, q̇)·q̇`: the velocity-product terms, without gravity (Wieber 2005, eq. 7).",
    },
    /// `gravity(q)`: `g(q)`.
    Gravity {
        name: "gravity",
        trait_name: "Gravity",
        group: Some(Group::Dynamics),
        default: true,
        args: [Q],
        parts: [Vector(Nv)],
        fallible: false,
        whole_body: false,
        value: "`g(q)`",
        equation: "`g(q)`, the generalized force that holds the chain still.",
        trait_doc: "`g(q)`: the generalized force that holds the chain still against gravity \
                    (minus Wieber's `𝓕_g`, eq. 14).",
    },
    /// `inverse_dynamics(q, v, a)`: `τ = M·a + bias + gravity`.
    InverseDynamics {
        name: "inverse_dynamics",
        trait_name: "InverseDynamics",
        group: Some(Group::Dynamics),
        default: true,
        args: [Q, V, A],
        parts: [Vector(Nv)],
        fallible: false,
        whole_body: false,
        value: "`τ`",
        equation: "`τ = M(q)·a + N(q, q̇)·q̇ + g(q)`: the joint forces that produce the \
                   acceleration `a`.",
        trait_doc: "`τ = M(q)·a + N(q, q̇)·q̇ + g(q)`: the joint forces that produce the \
                    acceleration `a` (Featherstone 2008, RBDA §5.3).",
    },
    /// `forward_dynamics(q, v, tau)`: `q̈`, or an error where `M` is singular.
    ForwardDynamics {
        name: "forward_dynamics",
        trait_name: "ForwardDynamics",
        group: Some(Group::Dynamics),
        default: true,
        args: [Q, V, Tau],
        parts: [Vector(Nv)],
        fallible: true,
        whole_body: false,
        value: "`q̈`",
        equation: "`q̈ = M(q)⁻¹·(τ − N(q, q̇)·q̇ − g(q))`; an error where `M(q)` is singular.",
        trait_doc: "`q̈ = M(q)⁻¹·(τ − N(q, q̇)·q̇ − g(q))`, or an error where `M(q)` is singular.",
    },
    /// `nonlinear_effects(q, v)`: `N(q, q̇)·q̇ + g(q)` in one pass (Pinocchio's
    /// `nonLinearEffects`).
    NonlinearEffects {
        name: "nonlinear_effects",
        trait_name: "NonlinearEffects",
        group: Some(Group::Dynamics),
        default: false,
        args: [Q, V],
        parts: [Vector(Nv)],
        fallible: false,
        whole_body: false,
        value: "`N·q̇ + g`",
        equation: "`N(q, q̇)·q̇ + g(q)`, bias and gravity in one pass: inverse dynamics at `a = 0` \
                   (Pinocchio's `nonLinearEffects`).",
        trait_doc: "`N(q, q̇)·q̇ + g(q)`: the velocity-product terms and gravity together, in one \
                    pass (inverse dynamics at `a = 0`; Pinocchio's `nonLinearEffects`), cheaper \
                    than [`Bias`] then [`Gravity`].",
    },
    /// `mass_matrix_and_nonlinear_effects(q, v)`: `M(q)` and `N·q̇ + g` from one function that
    /// computes the kinematics they share once (what a controller asks at every tick).
    MassMatrixAndNonlinearEffects {
        name: "mass_matrix_and_nonlinear_effects",
        trait_name: "MassMatrixAndNonlinearEffects",
        group: Some(Group::Dynamics),
        default: false,
        args: [Q, V],
        parts: [Matrix(Nv, Nv, Columns), Vector(Nv)],
        fallible: false,
        whole_body: false,
        value: "`M` and `N·q̇ + g`",
        equation: "`(M(q), N(q, q̇)·q̇ + g(q))` from one function, the kinematics both need \
                   computed once: what a controller asks at every tick.",
        trait_doc: "`(M(q), N(q, q̇)·q̇ + g(q))` from one function, which computes the kinematics \
                    both need once: what a controller asks at every tick.",
    },
    /// `joint_wrenches(q, v, a)`: the wrench each joint transmits, from the free ends down.
    JointWrenches {
        name: "joint_wrenches",
        trait_name: "JointWrenches",
        group: Some(Group::Wrenches),
        default: false,
        args: [Q, V, A],
        parts: [Matrix(N(6), Nb, Columns)],
        fallible: false,
        whole_body: false,
        value: "The wrenches at `(q, v, a)`",
        equation: "The wrench `[n; f]` each joint transmits at `(q, v, a)`, gravity included: \
                   what the parent exerts on the child, in the child's frame about its origin \
                   (Hemami's couple and reaction force), one column per joint in joint order. \
                   From the free ends down (the backward pass of Newton–Euler).",
        trait_doc: "The wrench each joint transmits (Hemami's joint couple and reaction force), \
                    from the free ends down: what the parent exerts on the child across the \
                    joint, in the child's frame about its origin, `[n; f]` (angular first), \
                    gravity included. One column per joint in joint order (`NB` joints, fixed \
                    ones included). The backward pass of Newton–Euler (Featherstone 2008, RBDA \
                    §5.3).",
    },
    /// `joint_wrenches_bottom_up(q, v, a, base)`: the same from the base up, starting from the
    /// wrench the world exerts on the root body (a serial chain only).
    JointWrenchesBottomUp {
        name: "joint_wrenches_bottom_up",
        trait_name: "JointWrenchesBottomUp",
        group: None,
        default: false,
        args: [Q, V, A, Base],
        parts: [Matrix(N(6), Nb, Columns)],
        fallible: false,
        whole_body: false,
        value: "The wrenches at `(q, v, a)` from `base`",
        equation: "The wrench `[n; f]` each joint transmits at `(q, v, a)`, from the base up \
                   (Hemami, Dariush & Barin 2005, §5): `base` is the wrench the world exerts on \
                   the root body, in its frame about its origin (a measured ground reaction). \
                   With the true base wrench it equals `joint_wrenches`; on measured motion \
                   their difference checks the data.",
        trait_doc: "The wrench each joint transmits, as [`JointWrenches`], but from the base up \
                    (Hemami, Dariush & Barin 2005, §5: \"the sequence can start from the ground \
                    upwards\"): from `base`, the wrench the world exerts on the root body (a \
                    measured ground reaction, in the root body's frame about its origin), body \
                    by body up a serial chain. With the true base wrench both agree; on measured \
                    motion their difference is the consistency check of the data.",
    },
    /// `center_of_mass(q)`: the centre of mass `x_G`, world frame.
    CenterOfMass {
        name: "center_of_mass",
        trait_name: "CenterOfMass",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q],
        parts: [Vector(N(3))],
        fallible: false,
        whole_body: true,
        value: "`x_G`",
        equation: "`x_G(q) = Σ m_k·x_k / Σ m_k`, the centre of mass in the world frame.",
        trait_doc: "`x_G(q)`: the centre of mass of the whole system, world frame (Wieber 2005, \
                    §4).",
    },
    /// `center_of_mass_velocity(q, v)`: `ẋ_G`, world frame.
    CenterOfMassVelocity {
        name: "center_of_mass_velocity",
        trait_name: "CenterOfMassVelocity",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V],
        parts: [Vector(N(3))],
        fallible: false,
        whole_body: true,
        value: "`ẋ_G`",
        equation: "`ẋ_G(q, v) = p / m`, the velocity of the centre of mass in the world frame.",
        trait_doc: "`ẋ_G(q, v) = p / m`: the velocity of the centre of mass, world frame.",
    },
    /// `center_of_mass_jacobian(q)`: `J_G` with `ẋ_G = J_G·v`, `3 × NV`.
    CenterOfMassJacobian {
        name: "center_of_mass_jacobian",
        trait_name: "CenterOfMassJacobian",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q],
        parts: [Matrix(N(3), Nv, Rows)],
        fallible: false,
        whole_body: true,
        value: "`J_G`",
        equation: "`J_G(q)`, `3 × NV`, with `ẋ_G = J_G·v`: the centre of mass Jacobian, world \
                   frame.",
        trait_doc: "`J_G(q)`, `3 × NV`: the centre of mass Jacobian, `ẋ_G = J_G·v`, world frame.",
    },
    /// `centroidal_momentum(q, v)`: `h_G = [k_G; p]`, the angular momentum about the centre of
    /// mass and the linear momentum, world axes.
    CentroidalMomentum {
        name: "centroidal_momentum",
        trait_name: "CentroidalMomentum",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V],
        parts: [Vector(N(6))],
        fallible: false,
        whole_body: true,
        value: "`h_G`",
        equation: "`h_G = [k_G; p]`: the angular momentum about the centre of mass, then the \
                   linear momentum, world axes (Wieber 2005, §4: the Newton and Euler equations \
                   of the whole system are its rate of change).",
        trait_doc: "`h_G = [k_G; p]`: the angular momentum about the centre of mass, then the \
                    linear momentum, world axes (angular first, like every spatial vector here). \
                    Internal forces leave it constant up to gravity, which changes `p` only \
                    (Wieber 2005, §5).",
    },
    /// `centroidal_momentum_matrix(q)`: `A_G` with `h_G = A_G·v`, `6 × NV`, angular rows first.
    CentroidalMomentumMatrix {
        name: "centroidal_momentum_matrix",
        trait_name: "CentroidalMomentumMatrix",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q],
        parts: [Matrix(N(6), Nv, Rows)],
        fallible: false,
        whole_body: true,
        value: "`A_G`",
        equation: "`A_G(q)`, `6 × NV`, angular rows first, with `h_G = A_G·v`: the centroidal \
                   momentum matrix (Orin, Goswami & Lee 2013).",
        trait_doc: "`A_G(q)`, `6 × NV`, angular rows first: the centroidal momentum matrix, \
                    `h_G = A_G·v` (Orin, Goswami & Lee 2013), what humanoid balance controllers \
                    use.",
    },
    /// `centroidal_momentum_rate(q, v, a)`: `ḣ_G = A_G·a + Ȧ_G·v`, laid out as `h_G`.
    CentroidalMomentumRate {
        name: "centroidal_momentum_rate",
        trait_name: "CentroidalMomentumRate",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V, A],
        parts: [Vector(N(6))],
        fallible: false,
        whole_body: true,
        value: "`ḣ_G`",
        equation: "`ḣ_G = [k̇_G; ṗ] = A_G·a + Ȧ_G·v`: the rate of the centroidal momentum at \
                   `(q, v, a)`, laid out as `centroidal_momentum` (angular about the centre of \
                   mass first, world axes), without gravity: the bodies' net forces of \
                   Newton–Euler summed to the centre of mass.",
        trait_doc: "`ḣ_G = [k̇_G; ṗ] = A_G·a + Ȧ_G·v`: the rate of [`CentroidalMomentum`], same \
                    layout (angular about the centre of mass first, world axes). It is the net \
                    external wrench about the centre of mass less gravity's `[0; m·g]`: what \
                    the contact wrenches of a standing or walking robot sum to (Wieber 2005, \
                    §5). Pinocchio's `computeCentroidalMomentumTimeVariation` (`dhg`) with the \
                    halves swapped.",
    },
    /// `centroidal_momentum_drift(q, v)`: `Ȧ_G·v`, the rate at `a = 0`.
    CentroidalMomentumDrift {
        name: "centroidal_momentum_drift",
        trait_name: "CentroidalMomentumDrift",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V],
        parts: [Vector(N(6))],
        fallible: false,
        whole_body: true,
        value: "`Ȧ_G·v`",
        equation: "`Ȧ_G·v`: the drift of the centroidal momentum, its rate at `a = 0` \
                   (`centroidal_momentum_rate`), laid out as `centroidal_momentum`.",
        trait_doc: "`Ȧ_G·v`: the drift of the centroidal momentum, [`CentroidalMomentumRate`] at \
                    `a = 0`, same layout (angular first, world axes): the term a centroidal \
                    task `A_G·a = ḣ_G* − Ȧ_G·v` needs.",
    },
    /// `kinetic_energy(q, v)`: `½·vᵀ·M(q)·v`.
    KineticEnergy {
        name: "kinetic_energy",
        trait_name: "KineticEnergy",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V],
        parts: [Scalar],
        fallible: false,
        whole_body: true,
        value: "The kinetic energy",
        equation: "`½·vᵀ·M(q)·v = ½·Σ v_kᵀ·I_k·v_k`, the kinetic energy.",
        trait_doc: "`½·vᵀ·M(q)·v`: the kinetic energy.",
    },
    /// `potential_energy(q)`: `−Σ m_k·gᵀ·x_k`.
    PotentialEnergy {
        name: "potential_energy",
        trait_name: "PotentialEnergy",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q],
        parts: [Scalar],
        fallible: false,
        whole_body: true,
        value: "The potential energy",
        equation: "`−Σ m_k·gᵀ·x_k`, the potential energy of gravity, zero with every centre of \
                   mass at the world origin.",
        trait_doc: "`−Σ m_k·gᵀ·x_k`: the potential energy of gravity, zero with every centre of \
                    mass at the world origin.",
    },
    /// `coriolis_matrix(q, v)`: `N(q, q̇)` of Wieber's eq. 7, with `N·v = bias` and `Ṁ − 2N`
    /// skew-symmetric.
    CoriolisMatrix {
        name: "coriolis_matrix",
        trait_name: "CoriolisMatrix",
        group: Some(Group::WholeBody),
        default: false,
        args: [Q, V],
        parts: [Matrix(Nv, Nv, Rows)],
        fallible: false,
        whole_body: true,
        value: "`N`",
        equation: "`N(q, q̇)` of Wieber 2005, eq. 7, `NV × NV`: `N·v` is the bias and `Ṁ − 2N` \
                   is skew-symmetric; where `v = q̇` it is the matrix of the Christoffel symbols \
                   of `M`.",
        trait_doc: "`N(q, q̇)` of Wieber 2005, eq. 7, `NV × NV`: `N·v` is [`Bias`], and `Ṁ − 2N` \
                    is skew-symmetric. Where `v = q̇` (no quaternion joint) it is the matrix of \
                    the Christoffel symbols of `M`, on Euler joints too.",
    },
    /// `inverse_dynamics_derivatives(q, v, a)`: `(∂τ/∂q, ∂τ/∂v)`, `NV × NV` each, `∂/∂q` along
    /// the configuration's tangent (the body-frame increment for quaternions).
    InverseDynamicsDerivatives {
        name: "inverse_dynamics_derivatives",
        trait_name: "InverseDynamicsDerivatives",
        group: Some(Group::Derivatives),
        default: false,
        args: [Q, V, A],
        parts: [Matrix(Nv, Nv, Rows), Matrix(Nv, Nv, Rows)],
        fallible: false,
        whole_body: false,
        value: "The derivatives",
        equation: "`(∂τ/∂q, ∂τ/∂v)` of inverse dynamics at `(q, v, a)`, `NV × NV` each (`∂τ/∂a` \
                   is `M`). Column `k` of `∂τ/∂q` is the derivative along tangent coordinate `k` \
                   of the configuration, `q ⊕ δ`: `q_k + δ_k` for revolute, prismatic and \
                   Euler-angle coordinates; for a quaternion the body-frame increment \
                   `q ⊗ exp(δ/2)`, and for a free quaternion base the position moved by \
                   `R(q)·δ_lin` too (as Pinocchio takes them; \
                   `articulated::control::tangent::retract`).",
        trait_doc: "`(∂τ/∂q, ∂τ/∂v)` of [`InverseDynamics`], `NV × NV` each (`∂τ/∂a = M`); \
                    `∂/∂q` along the configuration's tangent (`q ⊕ δ`, \
                    [`crate::control::tangent::retract`]).",
    },
    /// `forward_dynamics_derivatives(q, v, tau)`: `(∂q̈/∂q, ∂q̈/∂v, M⁻¹)`, or an error where `M`
    /// is singular.
    ForwardDynamicsDerivatives {
        name: "forward_dynamics_derivatives",
        trait_name: "ForwardDynamicsDerivatives",
        group: Some(Group::Derivatives),
        default: false,
        args: [Q, V, Tau],
        parts: [
            Hidden,
            Matrix(Nv, Nv, Rows),
            Matrix(Nv, Nv, Rows),
            Matrix(Nv, Nv, Rows)
        ],
        fallible: true,
        whole_body: false,
        value: "The derivatives",
        equation: "`(∂q̈/∂q, ∂q̈/∂v, M⁻¹)` of forward dynamics at `(q, v, τ)`, `NV × NV` each \
                   (`∂q̈/∂τ = M⁻¹`), `∂/∂q` along the configuration's tangent as in \
                   `inverse_dynamics_derivatives`; an error where `M(q)` is singular.",
        trait_doc: "`(∂q̈/∂q, ∂q̈/∂v, M⁻¹)` of [`ForwardDynamics`], `NV × NV` each \
                    (`∂q̈/∂τ = M⁻¹`); `∂/∂q` along the configuration's tangent (`q ⊕ δ`, \
                    [`crate::control::tangent::retract`]).",
    },
    /// `mass_matrix_inverse(q)`: `M(q)⁻¹`, or an error where `M` is singular.
    MassMatrixInverse {
        name: "mass_matrix_inverse",
        trait_name: "MassMatrixInverse",
        group: Some(Group::Derivatives),
        default: false,
        args: [Q],
        parts: [Matrix(Nv, Nv, Rows)],
        fallible: true,
        whole_body: false,
        value: "`M⁻¹`",
        equation: "`M(q)⁻¹`; an error where `M(q)` is singular.",
        trait_doc: "`M(q)⁻¹`, or an error where `M(q)` is singular.",
    },
    /// `frame_placements(q)`: each frame's rotation and translation in the world.
    FramePlacements {
        name: "frame_placements",
        trait_name: "FramePlacements",
        group: Some(Group::Frames),
        default: false,
        args: [Q],
        parts: [Frames(Each::Placement)],
        fallible: false,
        whole_body: false,
        value: "The frames' placements",
        equation: "Each frame's placement in the world, in the order of `FRAMES`: `rotation` \
                   (`world_R_frame`: the frame's axes in world coordinates, as columns) and \
                   `translation` (its origin in the world).",
        trait_doc: "Each frame's placement in the world (`Chain::FRAMES`, in that order): the \
                    rotation `world_R_frame` and the translation of its origin (Pinocchio's \
                    `oMf` after `framesForwardKinematics`, for these frames only).",
    },
    /// `frame_velocities(q, v)`: each frame's spatial velocity `[ω; v]` in LOCAL.
    FrameVelocities {
        name: "frame_velocities",
        trait_name: "FrameVelocities",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V],
        parts: [Frames(Each::Vector(6))],
        fallible: false,
        whole_body: false,
        value: "The frames' velocities",
        equation: "Each frame's spatial velocity `[ω; v]` in LOCAL (the frame's axes, its \
                   origin's velocity), angular first: `J_local·v`.",
        trait_doc: "Each frame's spatial velocity `[ω; v]`, angular first, in LOCAL: its angular \
                    velocity and its origin's velocity, in the frame's axes (`J_local·v`; \
                    Pinocchio's `getFrameVelocity(…, LOCAL)` with the halves swapped).",
    },
    /// `frame_accelerations(q, v, a)`: each frame origin's classical acceleration `[ω̇; p̈]` in
    /// LOCAL_WORLD_ALIGNED.
    FrameAccelerations {
        name: "frame_accelerations",
        trait_name: "FrameAccelerations",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V, A],
        parts: [Frames(Each::Vector(6))],
        fallible: false,
        whole_body: false,
        value: "The frames' classical accelerations",
        equation: "Each frame's classical acceleration `[ω̇; p̈]` in LOCAL_WORLD_ALIGNED (world \
                   axes): the angular acceleration and the second derivative of the origin's \
                   position, `J_lwa·a + J̇_lwa·v`; at `a = 0`, the drift a point contact needs. \
                   Not the spatial acceleration, whose linear part lacks `ω × v`.",
        trait_doc: "Each frame's classical acceleration `[ω̇; p̈]`, world axes: `J_lwa·a + \
                    J̇_lwa·v` (Pinocchio's `getFrameClassicalAcceleration(…, \
                    LOCAL_WORLD_ALIGNED)` with the halves swapped). At `a = 0` it is the drift \
                    of a point contact. It differs from the spatial acceleration: `p̈` is the \
                    spatial linear acceleration plus `ω × v`.",
    },
    /// `frame_velocity_derivatives(q, v)`: `(∂v/∂q, ∂v/∂v)` of each frame's LOCAL velocity.
    FrameVelocityDerivatives {
        name: "frame_velocity_derivatives",
        trait_name: "FrameVelocityDerivatives",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V],
        parts: [Frames(Each::Matrices(2, 6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The derivatives of the frames' velocities",
        equation: "`(∂v_f/∂q, ∂v_f/∂v)` of each frame's LOCAL velocity `v_f = J_local·v`, \
                   `6 × NV` each (`∂v_f/∂v = J_local`), `∂/∂q` along the configuration's \
                   tangent as for `inverse_dynamics_derivatives` (Pinocchio's \
                   `getFrameVelocityDerivatives(…, LOCAL)`, halves swapped).",
        trait_doc: "`(∂v_f/∂q, ∂v_f/∂v)` of each frame's LOCAL velocity, `6 × NV` each, `∂/∂q` \
                    along the configuration's tangent: what a cost on a tool's or a foot's \
                    velocity needs in DDP and MPC.",
    },
    /// `frame_acceleration_derivatives(q, v, a)`: `(∂α/∂q, ∂α/∂v, ∂α/∂a)` of each frame's
    /// classical acceleration.
    FrameAccelerationDerivatives {
        name: "frame_acceleration_derivatives",
        trait_name: "FrameAccelerationDerivatives",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V, A],
        parts: [Frames(Each::Matrices(3, 6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The derivatives of the frames' classical accelerations",
        equation: "`(∂α/∂q, ∂α/∂v, ∂α/∂a)` of each frame's classical acceleration \
                   `α = [ω̇; p̈] = J_lwa·a + J̇_lwa·v` (world axes), `6 × NV` each (`∂α/∂a = \
                   J_lwa`), `∂/∂q` along the configuration's tangent.",
        trait_doc: "`(∂α/∂q, ∂α/∂v, ∂α/∂a)` of each frame's classical acceleration (world axes), \
                    `6 × NV` each, `∂/∂q` along the configuration's tangent: what a cost or a \
                    contact constraint on a frame's acceleration needs in DDP and MPC.",
    },
    /// `frame_jacobians_local(q)`: each frame's Jacobian in LOCAL, `6 × NV`.
    FrameJacobiansLocal {
        name: "frame_jacobians_local",
        trait_name: "FrameJacobiansLocal",
        group: Some(Group::Frames),
        default: false,
        args: [Q],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The frames' LOCAL Jacobians",
        equation: "Each frame's Jacobian in LOCAL, `6 × NV`, angular rows first: `J_local·v` is \
                   the frame's spatial velocity in its own axes at its origin.",
        trait_doc: "Each frame's Jacobian in LOCAL (its origin, its axes), `6 × NV`, angular \
                    rows first, with respect to `v` (the tangent, for quaternion joints).",
    },
    /// `frame_jacobians_world(q)`: each frame's Jacobian in WORLD, `6 × NV`.
    FrameJacobiansWorld {
        name: "frame_jacobians_world",
        trait_name: "FrameJacobiansWorld",
        group: Some(Group::Frames),
        default: false,
        args: [Q],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The frames' WORLD Jacobians",
        equation: "Each frame's Jacobian in WORLD, `6 × NV`, angular rows first: `J_world·v` is \
                   the spatial velocity of the frame's body in world axes, at the point that \
                   passes through the world's origin.",
        trait_doc: "Each frame's Jacobian in WORLD (the point at the world's origin, world \
                    axes), `6 × NV`, angular rows first, with respect to `v`.",
    },
    /// `frame_jacobians_local_world_aligned(q)`: each frame's Jacobian in LOCAL_WORLD_ALIGNED.
    FrameJacobiansLocalWorldAligned {
        name: "frame_jacobians_local_world_aligned",
        trait_name: "FrameJacobiansLocalWorldAligned",
        group: Some(Group::Frames),
        default: false,
        args: [Q],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The frames' LOCAL_WORLD_ALIGNED Jacobians",
        equation: "Each frame's Jacobian in LOCAL_WORLD_ALIGNED, `6 × NV`, angular rows first: \
                   `J_lwa·v` is `[ω; ṗ]`, the angular velocity and the origin's velocity in \
                   world axes.",
        trait_doc: "Each frame's Jacobian in LOCAL_WORLD_ALIGNED (its origin, world axes), \
                    `6 × NV`, angular rows first: what inverse kinematics and task-space control \
                    of a point use.",
    },
    /// `frame_jacobian_time_variations_local(q, v)`: `J̇` of each frame's LOCAL Jacobian.
    FrameJacobianTimeVariationsLocal {
        name: "frame_jacobian_time_variations_local",
        trait_name: "FrameJacobianTimeVariationsLocal",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The rates of the frames' LOCAL Jacobians",
        equation: "`J̇_local = d/dt J_local(q)` at velocity `v`, `6 × NV` per frame: \
                   `J_local·a + J̇_local·v` is the frame's spatial acceleration in its axes, and \
                   `J̇_local·v` the drift of a six-dimensional contact.",
        trait_doc: "`J̇_local`, the time derivative of each frame's LOCAL Jacobian at velocity \
                    `v`, `6 × NV`: `J̇_local·v` is the spatial drift a six-dimensional contact \
                    needs.",
    },
    /// `frame_jacobian_time_variations_world(q, v)`: `J̇` of each frame's WORLD Jacobian.
    FrameJacobianTimeVariationsWorld {
        name: "frame_jacobian_time_variations_world",
        trait_name: "FrameJacobianTimeVariationsWorld",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The rates of the frames' WORLD Jacobians",
        equation: "`J̇_world = d/dt J_world(q)` at velocity `v`, `6 × NV` per frame.",
        trait_doc: "`J̇_world`, the time derivative of each frame's WORLD Jacobian at velocity \
                    `v`, `6 × NV`.",
    },
    /// `frame_jacobian_time_variations_local_world_aligned(q, v)`: `J̇` of each frame's
    /// LOCAL_WORLD_ALIGNED Jacobian.
    FrameJacobianTimeVariationsLocalWorldAligned {
        name: "frame_jacobian_time_variations_local_world_aligned",
        trait_name: "FrameJacobianTimeVariationsLocalWorldAligned",
        group: Some(Group::Frames),
        default: false,
        args: [Q, V],
        parts: [Frames(Each::Matrix(6, Nv, Rows))],
        fallible: false,
        whole_body: false,
        value: "The rates of the frames' LOCAL_WORLD_ALIGNED Jacobians",
        equation: "`J̇_lwa = d/dt J_lwa(q)` at velocity `v`, `6 × NV` per frame: `J̇_lwa·v` is \
                   the classical drift `[ω̇; p̈]` at `a = 0` (`frame_accelerations`).",
        trait_doc: "`J̇_lwa`, the time derivative of each frame's LOCAL_WORLD_ALIGNED Jacobian at \
                    velocity `v`, `6 × NV`: `J̇_lwa·v` is a point contact's drift.",
    },
}

/// How many outputs there are.
const COUNT: usize = SPECS.len();

/// How many outputs are generated by default.
const DEFAULTS: usize = {
    let (mut n, mut k) = (0, 0);
    while k < COUNT {
        if SPECS[k].default {
            n += 1;
        }
        k += 1;
    }
    n
};

impl Output {
    /// Every output, with its name in the grammar, in the order the generator emits them.
    pub const ALL: [(Output, &'static str); COUNT] = {
        let mut all = [(Output::MassMatrix, ""); COUNT];
        let mut k = 0;
        while k < COUNT {
            all[k] = (SPECS[k].output, SPECS[k].name);
            k += 1;
        }
        all
    };

    /// The outputs generated when a description names none.
    pub const DEFAULT: [Output; DEFAULTS] = {
        let mut out = [Output::MassMatrix; DEFAULTS];
        let (mut n, mut k) = (0, 0);
        while k < COUNT {
            if SPECS[k].default {
                out[n] = SPECS[k].output;
                n += 1;
            }
            k += 1;
        }
        out
    };

    /// Its description.
    pub fn spec(self) -> &'static Spec {
        &SPECS[self as usize]
    }

    /// Whether its function writes `M` into a kept matrix argument (`kept`) and returns nothing:
    /// `mass_matrix_update` and `mass_matrix_lower`.
    pub fn is_kept(self) -> bool {
        matches!(self.spec().parts, [Part::Kept { .. }])
    }

    /// Its name in the grammar: the generated function's name.
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// Whether it is a quantity of the whole system (centre of mass, momenta, energies, the
    /// Coriolis matrix; `reference::centroidal`) rather than one of the dynamics' terms.
    pub fn whole_body(self) -> bool {
        self.spec().whole_body
    }

    /// The output of that name.
    pub fn from_name(name: &str) -> Option<Output> {
        SPECS.iter().find(|s| s.name == name).map(|s| s.output)
    }

    /// What a name in `outputs:` stands for: one output, or every output of a [`Group`].
    pub fn named(name: &str) -> Option<Vec<Output>> {
        match (Output::from_name(name), Group::from_name(name)) {
            (Some(output), _) => Some(vec![output]),
            (None, Some(group)) => Some(group.outputs().collect()),
            (None, None) => None,
        }
    }
}

/// The words a signature is written in: the scalar, the sizes and the crate that defines the
/// traits, as tokens (concrete in a generated impl, generic in a runtime trait or a stand-in).
pub struct Types {
    /// The scalar: `f64`, `f32`, `T`.
    pub scalar: TokenStream,
    /// `NQ`.
    pub nq: TokenStream,
    /// `NV`.
    pub nv: TokenStream,
    /// `NB`.
    pub nb: TokenStream,
    /// `NF`.
    pub nf: TokenStream,
    /// The runtime crate: `::articulated`, or `crate` inside it.
    pub krate: TokenStream,
}

impl Types {
    /// A size as tokens.
    fn dim(&self, d: Dim) -> TokenStream {
        match d {
            Dim::Nv => self.nv.clone(),
            Dim::Nb => self.nb.clone(),
            Dim::Nf => self.nf.clone(),
            Dim::N(n) => {
                let n = Literal::usize_unsuffixed(n);
                quote!(#n)
            }
        }
    }

    /// `SVector<T, n>`.
    pub fn vector(&self, n: &TokenStream) -> TokenStream {
        let (k, t) = (&self.krate, &self.scalar);
        quote!(#k::nalgebra::SVector<#t, #n>)
    }

    /// `SMatrix<T, r, c>`.
    fn matrix(&self, r: &TokenStream, c: &TokenStream) -> TokenStream {
        let (k, t) = (&self.krate, &self.scalar);
        quote!(#k::nalgebra::SMatrix<#t, #r, #c>)
    }
}

impl Spec {
    /// Whether its type needs `NB`, the number of joints.
    pub fn uses_nb(&self) -> bool {
        self.parts
            .iter()
            .any(|p| matches!(p, Part::Matrix(Dim::Nb, _, _) | Part::Matrix(_, Dim::Nb, _)))
    }

    /// Whether it is computed for the frames (`NF` in its type).
    pub fn uses_nf(&self) -> bool {
        self.parts.iter().any(|p| matches!(p, Part::Frames(_)))
    }

    /// The trait, with its scalar and sizes: `MassMatrix<T, NQ, NV>`, `JointWrenches<T, NQ, NV,
    /// NB>`, `FramePlacements<T, NQ, NV, NF>`.
    pub fn trait_path(&self, t: &Types) -> TokenStream {
        let (k, scalar, nq, nv) = (&t.krate, &t.scalar, &t.nq, &t.nv);
        let name = Ident::new(self.trait_name, Span::call_site());
        if self.uses_nb() {
            let nb = &t.nb;
            quote!(#k::#name<#scalar, #nq, #nv, #nb>)
        } else if self.uses_nf() {
            let nf = &t.nf;
            quote!(#k::#name<#scalar, #nq, #nv, #nf>)
        } else {
            quote!(#k::#name<#scalar, #nq, #nv>)
        }
    }

    /// The type of an argument.
    pub fn arg_type(&self, arg: Arg, t: &Types) -> TokenStream {
        match arg {
            Arg::Q => t.vector(&t.nq),
            Arg::V | Arg::A | Arg::Tau => t.vector(&t.nv),
            Arg::Base => t.vector(&quote!(6)),
        }
    }

    /// The `kept` argument of an output written into a kept matrix: `kept: &mut …`.
    pub fn kept_arg(&self, t: &Types) -> Option<TokenStream> {
        self.kept_type(t).map(|ty| quote!(kept: #ty))
    }

    /// The type of the `kept` argument, typed by the chain (`Self`).
    pub fn kept_type(&self, t: &Types) -> Option<TokenStream> {
        let lower = match self.parts {
            [Part::Kept { lower }] => *lower,
            _ => return None,
        };
        let (k, scalar, nv) = (&t.krate, &t.scalar, &t.nv);
        let ty = if lower {
            quote!(KeptMassMatrixLower)
        } else {
            quote!(KeptMassMatrix)
        };
        Some(quote!(&mut #k::#ty<Self, #scalar, #nv>))
    }

    /// The type of one returned part.
    fn part_type(part: Part, t: &Types) -> Option<TokenStream> {
        match part {
            Part::Scalar => Some(t.scalar.clone()),
            Part::Vector(d) => Some(t.vector(&t.dim(d))),
            Part::Matrix(r, c, _) => Some(t.matrix(&t.dim(r), &t.dim(c))),
            Part::Hidden | Part::Kept { .. } => None,
            Part::Frames(each) => {
                let one = match each {
                    Each::Placement => {
                        let (k, scalar) = (&t.krate, &t.scalar);
                        quote!(#k::FramePlacement<#scalar>)
                    }
                    Each::Vector(n) => t.vector(&t.dim(Dim::N(n))),
                    Each::Matrix(r, c, _) => t.matrix(&t.dim(Dim::N(r)), &t.dim(c)),
                    Each::Matrices(n, r, c, _) => {
                        let m = t.matrix(&t.dim(Dim::N(r)), &t.dim(c));
                        let all = std::iter::repeat_n(m, n);
                        quote!((#(#all),*))
                    }
                };
                let nf = &t.nf;
                Some(quote!([#one; #nf]))
            }
        }
    }

    /// `-> R` (a `Result` where it is fallible), or nothing for an output written into `kept`.
    pub fn ret(&self, t: &Types) -> TokenStream {
        match self.result_type(t) {
            Some(ty) => quote!(-> #ty),
            None => TokenStream::new(),
        }
    }

    /// What the function returns without its `Result` (`None`: nothing, the kept outputs).
    pub fn value_type(&self, t: &Types) -> Option<TokenStream> {
        let parts: Vec<TokenStream> = self
            .parts
            .iter()
            .filter_map(|&p| Self::part_type(p, t))
            .collect();
        match &parts[..] {
            [] => None,
            [one] => Some(one.clone()),
            many => Some(quote!((#(#many),*))),
        }
    }

    /// What the function returns: [`Spec::value_type`], in a `Result` where it is fallible.
    pub fn result_type(&self, t: &Types) -> Option<TokenStream> {
        let value = self.value_type(t)?;
        let k = &t.krate;
        Some(if self.fallible {
            quote!(::core::result::Result<#value, #k::SingularMassMatrix>)
        } else {
            value
        })
    }

    /// The batch twin's name, `mass_matrix_batch`, and with the parameters,
    /// `mass_matrix_batch_with`.
    pub fn batch_names(&self) -> (Ident, Ident) {
        (
            format_ident!("{}_batch", self.name),
            format_ident!("{}_batch_with", self.name),
        )
    }

    /// The batch twin with parameters per state, `mass_matrix_batch_with_each`: the one
    /// generated code with lanes implements.
    pub fn batch_each_name(&self) -> Ident {
        format_ident!("{}_batch_with_each", self.name)
    }

    /// The batch twin's slice of results: the results, or for a kept output the kept matrices.
    pub fn batch_out_type(&self, t: &Types) -> TokenStream {
        let (k, scalar, nv) = (&t.krate, &t.scalar, &t.nv);
        match (self.result_type(t), self.parts) {
            (Some(ty), _) => ty,
            (None, [Part::Kept { lower: true }]) => {
                quote!(#k::KeptMassMatrixLower<Self, #scalar, #nv>)
            }
            (None, _) => quote!(#k::KeptMassMatrix<Self, #scalar, #nv>),
        }
    }

    /// The method with the parameters, `mass_matrix_with`.
    pub fn with_name(&self) -> Ident {
        format_ident!("{}_with", self.name)
    }
}

/// The runtime's traits, one per output, with their docs: what `articulated_macros::
/// __output_traits!()` expands to inside the `articulated` crate. Each has the method with the
/// parameters (`mass_matrix_with(q, p)`), which the generated code implements, and the method
/// with the defaults (`mass_matrix(q)`).
pub fn runtime_traits() -> TokenStream {
    let t = Types {
        scalar: quote!(T),
        nq: quote!(NQ),
        nv: quote!(NV),
        nb: quote!(NB),
        nf: quote!(NF),
        krate: quote!(crate),
    };
    let traits = SPECS.iter().map(|s| {
        let name = Ident::new(s.trait_name, Span::call_site());
        let generics = if s.uses_nb() {
            quote!(<T, const NQ: usize, const NV: usize, const NB: usize>)
        } else if s.uses_nf() {
            quote!(<T, const NQ: usize, const NV: usize, const NF: usize>)
        } else {
            quote!(<T, const NQ: usize, const NV: usize>)
        };
        let trait_doc = s.trait_doc.split('\n').map(|l| format!(" {l}"));
        let one = one_state_methods(s, &t);
        let batch = batch_methods(s, &t);
        // Kept outputs fill the caller's matrices in place: no threads over them.
        let par = (s.kept_arg(&t).is_none()).then(|| par_batch_methods(s, &t));
        quote! {
            #(#[doc = #trait_doc])*
            pub trait #name #generics: crate::Chain<T> {
                #one
                #batch
                #par
            }
        }
    });
    // A trait per group whose outputs need no `NB`, and one for the default outputs, each with
    // a blanket impl: the bounds a test or a benchmark over many chains writes once.
    let bundles: Vec<(String, Ident, Vec<&Spec>)> = Group::ALL
        .iter()
        .map(|&(g, name)| {
            let members = SPECS.iter().filter(|s| s.group == Some(g)).collect();
            (
                format!("every output of the group `{name}`"),
                g.trait_name(),
                members,
            )
        })
        .chain(std::iter::once((
            "the outputs generated when a description names none".to_string(),
            "DefaultOutputs",
            SPECS.iter().filter(|s| s.default).collect(),
        )))
        .filter(|(_, _, members): &(String, &str, Vec<&Spec>)| {
            members.iter().all(|s| !s.uses_nb() && !s.uses_nf())
        })
        .map(|(what, name, members)| (what, Ident::new(name, Span::call_site()), members))
        .collect();
    let groups = bundles.iter().map(|(what, name, members)| {
        let bounds: Vec<TokenStream> = members.iter().map(|s| s.trait_path(&t)).collect();
        let doc = format!(" A chain in `T` with {what}: one bound for all of them.");
        quote! {
            #[doc = #doc]
            pub trait #name<T, const NQ: usize, const NV: usize>: #(#bounds)+* {}
            impl<C, T, const NQ: usize, const NV: usize> #name<T, NQ, NV> for C where
                C: #(#bounds)+*
            {
            }
        }
    });
    let names = SPECS
        .iter()
        .map(|s| Ident::new(s.trait_name, Span::call_site()))
        .chain(bundles.iter().map(|(_, name, _)| name.clone()));
    quote! {
        #(#traits)*
        #(#groups)*
        /// Every output's trait and every group's, for the prelude (`articulated::prelude`).
        #[doc(hidden)]
        pub mod output_traits {
            pub use super::{#(#names),*};
        }
    }
}

/// An output's arguments in a trait's signatures: their names (`q`, `v`), their types for one
/// state, and the names as strings (for [`crate::lanes::BatchLengths`]'s message).
struct Arguments {
    idents: Vec<Ident>,
    types: Vec<TokenStream>,
    names: Vec<&'static str>,
}

impl Arguments {
    fn of(s: &Spec, t: &Types) -> Self {
        Arguments {
            idents: s
                .args
                .iter()
                .map(|a| format_ident!("{}", a.name()))
                .collect(),
            types: s.args.iter().map(|&a| s.arg_type(a, t)).collect(),
            names: s.args.iter().map(|a| a.name()).collect(),
        }
    }

    /// `out.iter_mut().zip(q).zip(v)` (from `start`, the iterator over `out`) and its pattern
    /// `((out, q), v)`; `each` maps an argument to what is zipped (`q`, `q.par_chunks(chunk)`).
    fn zipped(
        &self,
        start: TokenStream,
        each: impl Fn(&Ident) -> TokenStream,
    ) -> (TokenStream, TokenStream) {
        self.idents.iter().fold((start, quote!(out)), |(z, p), a| {
            let e = each(a);
            (quote!(#z.zip(#e)), quote!((#p, #a)))
        })
    }
}

/// The method for one state with the parameters (`mass_matrix_with(q, p)`), which generated
/// code implements, and the one with the defaults (`mass_matrix(q)`).
fn one_state_methods(s: &Spec, t: &Types) -> TokenStream {
    let Arguments { idents, types, .. } = Arguments::of(s, t);
    let kept = s.kept_arg(t).map(|k| quote!(, #k));
    let kept_name = kept.as_ref().map(|_| quote!(, kept));
    let into = if kept.is_some() { ", into `kept`" } else { "" };
    let ret = s.ret(t);
    let (with, plain) = (s.with_name(), format_ident!("{}", s.name));
    let errors = s.fallible.then(|| {
        quote! {
            #[doc = ""]
            #[doc = " # Errors"]
            #[doc = " [`SingularMassMatrix`](crate::SingularMassMatrix) where `M(q)` is singular or the result is not finite."]
        }
    });
    let doc_with = format!(" {} for the parameters `p`{into}.", s.value);
    let doc_plain = format!(" {} with the default parameters{into}.", s.value);
    quote! {
        #[doc = #doc_with]
        #errors
        #[allow(clippy::type_complexity)]
        fn #with(#(#idents: &#types,)* p: &Self::Params #kept) #ret;
        #[doc = #doc_plain]
        #errors
        #[allow(clippy::type_complexity)]
        fn #plain(#(#idents: &#types),* #kept) #ret {
            Self::#with(#(#idents,)* &Self::default_params() #kept_name)
        }
    }
}

/// The `# Errors` section of a batch method.
fn batch_errors(s: &Spec) -> TokenStream {
    let text = format!(
        " [`BatchLengths`](crate::lanes::BatchLengths) where an argument's length is not \
         `out`'s, or `p` holds neither one parameter set nor one per state (nothing is \
         computed).{}",
        if s.fallible {
            " A singular state's entry is its `Err`, its neighbours' their values."
        } else {
            ""
        }
    );
    quote! {
        #[doc = ""]
        #[doc = " # Errors"]
        #[doc = #text]
    }
}

/// The batch twins: `_batch_with_each` (the parameters per state, or one set for all), which
/// generated code with lanes overrides, and `_batch_with` and `_batch` through it.
fn batch_methods(s: &Spec, t: &Types) -> TokenStream {
    let args = Arguments::of(s, t);
    let Arguments {
        idents,
        types,
        names,
    } = &args;
    let (batch, batch_with) = s.batch_names();
    let each = s.batch_each_name();
    let out_ty = s.batch_out_type(t);
    let with = s.with_name();
    // `out.iter_mut().enumerate().zip(q).zip(v)` and its pattern `(((i, out), q), v)`.
    let (zipped, pattern) = idents.iter().fold(
        (quote!(out.iter_mut().enumerate()), quote!((i, out))),
        |(z, p), a| (quote!(#z.zip(#a)), quote!((#p, #a))),
    );
    let call = if s.kept_arg(t).is_some() {
        quote!(Self::#with(#(#idents,)* p, out);)
    } else {
        quote!(*out = Self::#with(#(#idents,)* p);)
    };
    let what = if s.kept_arg(t).is_some() {
        "kept matrices"
    } else {
        "results"
    };
    let doc_each = format!(
        " {} at every state, state `i` with the parameters `p[i]` (or `p[0]` for all where `p` \
         holds one set): `out[i]` for the `i`-th entry of each argument. Where the chain asks \
         for lanes (`lanes: N`), `N` states at a time in one pass of the generated code \
         (`articulated::lanes`), each lane with its own parameters; otherwise state by state. \
         Each state's {what} are the same as one call's with its parameters.",
        s.value
    );
    let doc_with =
        format!(" [`{each}`](Self::{each}) with the same parameters `p` for every state.");
    let doc_batch = format!(" {} at every state, with the default parameters.", s.value);
    let errors = batch_errors(s);
    quote! {
        #[doc = #doc_each]
        #errors
        #[allow(clippy::type_complexity)]
        fn #each(
            #(#idents: &[#types],)*
            p: &[Self::Params],
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths> {
            crate::lanes::check_batch(out.len(), &[#((#names, #idents.len())),*], p.len())?;
            for #pattern in #zipped {
                let p = crate::lanes::params_of(p, i);
                #call
            }
            Ok(())
        }
        #[doc = #doc_with]
        #errors
        #[allow(clippy::type_complexity)]
        fn #batch_with(
            #(#idents: &[#types],)*
            p: &Self::Params,
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths> {
            Self::#each(#(#idents,)* ::core::slice::from_ref(p), out)
        }
        #[doc = #doc_batch]
        #errors
        #[allow(clippy::type_complexity)]
        fn #batch(
            #(#idents: &[#types],)*
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths> {
            Self::#batch_with(#(#idents,)* &Self::default_params(), out)
        }
    }
}

/// The batch twins spread over threads (runtime feature `rayon`): `_par_batch_with_each`, and
/// `_par_batch_with` and `_par_batch` through it.
fn par_batch_methods(s: &Spec, t: &Types) -> TokenStream {
    let args = Arguments::of(s, t);
    let Arguments {
        idents,
        types,
        names,
    } = &args;
    let each = s.batch_each_name();
    let out_ty = s.batch_out_type(t);
    let par_each = format_ident!("{}_par_batch_with_each", s.name);
    let par_with = format_ident!("{}_par_batch_with", s.name);
    let par_plain = format_ident!("{}_par_batch", s.name);
    let doc_par_each = format!(
        " [`{each}`](Self::{each}) spread over threads (rayon's current pool), in groups of \
         states ([`par_chunk`](crate::lanes::par_chunk)). Each state's result is computed in \
         its own lane, whatever its group: the results are the same whatever the number of \
         threads."
    );
    let doc_par_with =
        format!(" [`{par_each}`](Self::{par_each}) with the same parameters `p` for every state.");
    let doc_par = format!(" [`{par_with}`](Self::{par_with}) with the default parameters.");
    let errors = batch_errors(s);
    // `((out, q), v)` over `par_chunks` of every slice, numbered.
    let (zipped, pattern) = args.zipped(
        quote!(out.par_chunks_mut(chunk)),
        |a| quote!(#a.par_chunks(chunk)),
    );
    quote! {
        #[cfg(feature = "rayon")]
        #[doc = #doc_par_each]
        #errors
        #[allow(clippy::type_complexity)]
        fn #par_each(
            #(#idents: &[#types],)*
            p: &[Self::Params],
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths>
        where
            T: Send + Sync,
            Self::Params: Sync,
        {
            use rayon::prelude::*;
            crate::lanes::check_batch(out.len(), &[#((#names, #idents.len())),*], p.len())?;
            let chunk = crate::lanes::par_chunk(out.len());
            let n = out.len();
            #zipped.enumerate().for_each(|(k, #pattern)| {
                let p = crate::lanes::params_chunk(p, n, k * chunk, out.len());
                // The lengths agree chunk by chunk, as they did whole.
                let _ = Self::#each(#(#idents,)* p, out);
            });
            Ok(())
        }
        #[cfg(feature = "rayon")]
        #[doc = #doc_par_with]
        #errors
        #[allow(clippy::type_complexity)]
        fn #par_with(
            #(#idents: &[#types],)*
            p: &Self::Params,
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths>
        where
            T: Send + Sync,
            Self::Params: Sync,
        {
            Self::#par_each(#(#idents,)* ::core::slice::from_ref(p), out)
        }
        #[cfg(feature = "rayon")]
        #[doc = #doc_par]
        #errors
        #[allow(clippy::type_complexity)]
        fn #par_plain(
            #(#idents: &[#types],)*
            out: &mut [#out_ty],
        ) -> ::core::result::Result<(), crate::lanes::BatchLengths>
        where
            T: Send + Sync,
            Self::Params: Sync,
        {
            Self::#par_with(#(#idents,)* &Self::default_params(), out)
        }
    }
}
