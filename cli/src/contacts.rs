//! `articulated eval --contacts`: the constrained dynamics and impacts at one state
//! (`articulated::constraint::dynamic`), from the kinematics either engine computes.

use articulated::constraint::dynamic::{self, FrameKinematics, System};
use articulated::constraint::{Baumgarte, Kind, Settings};
use nalgebra::{DMatrix, DVector};
use serde_json::Value;

use crate::parse_vector;

/// What the constraints are made of at one state: `M`, `nle = N·q̇ + g`, and each constrained
/// frame's kinematics (in the order of `--contacts`).
pub struct Kinematics {
    pub m: DMatrix<f64>,
    pub nle: DVector<f64>,
    pub frames: Vec<FrameKinematics>,
}

/// `--contacts a:six_d,b:point`: each frame's name and kind, in order.
pub fn parse(list: &str) -> Result<Vec<(String, Kind)>, String> {
    list.split(',')
        .map(str::trim)
        .map(|item| {
            let bad = || {
                format!(
                    "error: --contacts: `{item}`: expected FRAME:KIND with KIND `six_d` or `point`"
                )
            };
            let (name, kind) = item.split_once(':').ok_or_else(bad)?;
            let kind = match kind.trim() {
                "six_d" => Kind::SixD,
                "point" => Kind::Point,
                _ => return Err(bad()),
            };
            let name = name.trim();
            if name.is_empty() {
                return Err(bad());
            }
            Ok((name.to_string(), kind))
        })
        .collect()
}

/// `--baumgarte KP,KD`.
pub fn parse_gains(text: &str) -> Result<Baumgarte, String> {
    match parse_vector(text, "baumgarte", 2)?[..] {
        [kp, kd] => Ok(Baumgarte { kp, kd }),
        _ => Err("error: --baumgarte: expected KP,KD".into()),
    }
}

/// `--restitution E`, a finite number ≥ 0.
pub fn parse_restitution(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(e) if e.is_finite() && e >= 0.0 => Ok(e),
        _ => Err(format!(
            "error: --restitution: `{text}`: expected a finite number ≥ 0"
        )),
    }
}

/// The JSON of each contact's force (or impulse), by frame name: 6 numbers for `six_d`, 3 for
/// `point`.
fn by_frame(contacts: &[(String, Kind)], forces: &DVector<f64>) -> Value {
    let mut object = serde_json::Map::new();
    let mut start = 0;
    for (name, kind) in contacts {
        let k = kind.rows();
        let values: Vec<f64> = forces.iter().skip(start).take(k).copied().collect();
        object.insert(name.clone(), Value::from(values));
        start += k;
    }
    Value::Object(object)
}

/// `"constrained"` and, with a restitution, `"impulse"` (DESIGN §9), or why not.
pub fn solve(
    kinematics: &Kinematics,
    contacts: &[(String, Kind)],
    v: &[f64],
    tau: &[f64],
    baumgarte: Option<Baumgarte>,
    restitution: Option<f64>,
) -> (Result<Value, String>, Option<Result<Value, String>>) {
    let nv = kinematics.m.ncols();
    let mut system = System::new(nv);
    for ((_, kind), frame) in contacts.iter().zip(&kinematics.frames) {
        if let Err(e) = system.push(*kind, frame, None) {
            let e = e.to_string();
            return (Err(e.clone()), restitution.map(|_| Err(e)));
        }
    }
    let name_of = |contact: usize| contacts.get(contact).map_or("?", |c| c.0.as_str());
    let explain = |e: articulated::constraint::ConstraintError| match e {
        articulated::constraint::ConstraintError::Redundant { contact, row } => format!(
            "row {row} of the contact on `{}` depends on the rows before it: the contacts are \
             redundant",
            name_of(contact)
        ),
        other => other.to_string(),
    };
    let settings = Settings::default();
    let (v, tau) = (
        DVector::from_column_slice(v),
        DVector::from_column_slice(tau),
    );
    let constrained = dynamic::forward_dynamics(
        &kinematics.m,
        &kinematics.nle,
        &tau,
        &v,
        &system,
        baumgarte,
        &settings,
    )
    .map(|s| {
        serde_json::json!({
            "qdd": s.acceleration.iter().copied().collect::<Vec<f64>>(),
            "forces": by_frame(contacts, &s.forces),
            "residual": s.residual,
        })
    })
    .map_err(explain);
    let impulse = restitution.map(|e| {
        dynamic::impulse_dynamics(&kinematics.m, &v, &system, e, &settings)
            .map(|s| {
                serde_json::json!({
                    "v_plus": s.acceleration.iter().copied().collect::<Vec<f64>>(),
                    "impulses": by_frame(contacts, &s.forces),
                })
            })
            .map_err(explain)
    });
    (constrained, impulse)
}
