// The bindings of a generated chain, written into each crate `articulated.generate()` builds
// (after the chain's `#[derive(Chain)]`, whose type is `Generated` in the scalar `Scalar`).
// Every output's binding takes one state `(n,)` or a batch `(B, n)` per argument and calls the
// output's `_par_batch` twin (lanes on every core) with the interpreter's lock released.

use articulated::nalgebra::{SMatrix, SVector};
use articulated::prelude::*;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLikeDyn, PyUntypedArrayMethods};
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
    /// Appends part `part`'s values to `out`; the error of a failed state.
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String>;
}

impl Flat for Scalar {
    fn zero() -> Self {
        0.0
    }
    fn shapes() -> Vec<Vec<usize>> {
        vec![vec![]]
    }
    fn write(&self, _: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
        out.push(*self);
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
    fn write(&self, _: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
        for i in 0..R {
            for j in 0..C {
                out.push(self[(i, j)]);
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
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
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
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
        self.iter().try_for_each(|x| x.write(part, out))
    }
}

impl<A: Flat, B: Flat> Flat for (A, B) {
    fn zero() -> Self {
        (A::zero(), B::zero())
    }
    fn shapes() -> Vec<Vec<usize>> {
        A::shapes().into_iter().chain(B::shapes()).collect()
    }
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
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
        let ab = <(A, B)>::shapes();
        ab.into_iter().chain(C::shapes()).collect()
    }
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
        let ab = <(A, B)>::shapes().len();
        if part < ab {
            match part < A::shapes().len() {
                true => self.0.write(part, out),
                false => self.1.write(part - A::shapes().len(), out),
            }
        } else {
            self.2.write(part - ab, out)
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
    fn write(&self, part: usize, out: &mut Vec<Scalar>) -> Result<(), String> {
        match self {
            Ok(x) => x.write(part, out),
            Err(e) => Err(e.to_string()),
        }
    }
}

/// Argument `name` as states of `N` values: `(N,)` or `(B, N)`; `batch` is the call's number
/// of states so far (`Some(None)`: one state), which every argument must agree with.
fn states<const N: usize>(
    py: Python<'_>,
    name: &str,
    array: &PyArrayLikeDyn<'_, Scalar, AllowTypeChange>,
    batch: &mut Option<Option<usize>>,
) -> PyResult<Vec<SVector<Scalar, N>>> {
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
    // Row-major whatever the array's layout: a C-ordered array's memory as it lies, any other
    // element by element (a Fortran-ordered one's memory is its transpose).
    let copied;
    let values: &[Scalar] = match array.as_slice() {
        Ok(s) if array.is_c_contiguous() => s,
        _ => {
            copied = array.as_array().iter().copied().collect::<Vec<_>>();
            &copied
        }
    };
    Ok(values
        .chunks_exact(N)
        .map(SVector::from_column_slice)
        .collect())
}

/// The results of a call as arrays (a tuple where the output has several parts); the first
/// failed state (in batch order) raises `articulated.Error`.
fn finish<R: Flat>(py: Python<'_>, out: Vec<R>, batch: Option<usize>) -> PyResult<Py<PyAny>> {
    let shapes = R::shapes();
    let mut parts = Vec::with_capacity(shapes.len());
    for (p, shape) in shapes.iter().enumerate() {
        let mut values = Vec::with_capacity(out.len() * shape.iter().product::<usize>());
        for (k, r) in out.iter().enumerate() {
            if let Err(e) = r.write(p, &mut values) {
                return Err(error(
                    py,
                    match batch {
                        Some(_) => format!("state {k} of the batch: {e}"),
                        None => e,
                    },
                ));
            }
        }
        let dims: Vec<usize> = batch.into_iter().chain(shape.iter().copied()).collect();
        if dims.is_empty() {
            parts.push(values[0].into_pyobject(py)?.into_any().unbind());
        } else {
            let array = ArrayD::from_shape_vec(IxDyn(&dims), values)
                .map_err(|e| error(py, e.to_string()))?;
            parts.push(array.into_pyarray(py).into_any().unbind());
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
                    let batch = batch.flatten();
                    let mut out = Vec::new();
                    out.resize_with(batch.unwrap_or(1), Flat::zero);
                    py.detach(|| Generated::$par($(&$arg,)* &mut out))
                        .map_err(|e| error(py, e.to_string()))?;
                    finish(py, out, batch)
                }
            )*
        }
    };
}
