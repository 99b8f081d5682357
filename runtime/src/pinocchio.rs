//! Pinocchio's layout of `q` and `v`, and the conversions between it and ours.
//!
//! Pinocchio and `articulated` agree on every joint's velocity; they store three kinds of
//! joint's positions differently:
//!
//! | joint | our `q` | Pinocchio's `q` |
//! |---|---|---|
//! | free, quaternion ([`Coordinates::FreeQuaternion`]) | `[x, y, z, w, qx, qy, qz]` | `[x, y, z, qx, qy, qz, w]` (free flyer) |
//! | spherical, quaternion ([`Coordinates::Quaternion`]) | `[w, x, y, z]` | `[x, y, z, w]` |
//! | URDF `continuous` (a revolute joint) | `θ` | `(cos θ, sin θ)` (`JointModelRUB*`) |
//!
//! The velocities are the same, joint by joint: a free base's `[v; ω]` with both in the child
//! frame (Pinocchio's `LOCAL`), a spherical joint's `ω` in the child frame, a continuous joint's
//! `θ̇`; our Euler joints have `v = q̇` as Pinocchio's `SphericalZYX` and translation joints
//! do.
//!
//! The joints may come in another order. Both go depth first from the root; we take a body's
//! children in the order the description declares them (a URDF's document order), Pinocchio's
//! URDF parser in the order of the joints' names. On TIAGo, whose file lists the wheels first,
//! Pinocchio has them last. [`Layout::with_order`] takes Pinocchio's order (the URDF importer
//! computes it: `Description::pinocchio_order`), and then every conversion, `v` and `τ`
//! included, moves whole joints between the two orders.
//!
//! Passing Pinocchio's `q` of a free flyer unchanged takes its `qx` for our `w`: at Pinocchio's
//! neutral configuration `[0, 0, 0, 0, 0, 0, 1]` that is a half turn about z, a unit quaternion,
//! which nothing can tell from a meant one (on a Unitree G1 the joint torques come out off by
//! 152 N·m). Convert at the boundary.
//!
//! What a chain's coordinates do not say is given: which revolute joints a URDF declares
//! `continuous` ([`Layout::new`]) and Pinocchio's joint order ([`Layout::with_order`]); the
//! URDF importer reports both (`Description::continuous`, `Description::pinocchio_order`).
//! Where in doubt, compare the names: ours are [`Chain::Q_NAMES`](crate::Chain::Q_NAMES),
//! Pinocchio's `model.names`. Mimic joints: load the URDF in Pinocchio with `mimic=True`, so
//! that they have no coordinates there either.
//!
//! ```
//! use articulated::pinocchio::Layout;
//! use articulated::Coordinates;
//!
//! // A free base (quaternion) carrying one continuous wheel at q[7].
//! let layout = Layout::new(&[Coordinates::FreeQuaternion, Coordinates::Vector(1)], &[7]).unwrap();
//! assert_eq!((layout.nq(), layout.nq_pinocchio(), layout.nv()), (8, 9, 7));
//! let q = [0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0, core::f64::consts::FRAC_PI_2];
//! let mut pin = [0.0; 9];
//! layout.q_to_pinocchio(&q, &mut pin).unwrap();
//! assert_eq!(&pin[..7], &[0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 1.0]);
//! assert!(pin[7].abs() < 1e-16 && pin[8] == 1.0);
//! let mut back = [0.0; 8];
//! layout.q_from_pinocchio(&pin, &mut back).unwrap();
//! assert_eq!(back, q);
//! ```

use core::fmt;

use nalgebra::RealField;

#[cfg(feature = "alloc")]
use alloc::{format, string::String, vec::Vec};

use crate::configuration::{joints, SizeMismatch};
use crate::Coordinates;

/// A chain's coordinates with the positions Pinocchio stores differently and, where it
/// differs, Pinocchio's order of the joints: what the conversions need.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout<'a> {
    coordinates: &'a [Coordinates],
    continuous: &'a [usize],
    order: Option<&'a [usize]>,
}

/// Why a [`Layout`] cannot be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayoutError {
    /// An index of `continuous` is not the position of a one-coordinate joint.
    NotContinuous {
        /// The index in `q`.
        index: usize,
    },
    /// An index of `continuous` is given twice.
    Repeated {
        /// The index in `q`.
        index: usize,
    },
    /// The joint order is not a permutation of the chain's joints.
    Order {
        /// The chain's joints (entries of its coordinates).
        joints: usize,
    },
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LayoutError::NotContinuous { index } => write!(
                f,
                "q[{index}] is not the coordinate of a one-coordinate (revolute) joint, so it \
                 cannot be a continuous joint"
            ),
            LayoutError::Repeated { index } => {
                write!(f, "q[{index}] is named twice as a continuous joint")
            }
            LayoutError::Order { joints } => write!(
                f,
                "the joint order must name each of the chain's {joints} joints with coordinates \
                 once"
            ),
        }
    }
}

impl core::error::Error for LayoutError {}

impl<'a> Layout<'a> {
    /// The layout of a chain whose joints are `coordinates` ([`Chain::COORDINATES`], or
    /// [`interpreted::coordinates_of`] for a model read at run time) and whose URDF
    /// `continuous` joints have their angle at the indices `continuous` of our `q` (empty when
    /// it has none, or was not read from a URDF); Pinocchio's joint order taken as ours.
    ///
    /// # Errors
    /// An index of `continuous` that is not a one-coordinate joint's, or given twice.
    ///
    /// [`Chain::COORDINATES`]: crate::Chain::COORDINATES
    /// [`interpreted::coordinates_of`]: crate::interpreted::coordinates_of
    pub fn new(
        coordinates: &'a [Coordinates],
        continuous: &'a [usize],
    ) -> Result<Self, LayoutError> {
        for (k, &index) in continuous.iter().enumerate() {
            let single =
                joints(coordinates).any(|(c, iq, _)| c == Coordinates::Vector(1) && iq == index);
            if !single {
                return Err(LayoutError::NotContinuous { index });
            }
            if continuous.get(..k).is_some_and(|s| s.contains(&index)) {
                return Err(LayoutError::Repeated { index });
            }
        }
        Ok(Layout {
            coordinates,
            continuous,
            order: None,
        })
    }

    /// The layout with Pinocchio's joint order: `order[k]` is the index in `coordinates` of
    /// Pinocchio's `k`-th joint with coordinates (its joint `k + 1`: Pinocchio's joint 0 is the
    /// universe).
    ///
    /// # Errors
    /// `order` is not a permutation of `0..coordinates.len()`.
    pub fn with_order(self, order: &'a [usize]) -> Result<Self, LayoutError> {
        let n = self.coordinates.len();
        let permutation =
            order.len() == n && (0..n).all(|j| order.iter().filter(|&&k| k == j).count() == 1);
        if !permutation {
            return Err(LayoutError::Order { joints: n });
        }
        Ok(Layout {
            order: Some(order),
            ..self
        })
    }

    /// Our number of positions.
    pub fn nq(&self) -> usize {
        crate::configuration::dimensions(self.coordinates).0
    }

    /// Pinocchio's number of positions: one more per continuous joint.
    pub fn nq_pinocchio(&self) -> usize {
        self.nq() + self.continuous.len()
    }

    /// The number of velocities, ours and Pinocchio's.
    pub fn nv(&self) -> usize {
        crate::configuration::dimensions(self.coordinates).1
    }

    /// Each joint in Pinocchio's order: its coordinates, where its positions and velocities
    /// start in our `q` and `v`, and where they start in Pinocchio's.
    fn pinocchio_joints(
        &self,
    ) -> impl Iterator<Item = (Coordinates, [usize; 2], [usize; 2])> + use<'_, 'a> {
        (0..self.coordinates.len())
            .filter_map(move |k| {
                let j = self.order.map_or(Some(k), |o| o.get(k).copied())?;
                joints(self.coordinates).nth(j)
            })
            .scan((0, 0), move |(pq, pv), (c, iq, iv)| {
                let nq = c.nq() + usize::from(self.continuous.contains(&iq));
                let joint = (c, [iq, iv], [*pq, *pv]);
                (*pq, *pv) = (*pq + nq, *pv + c.nv());
                Some(joint)
            })
    }

    /// Checks our and Pinocchio's numbers of positions.
    fn check_q(&self, ours: usize, theirs: usize) -> Result<(), SizeMismatch> {
        for (found, needed) in [(ours, self.nq()), (theirs, self.nq_pinocchio())] {
            if found != needed {
                return Err(SizeMismatch {
                    nq: needed,
                    nv: self.nv(),
                    expected_nq: found,
                    expected_nv: self.nv(),
                });
            }
        }
        Ok(())
    }

    /// Checks our and Pinocchio's numbers of velocities.
    fn check_v(&self, ours: usize, theirs: usize) -> Result<(), SizeMismatch> {
        for found in [ours, theirs] {
            if found != self.nv() {
                return Err(SizeMismatch {
                    nq: self.nq(),
                    nv: self.nv(),
                    expected_nq: self.nq(),
                    expected_nv: found,
                });
            }
        }
        Ok(())
    }

    /// Our `q` (length [`nq`](Self::nq)) in Pinocchio's layout, written to `out` (length
    /// [`nq_pinocchio`](Self::nq_pinocchio)).
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn q_to_pinocchio<T: RealField + Copy>(
        &self,
        q: &[T],
        out: &mut [T],
    ) -> Result<(), SizeMismatch> {
        self.check_q(q.len(), out.len())?;
        for (c, [iq, _], [pq, _]) in self.pinocchio_joints() {
            let continuous = self.continuous.contains(&iq);
            let n = c.nq() + usize::from(continuous);
            let (Some(s), Some(d)) = (q.get(iq..iq + c.nq()), out.get_mut(pq..pq + n)) else {
                continue;
            };
            match c {
                Coordinates::FreeQuaternion => {
                    d[..3].copy_from_slice(&s[..3]);
                    d[3..6].copy_from_slice(&s[4..7]);
                    d[6] = s[3];
                }
                Coordinates::Quaternion => {
                    d[..3].copy_from_slice(&s[1..4]);
                    d[3] = s[0];
                }
                Coordinates::Vector(_) if continuous => {
                    let (sin, cos) = s[0].sin_cos();
                    d.copy_from_slice(&[cos, sin]);
                }
                Coordinates::Vector(_) => d.copy_from_slice(s),
            }
        }
        Ok(())
    }

    /// Pinocchio's `q` (length [`nq_pinocchio`](Self::nq_pinocchio)) in our layout, written to
    /// `out` (length [`nq`](Self::nq)). A continuous joint's angle is `atan2(sin, cos)`, in
    /// `(−π, π]`.
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn q_from_pinocchio<T: RealField + Copy>(
        &self,
        q: &[T],
        out: &mut [T],
    ) -> Result<(), SizeMismatch> {
        self.check_q(out.len(), q.len())?;
        for (c, [iq, _], [pq, _]) in self.pinocchio_joints() {
            let continuous = self.continuous.contains(&iq);
            let n = c.nq() + usize::from(continuous);
            let (Some(s), Some(d)) = (q.get(pq..pq + n), out.get_mut(iq..iq + c.nq())) else {
                continue;
            };
            match c {
                Coordinates::FreeQuaternion => {
                    d[..3].copy_from_slice(&s[..3]);
                    d[3] = s[6];
                    d[4..7].copy_from_slice(&s[3..6]);
                }
                Coordinates::Quaternion => {
                    d[0] = s[3];
                    d[1..4].copy_from_slice(&s[..3]);
                }
                Coordinates::Vector(_) if continuous => d[0] = s[1].atan2(s[0]),
                Coordinates::Vector(_) => d.copy_from_slice(s),
            }
        }
        Ok(())
    }

    /// Our `v` (or an acceleration, or `τ`) in Pinocchio's layout: each joint's entries
    /// unchanged ([module docs](self)), in Pinocchio's joint order.
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn v_to_pinocchio<T: Copy>(&self, v: &[T], out: &mut [T]) -> Result<(), SizeMismatch> {
        self.check_v(v.len(), out.len())?;
        for (c, [_, iv], [_, pv]) in self.pinocchio_joints() {
            if let (Some(s), Some(d)) = (v.get(iv..iv + c.nv()), out.get_mut(pv..pv + c.nv())) {
                d.copy_from_slice(s);
            }
        }
        Ok(())
    }

    /// Pinocchio's `v` (or `a`, or `τ`) in our layout.
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn v_from_pinocchio<T: Copy>(&self, v: &[T], out: &mut [T]) -> Result<(), SizeMismatch> {
        self.check_v(out.len(), v.len())?;
        for (c, [_, iv], [_, pv]) in self.pinocchio_joints() {
            if let (Some(s), Some(d)) = (v.get(pv..pv + c.nv()), out.get_mut(iv..iv + c.nv())) {
                d.copy_from_slice(s);
            }
        }
        Ok(())
    }

    /// Our state `(q, v)` in Pinocchio's layout, into `(q_out, v_out)`.
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn to_pinocchio<T: RealField + Copy>(
        &self,
        q: &[T],
        v: &[T],
        q_out: &mut [T],
        v_out: &mut [T],
    ) -> Result<(), SizeMismatch> {
        self.check_q(q.len(), q_out.len())?;
        self.v_to_pinocchio(v, v_out)?;
        self.q_to_pinocchio(q, q_out)
    }

    /// Pinocchio's state `(q, v)` in our layout, into `(q_out, v_out)`.
    ///
    /// # Errors
    /// A slice of the wrong length (nothing is written).
    pub fn from_pinocchio<T: RealField + Copy>(
        &self,
        q: &[T],
        v: &[T],
        q_out: &mut [T],
        v_out: &mut [T],
    ) -> Result<(), SizeMismatch> {
        self.check_q(q_out.len(), q.len())?;
        self.v_from_pinocchio(v, v_out)?;
        self.q_from_pinocchio(q, q_out)
    }
}

/// A model's layout in Pinocchio, owned: what a model read at run time (the CLI, the Python
/// package) converts with.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug)]
pub struct ModelLayout {
    coordinates: Vec<Coordinates>,
    continuous: Vec<usize>,
    order: Vec<usize>,
    /// Each of our joints with coordinates: its name and kind.
    joints: Vec<(String, crate::model::JointKind)>,
}

#[cfg(feature = "alloc")]
impl ModelLayout {
    /// The layout of `model` whose URDF declares the joints named `continuous` continuous and
    /// whose joints with coordinates Pinocchio takes in the order `order` (by name; what the
    /// URDF importer reports as `Description::continuous` and `Description::pinocchio_order`).
    /// An `order` that does not name every joint with coordinates once is taken as ours (a
    /// `.chain` file's).
    pub fn of(model: &crate::model::Model, continuous: &[String], order: &[String]) -> Self {
        let joints: Vec<(String, crate::model::JointKind)> = model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| (j.name.clone(), j.kind))
            .collect();
        let continuous = continuous
            .iter()
            .filter_map(|c| {
                let i = model.joints.iter().position(|j| &j.name == c)?;
                Some(model.q_offset(i))
            })
            .collect();
        let order: Vec<usize> = order
            .iter()
            .filter_map(|name| joints.iter().position(|(n, _)| n == name))
            .collect();
        let order = if order.len() == joints.len() {
            order
        } else {
            (0..joints.len()).collect()
        };
        ModelLayout {
            coordinates: crate::interpreted::coordinates_of(model),
            continuous,
            order,
            joints,
        }
    }

    /// The borrowed [`Layout`] that converts.
    ///
    /// # Errors
    /// As [`Layout::new`] and [`Layout::with_order`].
    pub fn layout(&self) -> Result<Layout<'_>, LayoutError> {
        Layout::new(&self.coordinates, &self.continuous)?.with_order(&self.order)
    }

    /// The names of Pinocchio's `q` and `v` entries (ours, `Model::coordinate_names`, moved
    /// and renamed: `base.qx, …, base.qw`, `wheel.cos, wheel.sin`).
    pub fn names(&self, q_names: &[String], v_names: &[String]) -> (Vec<String>, Vec<String>) {
        let (mut q, mut v) = (Vec::new(), Vec::new());
        let (mut iq, mut iv) = (Vec::new(), Vec::new());
        let (mut at_q, mut at_v) = (0, 0);
        for c in &self.coordinates {
            iq.push(at_q);
            iv.push(at_v);
            at_q += c.nq();
            at_v += c.nv();
        }
        for &j in &self.order {
            let (Some((&a, &b)), Some(c), Some((name, kind))) = (
                iq.get(j).zip(iv.get(j)),
                self.coordinates.get(j),
                self.joints.get(j),
            ) else {
                continue;
            };
            let ours = q_names.get(a..a + c.nq()).unwrap_or_default();
            match (c, kind) {
                (Coordinates::FreeQuaternion, _) => {
                    q.extend(ours.iter().take(3).cloned());
                    q.extend(ours.iter().skip(4).cloned());
                    q.extend(ours.get(3).cloned());
                }
                (Coordinates::Quaternion, _) => {
                    q.extend(ours.iter().skip(1).cloned());
                    q.extend(ours.first().cloned());
                }
                (Coordinates::Vector(1), crate::model::JointKind::Revolute { .. })
                    if self.continuous.contains(&a) =>
                {
                    q.push(format!("{name}.cos"));
                    q.push(format!("{name}.sin"));
                }
                _ => q.extend(ours.iter().cloned()),
            }
            v.extend(
                v_names
                    .get(b..b + c.nv())
                    .unwrap_or_default()
                    .iter()
                    .cloned(),
            );
        }
        (q, v)
    }
}
