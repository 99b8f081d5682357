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
//!
//! # The sidecar
//!
//! The header names columns by position only (`q3`), and it stays so: programs read it. What
//! each column is and how the run went is in a second file, a JSON [`Sidecar`] (`alloc`): for
//! `swing.csv`, `swing.csv.json` ([`sidecar_path`], `std`), which `articulated simulate` writes
//! beside every trajectory (and `articulated invert` beside its couples, in the same layout).
//! For a run that stopped on a fault, the CSV holds every state up to the last good one and the
//! sidecar says where and why it stopped:
//!
//! ```json
//! {
//!   "format": "articulated-trajectory/1",
//!   "model": {"file": "models/two_link.chain", "name": "TwoLink"},
//!   "columns": [
//!     {"header": "t", "name": "time", "unit": "s"},
//!     {"header": "q0", "name": "ankle.rx", "unit": "rad"},
//!     …,
//!     {"header": "v5", "name": "hip.rz", "unit": "rad/s"}
//!   ],
//!   "integrator": "rk4",
//!   "dt": 0.001,
//!   "rows": 812,
//!   "t_last": 0.811,
//!   "outcome": {"status": "fault", "t": 0.8115, "step": 811, "message": "…"}
//! }
//! ```
//!
//! `columns` lists every CSV column in order: its header, the coordinate's name
//! (`Model::coordinate_names`: the joint, and for a joint of several coordinates a component,
//! `hip.ry`, `base.qw`) and its unit (`Model::coordinate_units`: `rad`, `m`, `1` for quaternion
//! components, `rad/s`, `m/s`). `rows` counts the data rows and `t_last` is the last row's time
//! (`null` when there is none). `outcome` is `{"status": "completed"}`, or a fault with the time
//! and the (0-based) step it happened in and its message. Numbers are written as in the CSV; a
//! number that is not finite is `null`.

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
#[cfg(feature = "std")]
pub use sidecar::sidecar_path;
#[cfg(feature = "alloc")]
pub use sidecar::{Column, Outcome, Sidecar};

#[cfg(feature = "alloc")]
mod sidecar {
    use alloc::string::{String, ToString};
    use alloc::vec::Vec;
    use core::fmt;

    use crate::integrate::Fault;

    /// One column of a trajectory CSV: its header (`q3`), what it holds (`hip.ry`) and the
    /// unit (`rad`). See the [module docs](super#the-sidecar).
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Column {
        /// The CSV header's name for it.
        pub header: String,
        /// The coordinate (or quantity) it holds.
        pub name: String,
        /// Its unit (`1` for none).
        pub unit: String,
    }

    impl Column {
        /// A column.
        pub fn new(header: &str, name: &str, unit: &str) -> Self {
            Column {
                header: header.into(),
                name: name.into(),
                unit: unit.into(),
            }
        }

        /// The columns of [`write_csv_header`](super::write_csv_header)'s header
        /// `t,q0,…,v0,…`, named and with units: `q_names[i]` in `q_units[i]` for `qi`, and
        /// the same for `v` (`Model::coordinate_names` and `Model::coordinate_units` give
        /// them). A name or unit missing from a shorter list is left empty; `t` is `time` in
        /// `s`.
        pub fn trajectory<N: AsRef<str>, U: AsRef<str>>(
            (q_names, q_units): (&[N], &[U]),
            (v_names, v_units): (&[N], &[U]),
        ) -> Vec<Column> {
            let n = q_names.len().max(q_units.len());
            let m = v_names.len().max(v_units.len());
            fn at<S: AsRef<str>>(list: &[S], i: usize) -> &str {
                list.get(i).map_or("", AsRef::as_ref)
            }
            let mut columns = Vec::with_capacity(1 + n + m);
            columns.push(Column::new("t", "time", "s"));
            for i in 0..n {
                let header = alloc::format!("q{i}");
                columns.push(Column::new(&header, at(q_names, i), at(q_units, i)));
            }
            for i in 0..m {
                let header = alloc::format!("v{i}");
                columns.push(Column::new(&header, at(v_names, i), at(v_units, i)));
            }
            columns
        }
    }

    /// How a run ended.
    #[derive(Clone, Debug, PartialEq)]
    pub enum Outcome {
        /// It reached its end time.
        Completed,
        /// It stopped on a [`Fault`]: the file holds the states before it.
        Fault {
            /// When (s).
            t: f64,
            /// In which step (0-based: the step from row `step` to row `step + 1`).
            step: usize,
            /// Why.
            message: String,
        },
    }

    impl Outcome {
        /// The outcome of a run that ended with `result` (`Err`: the fault, its cause as the
        /// message).
        pub fn of<T, R>(result: &Result<R, Fault<T>>) -> Self
        where
            T: Copy + Into<f64> + fmt::Display,
        {
            match result {
                Ok(_) => Outcome::Completed,
                Err(fault) => Outcome::Fault {
                    t: fault.t.into(),
                    step: fault.step,
                    message: fault.cause.to_string(),
                },
            }
        }
    }

    /// What a trajectory file holds and how its run went: the JSON written beside it (see
    /// the [module docs](super#the-sidecar)).
    ///
    /// ```
    /// use articulated::trajectory::{Column, Outcome, Sidecar};
    /// let sidecar = Sidecar {
    ///     model: "pendulum.chain".into(),
    ///     name: "Pendulum".into(),
    ///     columns: Column::trajectory((&["pivot"], &["rad"]), (&["pivot"], &["rad/s"])),
    ///     integrator: "rk4".into(),
    ///     dt: 0.01,
    ///     rows: 101,
    ///     t_last: Some(1.0),
    ///     outcome: Outcome::Completed,
    /// };
    /// let json = sidecar.to_string();
    /// assert!(json.contains(r#"{"header": "q0", "name": "pivot", "unit": "rad"}"#));
    /// assert!(json.contains(r#""outcome": {"status": "completed"}"#));
    /// ```
    #[derive(Clone, Debug, PartialEq)]
    pub struct Sidecar {
        /// The model's file, as the user gave it.
        pub model: String,
        /// The chain's name.
        pub name: String,
        /// Every column of the CSV, in order.
        pub columns: Vec<Column>,
        /// The integrator (`rk4`, `dopri5`, …).
        pub integrator: String,
        /// Its step (s): for an adaptive method, the spacing of the recorded states.
        pub dt: f64,
        /// The number of data rows.
        pub rows: usize,
        /// The last row's time, if any.
        pub t_last: Option<f64>,
        /// How the run ended.
        pub outcome: Outcome,
    }

    impl Sidecar {
        /// Writes the JSON, one column a line, and a newline.
        ///
        /// # Errors
        /// The writer's.
        pub fn write_json<W: fmt::Write + ?Sized>(&self, w: &mut W) -> fmt::Result {
            w.write_str(
                "{\n  \"format\": \"articulated-trajectory/1\",\n  \"model\": {\"file\": ",
            )?;
            string(w, &self.model)?;
            w.write_str(", \"name\": ")?;
            string(w, &self.name)?;
            w.write_str("},\n  \"columns\": [")?;
            for (i, c) in self.columns.iter().enumerate() {
                w.write_str(if i == 0 { "\n    " } else { ",\n    " })?;
                w.write_str("{\"header\": ")?;
                string(w, &c.header)?;
                w.write_str(", \"name\": ")?;
                string(w, &c.name)?;
                w.write_str(", \"unit\": ")?;
                string(w, &c.unit)?;
                w.write_str("}")?;
            }
            w.write_str("\n  ],\n  \"integrator\": ")?;
            string(w, &self.integrator)?;
            w.write_str(",\n  \"dt\": ")?;
            number(w, self.dt)?;
            write!(w, ",\n  \"rows\": {},\n  \"t_last\": ", self.rows)?;
            match self.t_last {
                Some(t) => number(w, t)?,
                None => w.write_str("null")?,
            }
            w.write_str(",\n  \"outcome\": ")?;
            match &self.outcome {
                Outcome::Completed => w.write_str("{\"status\": \"completed\"}")?,
                Outcome::Fault { t, step, message } => {
                    w.write_str("{\"status\": \"fault\", \"t\": ")?;
                    number(w, *t)?;
                    write!(w, ", \"step\": {step}, \"message\": ")?;
                    string(w, message)?;
                    w.write_str("}")?;
                }
            }
            w.write_str("\n}\n")
        }
    }

    impl fmt::Display for Sidecar {
        /// The JSON ([`write_json`](Sidecar::write_json)).
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            self.write_json(f)
        }
    }

    /// A JSON number: as in the CSV (`{:?}`, which reads back exactly), `null` if not finite.
    fn number<W: fmt::Write + ?Sized>(w: &mut W, x: f64) -> fmt::Result {
        if x.is_finite() {
            write!(w, "{x:?}")
        } else {
            w.write_str("null")
        }
    }

    /// A JSON string, quoted and escaped (RFC 8259 §7).
    fn string<W: fmt::Write + ?Sized>(w: &mut W, s: &str) -> fmt::Result {
        w.write_char('"')?;
        for c in s.chars() {
            match c {
                '"' => w.write_str("\\\"")?,
                '\\' => w.write_str("\\\\")?,
                '\n' => w.write_str("\\n")?,
                '\r' => w.write_str("\\r")?,
                '\t' => w.write_str("\\t")?,
                c if (c as u32) < 0x20 => write!(w, "\\u{:04x}", c as u32)?,
                c => w.write_char(c)?,
            }
        }
        w.write_char('"')
    }

    /// Where the sidecar of the trajectory file `csv` goes: `csv` with `.json` appended
    /// (`swing.csv` → `swing.csv.json`).
    #[cfg(feature = "std")]
    pub fn sidecar_path(csv: &std::path::Path) -> std::path::PathBuf {
        let mut name = csv.as_os_str().to_os_string();
        name.push(".json");
        name.into()
    }
}

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

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::{sidecar_path, Column, Outcome, Sidecar};

    /// The sidecar is JSON a standard parser reads back, field for field, with names that need
    /// escaping, a fault and a step that is not finite.
    #[test]
    fn the_sidecar_reads_back() {
        let sidecar = Sidecar {
            model: "dir/odd \"name\"\\x.chain".into(),
            name: "Odd".into(),
            columns: Column::trajectory(
                (&["a.qw", "tab\tnew\nline\u{1}"], &["1", "m"]),
                (&["é"], &["rad/s"]),
            ),
            integrator: "euler".into(),
            dt: f64::NAN,
            rows: 3,
            t_last: Some(0.2),
            outcome: Outcome::Fault {
                t: 0.25,
                step: 2,
                message: "acceleration[0] is not finite".into(),
            },
        };
        let json: serde_json::Value = serde_json::from_str(&sidecar.to_string()).unwrap();
        assert_eq!(json["format"], "articulated-trajectory/1");
        assert_eq!(json["model"]["file"], sidecar.model.as_str());
        assert_eq!(json["model"]["name"], "Odd");
        let columns: Vec<[String; 3]> = json["columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| ["header", "name", "unit"].map(|k| c[k].as_str().unwrap().to_string()))
            .collect();
        let want = [
            ["t", "time", "s"],
            ["q0", "a.qw", "1"],
            ["q1", "tab\tnew\nline\u{1}", "m"],
            ["v0", "é", "rad/s"],
        ];
        assert_eq!(columns, want.map(|c| c.map(String::from)));
        assert_eq!(json["integrator"], "euler");
        assert!(json["dt"].is_null());
        assert_eq!(json["rows"], 3);
        assert_eq!(json["t_last"], 0.2);
        assert_eq!(json["outcome"]["status"], "fault");
        assert_eq!(json["outcome"]["t"], 0.25);
        assert_eq!(json["outcome"]["step"], 2);
        assert_eq!(json["outcome"]["message"], "acceleration[0] is not finite");
        let completed = Sidecar {
            outcome: Outcome::Completed,
            t_last: None,
            ..sidecar
        };
        let json: serde_json::Value = serde_json::from_str(&completed.to_string()).unwrap();
        assert_eq!(json["outcome"], serde_json::json!({"status": "completed"}));
        assert!(json["t_last"].is_null());
        assert_eq!(
            sidecar_path(std::path::Path::new("out/swing.csv")),
            std::path::Path::new("out/swing.csv.json")
        );
    }
}
