// The bindings of a generated chain, written into each crate `articulated.generate()` builds
// (after the chain's `#[derive(Chain)]`, whose type is `Generated` in the scalar `Scalar`).
// Every output's binding takes one state `(n,)` or a batch `(B, n)` per argument, reads C-ordered
// arrays where they lie and calls the output's `_batch` twin (lanes) on groups of states spread
// over every core, with the interpreter's lock released, writing into the result arrays.

use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use numpy::ndarray::IxDyn;
use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// `articulated.Error` with `message`.
fn error(py: Python<'_>, message: String) -> PyErr {
    match py
        .import("articulated")
        .and_then(|m| m.getattr("Error"))
        .and_then(|e| e.call1((message.clone(),)))
    {
        Ok(value) => PyErr::from_value(value),
        Err(_) => pyo3::exceptions::PyValueError::new_err(message),
    }
}

/// A result of a generated function, as arrays: its parts' shapes for one state, and each
/// part's values row-major.
trait Flat: Sized {
    /// A value to overwrite.
    fn zero() -> Self;
    /// The shape of each part.
    fn shapes() -> Vec<Vec<usize>>;
    /// Writes part `part`'s values into `out`, exactly as long; the error of a failed state.
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String>;
    /// The number of values of part `part`.
    fn size(part: usize) -> usize {
        Self::shapes().get(part).map_or(0, |s| s.iter().product())
    }
}

impl Flat for Scalar {
    fn zero() -> Self {
        0.0
    }
    fn shapes() -> Vec<Vec<usize>> {
        vec![vec![]]
    }
    fn write(&self, _: usize, out: &mut [Scalar]) -> Result<(), String> {
        out[0] = *self;
        Ok(())
    }
}

impl<const R: usize, const C: usize> Flat for SMatrix<Scalar, R, C> {
    fn zero() -> Self {
        SMatrix::zeros()
    }
    fn shapes() -> Vec<Vec<usize>> {
        if C == 1 {
            vec![vec![R]]
        } else {
            vec![vec![R, C]]
        }
    }
    fn write(&self, _: usize, out: &mut [Scalar]) -> Result<(), String> {
        if C == 1 {
            out.copy_from_slice(self.as_slice());
        } else {
            for (k, x) in out.iter_mut().enumerate() {
                *x = self[(k / C, k % C)];
            }
        }
        Ok(())
    }
}

impl Flat for articulated::FramePlacement<Scalar> {
    fn zero() -> Self {
        articulated::FramePlacement {
            rotation: SMatrix::zeros(),
            translation: SVector::zeros(),
        }
    }
    fn shapes() -> Vec<Vec<usize>> {
        vec![vec![3, 3], vec![3]]
    }
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String> {
        match part {
            0 => self.rotation.write(0, out),
            _ => self.translation.write(0, out),
        }
    }
}

impl<X: Flat, const N: usize> Flat for [X; N] {
    fn zero() -> Self {
        core::array::from_fn(|_| X::zero())
    }
    fn shapes() -> Vec<Vec<usize>> {
        X::shapes()
            .into_iter()
            .map(|s| std::iter::once(N).chain(s).collect())
            .collect()
    }
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String> {
        let size = X::size(part);
        self.iter()
            .zip(out.chunks_mut(size.max(1)))
            .try_for_each(|(x, o)| x.write(part, o))
    }
}

impl<A: Flat, B: Flat> Flat for (A, B) {
    fn zero() -> Self {
        (A::zero(), B::zero())
    }
    fn shapes() -> Vec<Vec<usize>> {
        A::shapes().into_iter().chain(B::shapes()).collect()
    }
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String> {
        let a = A::shapes().len();
        if part < a {
            self.0.write(part, out)
        } else {
            self.1.write(part - a, out)
        }
    }
}

impl<A: Flat, B: Flat, C: Flat> Flat for (A, B, C) {
    fn zero() -> Self {
        (A::zero(), B::zero(), C::zero())
    }
    fn shapes() -> Vec<Vec<usize>> {
        <(A, B)>::shapes().into_iter().chain(C::shapes()).collect()
    }
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String> {
        let (a, b) = (A::shapes().len(), B::shapes().len());
        if part < a {
            self.0.write(part, out)
        } else if part < a + b {
            self.1.write(part - a, out)
        } else {
            self.2.write(part - a - b, out)
        }
    }
}

impl<X: Flat, E: core::fmt::Display> Flat for Result<X, E> {
    fn zero() -> Self {
        Ok(X::zero())
    }
    fn shapes() -> Vec<Vec<usize>> {
        X::shapes()
    }
    fn write(&self, part: usize, out: &mut [Scalar]) -> Result<(), String> {
        match self {
            Ok(x) => x.write(part, out),
            Err(e) => Err(e.to_string()),
        }
    }
}

/// An argument's states: the numpy array's own memory where it is C-ordered and aligned (no
/// copy: a batch's inputs are read where they lie), else a row-major copy.
enum States<'a, const N: usize> {
    Borrowed(&'a [SVector<Scalar, N>]),
    Owned(Vec<SVector<Scalar, N>>),
}

impl<const N: usize> core::ops::Deref for States<'_, N> {
    type Target = [SVector<Scalar, N>];
    fn deref(&self) -> &[SVector<Scalar, N>] {
        match self {
            States::Borrowed(s) => s,
            States::Owned(v) => v,
        }
    }
}

/// Argument `name` as states of `N` values: `(N,)` or `(B, N)`; `batch` is the call's number
/// of states so far (`Some(None)`: one state), which every argument must agree with.
fn states<'a, const N: usize>(
    py: Python<'_>,
    name: &str,
    array: &'a PyArrayLikeDyn<'_, Scalar, AllowTypeChange>,
    batch: &mut Option<Option<usize>>,
) -> PyResult<States<'a, N>> {
    let shape = array.shape().to_vec();
    let states = match shape.as_slice() {
        [n] if *n == N => None,
        [b, n] if *n == N => Some(*b),
        _ => {
            return Err(error(
                py,
                format!(
                    "argument `{name}` has shape {shape:?}, expected ({N},) for one state or (B, \
                     {N}) for a batch"
                ),
            ))
        }
    };
    match batch {
        Some(seen) if *seen != states => {
            return Err(error(
                py,
                format!(
                    "argument `{name}` has shape {shape:?}: give every argument as one state or \
                     all as batches of the same length"
                ),
            ))
        }
        _ => *batch = Some(states),
    }
    if array.is_c_contiguous() {
        if let Ok(values) = array.as_slice() {
            if let Ok(states) = bytemuck::try_cast_slice(values) {
                return Ok(States::Borrowed(states));
            }
        }
    }
    // Any other layout (a Fortran-ordered array's memory is its transpose) element by element.
    let values: Vec<Scalar> = array.as_array().iter().copied().collect();
    Ok(States::Owned(
        values
            .chunks_exact(N)
            .map(SVector::from_column_slice)
            .collect(),
    ))
}

/// States per group of a batch: each group's results go through a buffer this long (it stays
/// in the cache) into the output arrays, and the groups are spread over rayon's threads.
const GROUP: usize = 256;

/// Runs `f(range, out)` (the output's batch function on the states in `range`) over the
/// `n` states of a call, group by group on every core without the interpreter's lock, writing
/// each state's parts into arrays allocated once; the first failed state (in batch order)
/// raises `articulated.Error`. `batch`: `None` for one state (arrays without the leading `B`).
fn call<R, F>(py: Python<'_>, batch: Option<usize>, f: F) -> PyResult<Py<PyAny>>
where
    R: Flat + Send,
    F: Fn(core::ops::Range<usize>, &mut [R]) -> Result<(), articulated::lanes::BatchLengths> + Sync,
{
    use numpy::{PyArrayDyn, PyArrayMethods};
    use rayon::prelude::*;
    let n = batch.unwrap_or(1);
    let shapes = R::shapes();
    let arrays: Vec<Bound<'_, PyArrayDyn<Scalar>>> = shapes
        .iter()
        .map(|shape| {
            let dims: Vec<usize> = batch.into_iter().chain(shape.iter().copied()).collect();
            PyArrayDyn::<Scalar>::zeros(py, IxDyn(&dims), false)
        })
        .collect();
    let mut guards: Vec<_> = arrays.iter().map(|a| a.readwrite()).collect();
    let mut slices: Vec<&mut [Scalar]> = Vec::with_capacity(guards.len());
    for g in guards.iter_mut() {
        slices.push(g.as_slice_mut().map_err(|e| error(py, e.to_string()))?);
    }
    let sizes: Vec<usize> = (0..shapes.len()).map(R::size).collect();
    // Each group's share of every part.
    let mut groups: Vec<Vec<&mut [Scalar]>> = (0..n.div_ceil(GROUP)).map(|_| Vec::new()).collect();
    for (slice, &size) in slices.into_iter().zip(&sizes) {
        for (g, chunk) in groups
            .iter_mut()
            .zip(slice.chunks_mut((GROUP * size).max(1)))
        {
            g.push(chunk);
        }
        if size == 0 {
            groups.iter_mut().for_each(|g| g.push(&mut []));
        }
    }
    let group = |(k, mut parts): (usize, Vec<&mut [Scalar]>)| {
        let start = k * GROUP;
        let end = (start + GROUP).min(n);
        let mut out: Vec<R> = (start..end).map(|_| R::zero()).collect();
        if let Err(e) = f(start..end, &mut out) {
            return Some((start, e.to_string()));
        }
        for (i, r) in out.iter().enumerate() {
            for (p, part) in parts.iter_mut().enumerate() {
                let at = i * sizes[p];
                if let Err(e) = r.write(p, &mut part[at..at + sizes[p]]) {
                    return Some((start + i, e));
                }
            }
        }
        None
    };
    // One group (one state, a small batch) is computed here, holding the lock: waking the
    // pool's threads would cost more than the group.
    let failure = if groups.len() <= 1 {
        groups.into_iter().enumerate().find_map(group)
    } else {
        py.detach(|| {
            let failures: Vec<_> = groups.into_par_iter().enumerate().map(group).collect();
            failures.into_iter().flatten().next()
        })
    };
    drop(guards);
    if let Some((k, message)) = failure {
        return Err(error(
            py,
            match batch {
                Some(_) => format!("state {k} of the batch: {message}"),
                None => message,
            },
        ));
    }
    let mut parts: Vec<Py<PyAny>> = Vec::with_capacity(arrays.len());
    for a in arrays {
        if batch.is_none() && a.ndim() == 0 {
            // One state's number: a Python float.
            let x: Scalar = a
                .to_vec()
                .ok()
                .and_then(|v| v.first().copied())
                .unwrap_or_default();
            parts.push(x.into_pyobject(py)?.into_any().unbind());
        } else {
            parts.push(a.into_any().unbind());
        }
    }
    if parts.len() == 1 {
        Ok(parts.remove(0))
    } else {
        Ok(PyTuple::new(py, parts)?.into_any().unbind())
    }
}

/// The class `Model`: its constructor, sizes and names, and the binding of each output,
/// `name(arg: width, …) => its _par_batch twin` (one `#[pymethods]` block, as PyO3 wants).
macro_rules! bindings {
    ($($name:ident($($arg:ident: $n:expr),*) => $par:ident;)*) => {
        /// A model's generated code, as `articulated.generate()` built it.
        #[pyclass(frozen, module = "articulated")]
        struct Model;

        #[pymethods]
        impl Model {
            #[new]
            fn new() -> Self {
                Model
            }

            /// The number of position coordinates.
            #[getter]
            fn nq(&self) -> usize {
                Generated::NQ
            }

            /// The number of velocities.
            #[getter]
            fn nv(&self) -> usize {
                Generated::NV
            }

            /// The name of each entry of `q`.
            #[getter]
            fn q_names(&self) -> Vec<&'static str> {
                <Generated as articulated::Chain<Scalar>>::Q_NAMES.to_vec()
            }

            /// The name of each entry of `v` and `tau`.
            #[getter]
            fn v_names(&self) -> Vec<&'static str> {
                <Generated as articulated::Chain<Scalar>>::V_NAMES.to_vec()
            }

            /// The frames the frame outputs give, in their order.
            #[getter]
            fn frames(&self) -> Vec<&'static str> {
                <Generated as articulated::Chain<Scalar>>::FRAMES.to_vec()
            }

            /// The scalar of the generated code: `"f64"` or `"f32"`.
            #[getter]
            fn scalar(&self) -> &'static str {
                SCALAR
            }

            /// The outputs generated, in order.
            #[getter]
            fn outputs(&self) -> Vec<&'static str> {
                vec![$(stringify!($name)),*]
            }

            $(
                #[doc = concat!("`", stringify!($name), "` by generated code (see `articulated.Model.", stringify!($name), "`).")]
                fn $name(
                    &self,
                    py: Python<'_>,
                    $($arg: PyArrayLikeDyn<'_, Scalar, AllowTypeChange>),*
                ) -> PyResult<Py<PyAny>> {
                    let mut batch = None;
                    $(let $arg = states::<{ $n }>(py, stringify!($arg), &$arg, &mut batch)?;)*
                    call(py, batch.flatten(), |range, out| {
                        Generated::$par($(&$arg[range.clone()],)* out)
                    })
                }
            )*
        }
    };
}
