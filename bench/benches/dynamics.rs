//! Generated code against the interpreted reference, side by side: for every shipped model and
//! every output, the group `"<model>/<output>"` holds `generated` and `reference`, both cycling
//! through the same [`STATES`] seeded states with inputs and results through `black_box`.
//!
//! The reference is called through its `&[f64]` API, which checks the inputs and allocates its
//! result (`DMatrix`/`DVector`); criterion drops each result inside the timed loop, so the
//! allocation and the free are part of its figure. `Reference::forward_dynamics` also checks
//! that `M` is positive definite by its eigenvalues (CRBA plus an `O(n³)` eigen-solver), so the
//! forward-dynamics groups have a third function, `reference_aba`: the bare ABA recursion.
//!
//! `cargo bench -p articulated-bench` runs all 50 functions in about three minutes on two cores;
//! `cargo bench -p articulated-bench -- arm7/` runs one model, `-- /mass_matrix` one output.

use std::time::Duration;

use articulated_bench::{each_model, Output, Visit, STATES};
use criterion::{criterion_group, criterion_main, Criterion};

/// Registers one group per (model, output) on a [`Criterion`].
struct Groups<'a>(&'a mut Criterion);

impl Visit for Groups<'_> {
    fn visit<G: FnMut(usize), R: FnMut(usize)>(
        &mut self,
        model: &'static str,
        output: Output,
        _ops: articulated::OpCounts,
        mut generated: G,
        mut reference: R,
        bare: Option<&mut dyn FnMut(usize)>,
    ) {
        let mut group = self.0.benchmark_group(format!("{model}/{}", output.name()));
        group.bench_function("generated", |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) % STATES;
                generated(i)
            })
        });
        group.bench_function("reference", |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) % STATES;
                reference(i)
            })
        });
        if let Some(bare) = bare {
            group.bench_function("reference_aba", |b| {
                let mut i = 0;
                b.iter(|| {
                    i = (i + 1) % STATES;
                    bare(i)
                })
            });
        }
        group.finish();
    }
}

fn dynamics(c: &mut Criterion) {
    each_model(&mut Groups(c));
}

/// Private, so the `pub fn benches` that `criterion_group!` writes needs no docs.
mod group {
    use super::*;

    criterion_group! {
        name = benches;
        config = Criterion::default()
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_millis(1500))
            .sample_size(30);
        targets = dynamics
    }
}
criterion_main!(group::benches);
