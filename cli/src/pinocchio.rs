//! `--q-order pinocchio`: the vectors a command reads and prints in Pinocchio's layout
//! (`articulated::pinocchio`): its free flyer's quaternion `[qx, qy, qz, qw]`, a continuous
//! joint's `(cos θ, sin θ)`, its URDF joint order (a link's children by name).

use articulated::pinocchio::{Layout, ModelLayout};
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

/// A model's layout in Pinocchio, owned ([`ModelLayout`]), with the messages of the command line.
pub struct Pinocchio(ModelLayout);

impl Pinocchio {
    /// The layout of `description`'s model (its URDF's continuous joints and Pinocchio's joint
    /// order, as the importer reports them; a `.chain` file's order is ours).
    pub fn of(description: &Description) -> Self {
        Pinocchio(ModelLayout::of(
            &description.model,
            &description.continuous,
            &description.pinocchio_order,
        ))
    }

    fn layout(&self) -> Result<Layout<'_>, String> {
        self.0
            .layout()
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

    /// The names of Pinocchio's `q` and `v` entries ([`ModelLayout::names`]).
    pub fn names(&self, q_names: &[String], v_names: &[String]) -> (Vec<String>, Vec<String>) {
        self.0.names(q_names, v_names)
    }
}
