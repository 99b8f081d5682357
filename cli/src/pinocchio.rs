//! `--q-order pinocchio`: the vectors a command reads and prints in Pinocchio's layout
//! (`articulated::pinocchio`): its free flyer's quaternion `[qx, qy, qz, qw]`, a continuous
//! joint's `(cos θ, sin θ)`, its URDF joint order (a link's children by name).

use articulated::interpreted::coordinates_of;
use articulated::model::JointKind;
use articulated::pinocchio::Layout;
use articulated::Coordinates;
use articulated_codegen::options::Description;

/// Which layout the vectors on the command line and in the output follow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum QOrder {
    /// Ours: joints in the description's order, quaternions `[w, x, y, z]`, one angle per
    /// revolute joint.
    #[default]
    Articulated,
    /// Pinocchio's: joints as its URDF parser orders them, quaternions `[x, y, z, w]`,
    /// continuous joints as `(cos θ, sin θ)`.
    Pinocchio,
}

/// A model's layout in Pinocchio, owned.
pub struct Pinocchio {
    coordinates: Vec<Coordinates>,
    continuous: Vec<usize>,
    order: Vec<usize>,
    /// Each of our joints with coordinates: its name and kind.
    joints: Vec<(String, JointKind)>,
}

impl Pinocchio {
    /// The layout of `description`'s model (its URDF's continuous joints and Pinocchio's joint
    /// order, as the importer reports them; a `.chain` file's order is ours).
    pub fn of(description: &Description) -> Self {
        let model = &description.model;
        let joints: Vec<(String, JointKind)> = model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| (j.name.clone(), j.kind))
            .collect();
        let continuous = description
            .continuous
            .iter()
            .filter_map(|c| {
                let i = model.joints.iter().position(|j| &j.name == c)?;
                Some(model.q_offset(i))
            })
            .collect();
        let order: Vec<usize> = description
            .pinocchio_order
            .iter()
            .filter_map(|name| joints.iter().position(|(n, _)| n == name))
            .collect();
        let order = if order.len() == joints.len() {
            order
        } else {
            (0..joints.len()).collect()
        };
        Pinocchio {
            coordinates: coordinates_of(model),
            continuous,
            order,
            joints,
        }
    }

    fn layout(&self) -> Result<Layout<'_>, String> {
        Layout::new(&self.coordinates, &self.continuous)
            .and_then(|l| l.with_order(&self.order))
            .map_err(|e| format!("error: Pinocchio's layout of this model: {e}"))
    }

    /// Pinocchio's number of positions.
    pub fn nq(&self) -> Result<usize, String> {
        self.layout().map(|l| l.nq_pinocchio())
    }

    /// Pinocchio's `q` (the argument `what`) in our layout.
    pub fn q_in(&self, q: &[f64], what: &str) -> Result<Vec<f64>, String> {
        let layout = self.layout()?;
        let mut out = vec![0.0; layout.nq()];
        layout
            .q_from_pinocchio(q, &mut out)
            .map_err(|e| format!("error: --{what}: {e}"))?;
        Ok(out)
    }

    /// For each entry of Pinocchio's `v`, the index of ours it holds.
    pub fn v_sources(&self) -> Result<Vec<usize>, String> {
        let layout = self.layout()?;
        let ours: Vec<usize> = (0..layout.nv()).collect();
        let mut out = vec![0; layout.nv()];
        layout
            .v_to_pinocchio(&ours, &mut out)
            .map_err(|e| format!("error: {e}"))?;
        Ok(out)
    }

    /// Pinocchio's `v` (or `a`, `τ`: the argument `what`) in our layout.
    pub fn v_in(&self, v: &[f64], what: &str) -> Result<Vec<f64>, String> {
        let layout = self.layout()?;
        let mut out = vec![0.0; layout.nv()];
        layout
            .v_from_pinocchio(v, &mut out)
            .map_err(|e| format!("error: --{what}: {e}"))?;
        Ok(out)
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
                (Coordinates::Vector(1), JointKind::Revolute { .. })
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
