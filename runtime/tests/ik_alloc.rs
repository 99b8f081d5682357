//! Inverse kinematics (converged, stalled, refused) and the operational-space quantities
//! allocate nothing: counted by a global allocator that counts every allocation of the process
//! (`stats_alloc`), as in `simulate_alloc.rs`.
//!
//! One test function only: the counter is global, so a second test running on another thread
//! would be counted too.

use std::alloc::System;

use articulated::control::operational_space::{OperationalSpace, RANK_TOLERANCE};
use articulated::ik::{self, Options, Task};
use articulated::nalgebra::{SMatrix, SVector, Vector3};
use articulated::prelude::*;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

#[derive(articulated::Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    outputs = [mass_matrix, frame_placements, frame_jacobians_local_world_aligned],
    frames = [link7, link4]
)]
struct Arm7;

type Q7 = SVector<f64, 7>;

/// Allocations while `f` runs: the fewest of three runs (the harness's own thread allocates
/// now and then; an allocation in `f` shows in every run).
fn allocations(mut f: impl FnMut()) -> usize {
    (0..3)
        .map(|_| {
            let region = Region::new(GLOBAL);
            f();
            region.change().allocations
        })
        .min()
        .unwrap_or_default()
}

#[test]
fn inverse_kinematics_and_operational_space_allocate_nothing() {
    let truth = Q7::from([0.3, 0.7, -0.2, -1.2, 0.4, 0.8, 0.1]);
    let [flange, elbow] = Arm7::frame_placements(&truth);
    let options = Options::default();
    let mut stops = Vec::with_capacity(4);
    let counted = allocations(|| {
        stops.clear();
        for tasks in [
            [Task::pose(flange), Task::position(elbow.translation)],
            [Task::position(Vector3::new(3.0, 0.0, 0.36)), Task::FREE],
            [Task::position(Vector3::new(f64::NAN, 0.0, 0.0)), Task::FREE],
        ] {
            let result = ik::solve::<Arm7, 7, 7, 2>(&tasks, &Q7::zeros(), &options);
            stops.push(result.map(|s| s.iterations).map_err(|e| e.stop));
        }
    });
    assert_eq!(counted, 0, "inverse kinematics allocated");
    assert!(
        stops[0].is_ok() && stops[1].is_err() && stops[2].is_err(),
        "{stops:?}"
    );

    let m = Arm7::mass_matrix(&truth);
    let [j, _] = Arm7::frame_jacobians_local_world_aligned(&truth);
    let position: SMatrix<f64, 3, 7> = j.fixed_rows::<3>(3).into_owned();
    let mut checksum = 0.0;
    let counted = allocations(|| {
        for tolerance in [RANK_TOLERANCE, 1.0] {
            if let Ok(os) = OperationalSpace::from_mass_matrix(&m, &j, tolerance) {
                checksum += os.project_torque(&j, &Q7::repeat(1.0)).sum();
            }
            if let Ok(os) = OperationalSpace::from_mass_matrix(&m, &position, tolerance) {
                checksum += os.null_space_projector(&position).sum();
            }
        }
    });
    assert_eq!(counted, 0, "the operational-space quantities allocated");
    assert!(checksum.is_finite());
}
