//! Recorded states and their CSV form.
//!
//! The CSV format (what `articulated simulate` writes and `articulated invert` reads): a header
//! row `t,q0,…,q{NQ−1},v0,…,v{NV−1}`, then one row per state, the initial state first. Numbers
//! are written with Rust's `{:?}`, the shortest decimal that reads back to the same value
//! (`"0.1"`, `"1.0"`, `"1e-7"`), so `str::parse::<f64>` recovers every bit. Rows end in `\n`.
//!
//! [`write_csv`] writes states to any [`core::fmt::Write`] (so also under `no_std`);
//! [`Trajectory`] (`alloc`) owns states, and its
//! [`write_csv`](Trajectory::write_csv) (`std`) writes to any `std::io::Write`.

use core::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, Scalar};

use crate::integrate::State;

/// Writes the header `t,q0,…,q{nq−1},v0,…,v{nv−1}` and a newline.
///
/// # Errors
/// The writer's.
pub fn write_csv_header<W: fmt::Write + ?Sized>(w: &mut W, nq: usize, nv: usize) -> fmt::Result {
    w.write_str("t")?;
    for i in 0..nq {
        write!(w, ",q{i}")?;
    }
    for i in 0..nv {
        write!(w, ",v{i}")?;
    }
    w.write_str("\n")
}

/// Writes one state as a CSV row `t,q…,v…` and a newline.
///
/// # Errors
/// The writer's.
pub fn write_csv_row<T, Q, V, W>(w: &mut W, state: &State<T, Q, V>) -> fmt::Result
where
    T: Scalar + fmt::Debug,
    Q: Dim,
    V: Dim,
    W: fmt::Write + ?Sized,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    write!(w, "{:?}", state.t)?;
    for x in state.q.iter().chain(state.v.iter()) {
        write!(w, ",{x:?}")?;
    }
    w.write_str("\n")
}

/// Writes the header (sizes from the first state, or `nq`, `nv` when there is none) and one
/// row per state.
///
/// # Errors
/// The writer's.
pub fn write_csv<T, Q, V, W>(
    w: &mut W,
    states: &[State<T, Q, V>],
    nq: usize,
    nv: usize,
) -> fmt::Result
where
    T: Scalar + fmt::Debug,
    Q: Dim,
    V: Dim,
    W: fmt::Write + ?Sized,
    DefaultAllocator: Allocator<Q> + Allocator<V>,
{
    let (nq, nv) = states.first().map_or((nq, nv), |s| (s.q.len(), s.v.len()));
    write_csv_header(w, nq, nv)?;
    states.iter().try_for_each(|s| write_csv_row(w, s))
}

#[cfg(feature = "alloc")]
pub use owned::Trajectory;

#[cfg(feature = "alloc")]
mod owned {
    use alloc::vec::Vec;

    use nalgebra::allocator::Allocator;
    use nalgebra::{DefaultAllocator, Dim, Scalar};

    use crate::integrate::State;

    /// The states of a run, in time order (`alloc`).
    #[derive(Clone, Debug, PartialEq)]
    pub struct Trajectory<T: Scalar, Q: Dim, V: Dim>
    where
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        states: Vec<State<T, Q, V>>,
    }

    impl<T: Scalar, Q: Dim, V: Dim> Default for Trajectory<T, Q, V>
    where
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        fn default() -> Self {
            Trajectory { states: Vec::new() }
        }
    }

    impl<T: Scalar, Q: Dim, V: Dim> Trajectory<T, Q, V>
    where
        DefaultAllocator: Allocator<Q> + Allocator<V>,
    {
        /// An empty trajectory.
        pub fn new() -> Self {
            Self::default()
        }

        /// Appends a state.
        pub fn push(&mut self, state: State<T, Q, V>) {
            self.states.push(state);
        }

        /// Reserves room for `additional` more states.
        pub fn reserve(&mut self, additional: usize) {
            self.states.reserve(additional);
        }

        /// The states.
        pub fn states(&self) -> &[State<T, Q, V>] {
            &self.states
        }

        /// The number of states.
        pub fn len(&self) -> usize {
            self.states.len()
        }

        /// Whether there is no state.
        pub fn is_empty(&self) -> bool {
            self.states.is_empty()
        }

        /// The states, by value.
        pub fn into_states(self) -> Vec<State<T, Q, V>> {
            self.states
        }

        /// Writes the trajectory as CSV ([module docs](super)) to `w` (buffered here; pass the
        /// file itself). `nq` and `nv` size the header of an empty trajectory.
        ///
        /// # Errors
        /// The writer's.
        #[cfg(feature = "std")]
        pub fn write_csv<W: std::io::Write>(
            &self,
            w: W,
            nq: usize,
            nv: usize,
        ) -> std::io::Result<()>
        where
            T: core::fmt::Debug,
        {
            let mut adapter = IoAdapter {
                inner: std::io::BufWriter::new(w),
                error: None,
            };
            match super::write_csv(&mut adapter, &self.states, nq, nv) {
                Ok(()) => {}
                Err(core::fmt::Error) => {
                    return Err(adapter
                        .error
                        .unwrap_or_else(|| std::io::Error::other("formatting failed")))
                }
            }
            std::io::Write::flush(&mut adapter.inner)?;
            adapter
                .inner
                .into_inner()
                .map(|_| ())
                .map_err(|e| e.into_error())
        }
    }

    /// `fmt::Write` over `io::Write`, keeping the first I/O error.
    #[cfg(feature = "std")]
    struct IoAdapter<W: std::io::Write> {
        inner: W,
        error: Option<std::io::Error>,
    }

    #[cfg(feature = "std")]
    impl<W: std::io::Write> core::fmt::Write for IoAdapter<W> {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            std::io::Write::write_all(&mut self.inner, s.as_bytes()).map_err(|e| {
                self.error = Some(e);
                core::fmt::Error
            })
        }
    }
}
