//! numpy arrays in and out, one state or a batch, on every core.
//!
//! Every function of the package takes each argument as one state (`(n,)`) or a batch
//! (`(B, n)`): all of one call's arguments alike. A batch runs with the interpreter's lock
//! released, its states spread over rayon's threads; each state is computed on its own, so the
//! results are the same whatever the number of threads. The results come back as arrays of the
//! output's shape, with a leading `B` for a batch.

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rayon::prelude::*;

use crate::Error;

/// One argument of a call, its values state after state.
pub struct Arg {
    name: &'static str,
    values: Vec<f64>,
    width: usize,
    /// `Some(B)` for a `(B, width)` array, `None` for one state.
    states: Option<usize>,
}

impl Arg {
    /// Reads `array` as argument `name` of `width` values per state: `(width,)` or
    /// `(B, width)`, any dtype numpy can cast to float64.
    pub fn read(
        name: &'static str,
        array: &PyArrayLikeDyn<'_, f64, AllowTypeChange>,
        width: usize,
    ) -> PyResult<Arg> {
        let shape = array.shape().to_vec();
        let states = match shape.as_slice() {
            [n] if *n == width => None,
            [b, n] if *n == width => Some(*b),
            _ => {
                return Err(Error::new_err(format!(
                    "argument `{name}` has shape {shape:?}, expected ({width},) for one state or \
                     (B, {width}) for a batch"
                )))
            }
        };
        // In row-major order whatever the array's layout (`as_slice` would hand a Fortran-ordered
        // array's memory as it lies: its transpose).
        let values = match array.is_c_contiguous() {
            true => array.as_slice().map(<[f64]>::to_vec).unwrap_or_default(),
            false => array.as_array().iter().copied().collect(),
        };
        Ok(Arg {
            name,
            values,
            width,
            states,
        })
    }

    /// The same values for every state (`values` is one state's).
    pub fn constant(name: &'static str, values: &[f64]) -> Arg {
        Arg {
            name,
            values: values.to_vec(),
            width: values.len(),
            states: None,
        }
    }

    /// `Some(B)` for a batch of `B` states, `None` for one state.
    pub fn states(&self) -> Option<usize> {
        self.states
    }

    /// Every value, state after state.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// One state's values (the one state's for any `k` where it is not a batch).
    pub fn state(&self, k: usize) -> &[f64] {
        match self.states {
            Some(_) => &self.values[k * self.width..(k + 1) * self.width],
            None => &self.values,
        }
    }
}

/// The number of states of a call (`None`: one state, unbatched), the same for every argument.
pub fn states_of<'a>(args: impl IntoIterator<Item = &'a Arg>) -> PyResult<Option<usize>> {
    let mut args = args.into_iter();
    let Some(first) = args.next() else {
        return Ok(None);
    };
    for a in args {
        if a.states != first.states {
            let shape = |x: &Arg| match x.states {
                Some(b) => format!("({b}, {})", x.width),
                None => format!("({},)", x.width),
            };
            return Err(Error::new_err(format!(
                "arguments `{}` {} and `{}` {} differ: give every argument as one state or all as \
                 batches of the same length",
                first.name,
                shape(first),
                a.name,
                shape(a)
            )));
        }
    }
    Ok(first.states)
}

/// The shapes of an output's parts for one state (`[]` a number, `[n]` a vector, `[r, c]` a
/// matrix); several parts come back as a tuple of arrays.
pub type Shapes<'a> = &'a [&'a [usize]];

/// Evaluates `f(state's arguments, out)` for each state of `args`, `out` the state's values of
/// every part, one after the other, row-major; returns the parts as arrays. The first state that
/// fails (in batch order) raises [`Error`] with its message, prefixed by its index in a batch.
pub fn run<F>(py: Python<'_>, args: &[Arg], shapes: Shapes<'_>, f: F) -> PyResult<Py<PyAny>>
where
    F: Fn(&[&[f64]], &mut [f64]) -> Result<(), String> + Sync,
{
    let states = states_of(args)?;
    let per: usize = shapes.iter().map(|s| s.iter().product::<usize>()).sum();
    let n = states.unwrap_or(1);
    let mut out = vec![0.0; per * n];
    let one = |k: usize, o: &mut [f64]| {
        let inputs: Vec<&[f64]> = args.iter().map(|a| a.state(k)).collect();
        f(&inputs, o)
    };
    // One state is computed here, holding the lock: waking the pool's threads would cost more.
    if n == 1 && per > 0 {
        if let Err(message) = one(0, &mut out) {
            return Err(failed(states, 0, message));
        }
        return arrays(py, out, states, shapes);
    }
    let failure = py.detach(|| {
        let errors: Vec<Option<String>> = if per == 0 {
            (0..n).map(|k| one(k, &mut []).err()).collect()
        } else {
            out.par_chunks_mut(per)
                .enumerate()
                .map(|(k, o)| one(k, o).err())
                .collect()
        };
        errors
            .into_iter()
            .enumerate()
            .find_map(|(k, e)| e.map(|e| (k, e)))
    });
    if let Some((k, message)) = failure {
        return Err(failed(states, k, message));
    }
    arrays(py, out, states, shapes)
}

/// The error of state `k`: its message, prefixed by its index in a batch.
fn failed(states: Option<usize>, k: usize, message: String) -> PyErr {
    Error::new_err(match states {
        Some(_) => format!("state {k} of the batch: {message}"),
        None => message,
    })
}

/// Splits `out` (state after state, each the parts one after the other) into one array per part.
fn arrays(
    py: Python<'_>,
    out: Vec<f64>,
    states: Option<usize>,
    shapes: Shapes<'_>,
) -> PyResult<Py<PyAny>> {
    if let [shape] = shapes {
        return part(py, out, states, shape);
    }
    let per: usize = shapes.iter().map(|s| s.iter().product::<usize>()).sum();
    let mut parts = Vec::with_capacity(shapes.len());
    let mut offset = 0;
    for shape in shapes {
        let size: usize = shape.iter().product();
        let values = (0..states.unwrap_or(1))
            .flat_map(|k| {
                out[k * per + offset..k * per + offset + size]
                    .iter()
                    .copied()
            })
            .collect();
        offset += size;
        parts.push(part(py, values, states, shape)?);
    }
    Ok(PyTuple::new(py, parts)?.into_any().unbind())
}

/// One part's `values` as an array of `shape` (after `B` in a batch), or a Python float for one
/// state's number.
fn part(
    py: Python<'_>,
    values: Vec<f64>,
    states: Option<usize>,
    shape: &[usize],
) -> PyResult<Py<PyAny>> {
    let dims: Vec<usize> = states.into_iter().chain(shape.iter().copied()).collect();
    if dims.is_empty() {
        let x = values.first().copied().unwrap_or(f64::NAN);
        return Ok(x.into_pyobject(py)?.into_any().unbind());
    }
    let array =
        ArrayD::from_shape_vec(IxDyn(&dims), values).map_err(|e| Error::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py).into_any().unbind())
}

/// Copies a column-major nalgebra matrix into `out` row by row.
pub fn rows(m: &nalgebra::DMatrix<f64>, out: &mut [f64]) {
    let c = m.ncols();
    for ((i, j), x) in (0..m.nrows())
        .flat_map(|i| (0..c).map(move |j| (i, j)))
        .zip(out.iter_mut())
    {
        *x = m[(i, j)];
    }
}
