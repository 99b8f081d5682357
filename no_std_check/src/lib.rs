//! A `#![no_std]` staticlib with no allocator that builds generated chains and calls every
//! output: `cargo build --manifest-path no_std_check/Cargo.toml` (run by `.ci/run`).
//!
//! What makes it a check: a staticlib is linked, so every lang item must be resolved here.
//! If `articulated` (without default features) or the generated code pulled in `std`, its
//! `panic_impl` would clash with the `#[panic_handler]` below (E0152, duplicate lang item); if
//! they pulled in `alloc`, the link would need a `#[global_allocator]`, and there is none.
#![no_std]

use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;

articulated::chain! {
    /// Hemami's two-link system (`models/two_link.chain`).
    pub chain TwoLink {
        gravity: [0.0, 0.0, -9.81];
        body legs { mass: 22.0, com: [0.0, 0.0, 0.54], inertia: diag(1.46, 1.29, 0.24) }
        body trunk { mass: 50.9, com: [0.0, 0.0, 0.32], inertia: diag(3.2, 2.8, 0.7) }
        joint ankle: spherical(xyz) { parent: world, child: legs }
        joint hip: spherical(xyz) { parent: legs, child: trunk, xyz: [0.0, 0.0, 0.86] }
    }
}

/// The 7-DOF arm from its URDF, with batch functions in lanes of four states
/// (`articulated::lanes`: `wide`'s vectors, no `std` either).
#[derive(articulated::Chain)]
#[chain(urdf = "../models/arm7.urdf", lanes = 4)]
pub struct Arm7;

/// `q̈` of eight arm states, in two groups of four lanes. Returns 0 on success, 1 + the first
/// state where `M(q)` is singular.
#[no_mangle]
pub extern "C" fn arm7_forward_dynamics_batch(
    q: &[SVector<f64, 7>; 8],
    v: &[SVector<f64, 7>; 8],
    tau: &[SVector<f64, 7>; 8],
    out: &mut [SVector<f64, 7>; 8],
) -> i32 {
    let mut results = [Ok(SVector::zeros()); 8];
    if Arm7::forward_dynamics_batch(q, v, tau, &mut results).is_err() {
        return -1;
    }
    for (i, (r, o)) in results.iter().zip(out.iter_mut()).enumerate() {
        match r {
            Ok(qdd) => *o = *qdd,
            Err(_) => return 1 + i as i32,
        }
    }
    0
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}

/// Writes a vector to a C array of its length.
fn write<const N: usize>(x: &SVector<f64, N>, out: &mut [f64; N]) {
    out.copy_from_slice(x.as_slice());
}

/// Writes a matrix, column-major (symmetric here, so also row-major).
fn write_m<const N: usize, const NN: usize>(m: &SMatrix<f64, N, N>, out: &mut [f64; NN]) {
    out.copy_from_slice(m.as_slice());
}

macro_rules! exports {
    ($chain:ty, $n:literal, $nn:literal, $m:ident, $b:ident, $g:ident, $id:ident, $fd:ident) => {
        /// `M(q)`, column-major.
        #[no_mangle]
        pub extern "C" fn $m(q: &[f64; $n], out: &mut [f64; $nn]) {
            write_m(&<$chain>::mass_matrix(&SVector::from(*q)), out);
        }
        /// `N(q, q̇)·q̇`.
        #[no_mangle]
        pub extern "C" fn $b(q: &[f64; $n], v: &[f64; $n], out: &mut [f64; $n]) {
            write(&<$chain>::bias(&SVector::from(*q), &SVector::from(*v)), out);
        }
        /// `g(q)`.
        #[no_mangle]
        pub extern "C" fn $g(q: &[f64; $n], out: &mut [f64; $n]) {
            write(&<$chain>::gravity(&SVector::from(*q)), out);
        }
        /// `τ = M·a + bias + gravity`.
        #[no_mangle]
        pub extern "C" fn $id(q: &[f64; $n], v: &[f64; $n], a: &[f64; $n], out: &mut [f64; $n]) {
            let tau = <$chain>::inverse_dynamics(
                &SVector::from(*q),
                &SVector::from(*v),
                &SVector::from(*a),
            );
            write(&tau, out);
        }
        /// `q̈`; returns 0 on success, 1 + the failing velocity index where `M(q)` is singular.
        #[no_mangle]
        pub extern "C" fn $fd(
            q: &[f64; $n],
            v: &[f64; $n],
            tau: &[f64; $n],
            out: &mut [f64; $n],
        ) -> i32 {
            match <$chain>::forward_dynamics(
                &SVector::from(*q),
                &SVector::from(*v),
                &SVector::from(*tau),
            ) {
                Ok(qdd) => {
                    write(&qdd, out);
                    0
                }
                Err(e) => 1 + e.velocity as i32,
            }
        }
    };
}

exports!(
    TwoLink,
    6,
    36,
    two_link_mass_matrix,
    two_link_bias,
    two_link_gravity,
    two_link_inverse_dynamics,
    two_link_forward_dynamics
);
exports!(
    Arm7,
    7,
    49,
    arm7_mass_matrix,
    arm7_bias,
    arm7_gravity,
    arm7_inverse_dynamics,
    arm7_forward_dynamics
);

articulated::chain! {
    /// A free-floating two-body chain with every quantity of the whole system.
    pub chain Floater {
        gravity: [0.0, 0.0, -9.81];
        outputs: [
            center_of_mass, center_of_mass_velocity, center_of_mass_jacobian, centroidal_momentum,
            centroidal_momentum_matrix, kinetic_energy, potential_energy, coriolis_matrix
        ];
        body trunk { mass: 10.0, com: [0.0, 0.0, 0.2], inertia: diag(0.3, 0.3, 0.1) }
        body arm { mass: 2.0, com: [0.0, 0.0, -0.2], inertia: diag(0.02, 0.02, 0.005) }
        joint base: free(quaternion) { parent: world, child: trunk }
        joint shoulder: spherical(zyx) { parent: trunk, child: arm, xyz: [0.0, 0.2, 0.4] }
    }
}

/// Every quantity of the whole system of `Floater` at `(q, v)`: the centre of mass, its velocity,
/// the centroidal momentum (6), the kinetic and potential energy, then the column sums of the
/// centre of mass Jacobian (9), the centroidal momentum matrix (9) and the Coriolis matrix (9).
#[no_mangle]
pub extern "C" fn floater_whole_body(q: &[f64; 10], v: &[f64; 9], out: &mut [f64; 41]) {
    let (q, v) = (SVector::from(*q), SVector::from(*v));
    let com = Floater::center_of_mass(&q);
    let com_v = Floater::center_of_mass_velocity(&q, &v);
    let h = Floater::centroidal_momentum(&q, &v);
    let sums = [
        Floater::center_of_mass_jacobian(&q).row_sum_tr(),
        Floater::centroidal_momentum_matrix(&q)
            .row_sum_tr()
            .fixed_rows::<9>(0)
            .into_owned(),
    ];
    let coriolis = Floater::coriolis_matrix(&q, &v).row_sum_tr();
    let scalars = [
        Floater::kinetic_energy(&q, &v),
        Floater::potential_energy(&q),
    ];
    let values = com
        .iter()
        .chain(com_v.iter())
        .chain(h.iter())
        .chain(scalars.iter())
        .chain(sums[0].iter())
        .chain(sums[1].iter())
        .chain(coriolis.iter());
    for (o, x) in out.iter_mut().zip(values) {
        *o = *x;
    }
}

articulated::chain! {
    /// A quaternion ball joint on a slider, with the derivatives of the dynamics.
    pub chain Linearized {
        gravity: [0.0, 0.0, -9.81];
        outputs: [inverse_dynamics_derivatives, forward_dynamics_derivatives, mass_matrix_inverse];
        body carriage { mass: 3.0, com: [0.1, 0.0, 0.05], inertia: diag(0.02, 0.03, 0.04) }
        body pole { mass: 1.0, com: [0.0, 0.0, 0.5], inertia: diag(0.08, 0.08, 0.002) }
        joint slide: prismatic(x) { parent: world, child: carriage }
        joint ball: spherical(quaternion) { parent: carriage, child: pole }
    }
}

/// `∂τ/∂q`, `∂τ/∂v`, `∂q̈/∂q`, `∂q̈/∂v` and `M⁻¹` of `Linearized` (4 × 4 each, column-major,
/// one after the other) at `(q, v, a)`, with `τ = a` for forward dynamics; returns 0 on
/// success, 1 + the failing velocity index where `M(q)` is singular.
#[no_mangle]
pub extern "C" fn linearized_derivatives(
    q: &[f64; 5],
    v: &[f64; 4],
    a: &[f64; 4],
    out: &mut [f64; 80],
) -> i32 {
    let (q, v, a) = (SVector::from(*q), SVector::from(*v), SVector::from(*a));
    let (dq, dv) = Linearized::inverse_dynamics_derivatives(&q, &v, &a);
    let (fq, fv, minv) = match Linearized::forward_dynamics_derivatives(&q, &v, &a) {
        Ok(d) => d,
        Err(e) => return 1 + e.velocity as i32,
    };
    if let Err(e) = Linearized::mass_matrix_inverse(&q) {
        return 1 + e.velocity as i32;
    }
    for (chunk, m) in out.chunks_mut(16).zip([dq, dv, fq, fv, minv]) {
        chunk.copy_from_slice(m.as_slice());
    }
    0
}

articulated::chain! {
    /// A tool frame on an arm with a quaternion shoulder: every frame output, and what the
    /// constrained dynamics need.
    pub chain Tooled {
        gravity: [0.0, 0.0, -9.81];
        outputs: [frames, mass_matrix_and_nonlinear_effects];
        frames: [tool, fore];
        body upper { mass: 1.0, com: [0.0, 0.0, -0.3], inertia: diag(0.01, 0.01, 0.001) }
        body fore { mass: 0.5, com: [0.0, 0.0, -0.2], inertia: diag(0.005, 0.005, 0.001) }
        joint shoulder: spherical(quaternion) { parent: world, child: upper }
        joint elbow: revolute(y) { parent: upper, child: fore, xyz: [0.0, 0.0, -0.6] }
        frame tool { parent: fore, xyz: [0.0, 0.1, -0.4], rpy: [0.3, 0.0, 0.2] }
    }
}

/// The tool frame of `Tooled` at `(q, v, a)`: its translation (3), rotation (9, column-major),
/// LOCAL velocity (6), classical acceleration (6), then the column sums of its Jacobians
/// (LOCAL, WORLD, LOCAL_WORLD_ALIGNED, 4 each) and their time variations (4 each), and of the
/// derivatives of its velocity (2 × 4) and acceleration (3 × 4).
#[no_mangle]
pub extern "C" fn tooled_frames(q: &[f64; 5], v: &[f64; 4], a: &[f64; 4], out: &mut [f64; 68]) {
    let (q, v, a) = (SVector::from(*q), SVector::from(*v), SVector::from(*a));
    let [tool, _] = Tooled::frame_placements(&q);
    let [velocity, _] = Tooled::frame_velocities(&q, &v);
    let [acceleration, _] = Tooled::frame_accelerations(&q, &v, &a);
    let jacobians = [
        Tooled::frame_jacobians_local(&q)[0],
        Tooled::frame_jacobians_world(&q)[0],
        Tooled::frame_jacobians_local_world_aligned(&q)[0],
        Tooled::frame_jacobian_time_variations_local(&q, &v)[0],
        Tooled::frame_jacobian_time_variations_world(&q, &v)[0],
        Tooled::frame_jacobian_time_variations_local_world_aligned(&q, &v)[0],
    ];
    let (dv_dq, dv_dv) = Tooled::frame_velocity_derivatives(&q, &v)[0];
    let (da_dq, da_dv, da_da) = Tooled::frame_acceleration_derivatives(&q, &v, &a)[0];
    let values = tool
        .translation
        .iter()
        .chain(tool.rotation.iter())
        .chain(velocity.iter())
        .chain(acceleration.iter())
        .copied();
    let matrices = jacobians
        .into_iter()
        .chain([dv_dq, dv_dv, da_dq, da_dv, da_da]);
    let sums = matrices.flat_map(|m| {
        let s = m.row_sum_tr();
        [s[0], s[1], s[2], s[3]]
    });
    for (o, x) in out.iter_mut().zip(values.chain(sums)) {
        *o = x;
    }
}

/// One RK4 step of 1 ms of `Tooled` with its tool's point held where it starts (a point contact
/// with Baumgarte terms): the stepping path of `articulated::constraint` without an allocator.
/// Returns 0, or 1 where the constraint or the step fails.
#[no_mangle]
pub extern "C" fn tooled_held_step(q: &mut [f64; 5], v: &mut [f64; 4]) -> i32 {
    use articulated::constraint::{Baumgarte, ConstrainedChain, Contact, Settings};
    use articulated::integrate::{Integrator, Rk4, State};
    let contacts = [Contact::point(0)];
    let q0 = SVector::from(*q);
    let gains = Some(Baumgarte {
        kp: 100.0,
        kd: 20.0,
    });
    let unforced = |_: f64, _: &SVector<f64, 5>, _: &SVector<f64, 4>| SVector::<f64, 4>::zeros();
    let Ok(mut chain) = ConstrainedChain::<Tooled, _, 5, 4, 2, 3>::new(
        &q0,
        &contacts,
        &[],
        gains,
        Settings::default(),
        unforced,
    ) else {
        return 1;
    };
    let mut state = State::new(0.0, q0, SVector::from(*v));
    if Rk4.advance(&mut chain, &mut state, 1e-3, 1).is_err() {
        return 1;
    }
    q.copy_from_slice(state.q.as_slice());
    v.copy_from_slice(state.v.as_slice());
    0
}
