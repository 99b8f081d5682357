//! `articulated simulate --ground …`: a chain stepped with contacts (`articulated::contact`) on
//! the interpreted reference dynamics, its contact spheres against ground half-spaces.

use articulated::contact::dynamic::{At, TimeStepper};
use articulated::contact::{Ground, Settings, Sphere};
use articulated::drives::ModelDrives;
use articulated::integrate::State;
use articulated::model::Model;
use articulated::nalgebra::{DVector, Dyn, Matrix6xX, Vector3};
use articulated::plot::{Panel, Series};
use articulated::reference::{Reference, ReferenceFrame};
use articulated::simulate::Simulation;
use articulated::trajectory::{Column, Outcome, Trajectory};
use articulated::FramePlacement;
use indicatif::ProgressBar;

use crate::{parse_vector, SimulateArgs};

/// The sidecar's name for the stepping.
pub const INTEGRATOR: &str =
    "contact (semi-implicit Euler, exact Coulomb cones, projected Gauss-Seidel)";

/// The grounds and spheres of `--ground` and `--contact-points`.
pub struct Scene {
    grounds: Vec<Ground>,
    spheres: Vec<Sphere>,
    /// Each point as the user wrote it (the CSV's and the plot's names).
    points: Vec<String>,
    /// The frames the spheres sit on (a sphere's `frame` indexes this).
    frames: Vec<String>,
}

impl Scene {
    /// The scene the arguments describe, else the one the description declares (`grounds`,
    /// `spheres`, `friction`, `restitution`; `--friction` and a non-zero `--restitution`
    /// replace its coefficients), `None` with neither; the frames are checked against the model.
    pub fn of(
        args: &SimulateArgs,
        model: &Model,
        declared: &articulated_codegen::options::Options,
    ) -> Result<Option<Scene>, String> {
        let points = args.contact_points.as_deref();
        if args.ground.is_empty() && points.is_none() && !declared.spheres.is_empty() {
            return Self::declared(args, declared).map(Some);
        }
        if args.ground.is_empty() {
            if points.is_some() || args.friction.is_some() || args.contact_forces {
                return Err(
                    "error: --contact-points, --friction and --contact-forces need a \
                            --ground"
                        .into(),
                );
            }
            return Ok(None);
        }
        Self::from_arguments(args, model).map(Some)
    }

    /// No sphere yet on `grounds`.
    fn new(grounds: Vec<Ground>) -> Scene {
        Scene {
            grounds,
            spheres: Vec::new(),
            points: Vec::new(),
            frames: Vec::new(),
        }
    }

    /// Adds the sphere `sphere` (its `frame` ignored) on the frame `frame`, named `name`.
    fn push(&mut self, name: &str, frame: &str, sphere: Sphere) {
        let index = match self.frames.iter().position(|f| f == frame) {
            Some(i) => i,
            None => {
                self.frames.push(frame.to_string());
                self.frames.len() - 1
            }
        };
        self.spheres.push(Sphere {
            frame: index,
            ..sphere
        });
        self.points.push(name.to_string());
    }

    /// The scene the description declares, with the coefficients the arguments replace.
    fn declared(
        args: &SimulateArgs,
        declared: &articulated_codegen::options::Options,
    ) -> Result<Scene, String> {
        let grounds = declared
            .grounds
            .iter()
            .map(|g| Ground::new(g.normal, g.offset).map_err(|e| format!("error: {e}")))
            .collect::<Result<_, _>>()?;
        let mut scene = Scene::new(grounds);
        let friction = args.friction.or(declared.friction).unwrap_or(0.0);
        let restitution = if args.restitution > 0.0 {
            args.restitution
        } else {
            declared.restitution
        };
        for s in &declared.spheres {
            let sphere = Sphere {
                frame: 0,
                offset: s.offset,
                radius: s.radius,
                friction,
                restitution,
            };
            scene.push(&s.name, &s.frame, sphere);
        }
        Ok(scene)
    }

    /// The scene of `--ground`, `--contact-points`, `--radius`, `--friction` and
    /// `--restitution`, each checked.
    fn from_arguments(args: &SimulateArgs, model: &Model) -> Result<Scene, String> {
        let grounds = args
            .ground
            .iter()
            .map(|g| {
                let v = parse_vector(g, "ground", 4)?;
                match v[..] {
                    [nx, ny, nz, d] => Ground::new([nx, ny, nz], d)
                        .map_err(|e| format!("error: --ground `{g}`: {e}")),
                    _ => Err(format!("error: --ground `{g}`: expected NX,NY,NZ,D")),
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        let Some(points) = args.contact_points.as_deref() else {
            return Err(
                "error: --ground needs --contact-points (FRAME or FRAME@X:Y:Z, \
                        comma-separated)"
                    .into(),
            );
        };
        let Some(friction) = args.friction else {
            return Err("error: --ground needs --friction MU".into());
        };
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(format!(
                "error: --friction {friction}: expected a finite number ≥ 0"
            ));
        }
        if !(0.0..=1.0).contains(&args.restitution) {
            return Err(format!(
                "error: --restitution {}: expected a number in [0, 1]",
                args.restitution
            ));
        }
        if !(args.radius.is_finite() && args.radius >= 0.0) {
            return Err(format!(
                "error: --radius {}: expected a finite number ≥ 0",
                args.radius
            ));
        }
        let known: Vec<&str> = model.frame_names().collect();
        let mut scene = Scene::new(grounds);
        for item in points.split(',').map(str::trim) {
            let (frame, offset) = contact_point(item, &known)?;
            let sphere = Sphere {
                frame: 0,
                offset,
                radius: args.radius,
                friction,
                restitution: args.restitution,
            };
            scene.push(item, frame, sphere);
        }
        Ok(scene)
    }
}

/// `FRAME` or `FRAME@X:Y:Z` of `--contact-points`: the frame, one of `known`, and the point in
/// its axes.
fn contact_point<'a>(item: &'a str, known: &[&str]) -> Result<(&'a str, [f64; 3]), String> {
    let (frame, offset) = match item.split_once('@') {
        None => (item, [0.0; 3]),
        Some((frame, at)) => {
            let v = parse_vector(&at.replace(':', ","), "contact-points", 3).map_err(|_| {
                format!(
                    "error: --contact-points: `{item}`: expected FRAME@X:Y:Z with three finite \
                     numbers"
                )
            })?;
            let at = |i: usize| v.get(i).copied().unwrap_or(0.0);
            (frame.trim(), [at(0), at(1), at(2)])
        }
    };
    if !known.contains(&frame) {
        return Err(format!(
            "error: --contact-points: `{frame}` is not a frame of the model (its bodies and \
             frames: {})",
            known.join(", ")
        ));
    }
    Ok((frame, offset))
}

/// Each contact point's force at each row of the trajectory, world axes (N), summed over the
/// grounds.
pub struct Forces {
    points: Vec<String>,
    /// Each row's time.
    times: Vec<f64>,
    rows: Vec<Vec<[f64; 3]>>,
    /// The first ground's normal: the plot shows the forces along it.
    normal: [f64; 3],
}

impl Forces {
    /// The sidecar's columns for the forces.
    pub fn columns(&self) -> Vec<Column> {
        self.points
            .iter()
            .flat_map(|p| {
                ["x", "y", "z"].map(|axis| {
                    Column::new(
                        &format!("f.{p}.{axis}"),
                        &format!("contact force at {p}, world {axis}"),
                        "N",
                    )
                })
            })
            .collect()
    }

    /// `csv` (a trajectory's, a header then one line per row) with the force columns added.
    pub fn append_to_csv(&self, csv: &[u8]) -> Vec<u8> {
        let text = String::from_utf8_lossy(csv);
        let mut out = String::with_capacity(text.len() * 2);
        for (i, line) in text.lines().enumerate() {
            out.push_str(line);
            if i == 0 {
                for c in self.columns() {
                    out.push(',');
                    out.push_str(&c.header);
                }
            } else {
                let row = self.rows.get(i - 1).map_or(&[][..], Vec::as_slice);
                for k in 0..self.points.len() {
                    let f = row.get(k).copied().unwrap_or([0.0; 3]);
                    out.push_str(&format!(",{},{},{}", f[0], f[1], f[2]));
                }
            }
            out.push('\n');
        }
        out.into_bytes()
    }

    /// A panel of each point's normal force (along the first ground's normal), every
    /// `stride`-th row.
    pub fn panel(&self, name: &str, stride: usize) -> Panel {
        let n = Vector3::from(self.normal);
        let mut panel = Panel::new(
            &format!("{name}: normal contact forces"),
            "t (s)",
            "force (N)",
        );
        for (k, point) in self.points.iter().enumerate() {
            let points = self
                .rows
                .iter()
                .enumerate()
                .step_by(stride.max(1))
                .filter_map(|(i, row)| {
                    let f = row.get(k)?;
                    Some((*self.times.get(i)?, n.dot(&Vector3::from(*f))))
                })
                .collect();
            panel.series.push(Series {
                label: point.clone(),
                points,
            });
        }
        panel
    }
}

/// The dynamics at a state and the kinematics of the spheres' frames.
struct DynamicsAt {
    m: articulated::nalgebra::DMatrix<f64>,
    nle: DVector<f64>,
    tau: DVector<f64>,
    placements: Vec<FramePlacement<f64>>,
    jacobians: Vec<Matrix6xX<f64>>,
}

/// `M`, `nle`, `τ` (the drives', else zero) and the frames' placements and LOCAL Jacobians at
/// `(q, v)`, by the reference.
fn dynamics_at(
    reference: &Reference,
    drives: Option<&ModelDrives>,
    scene: &Scene,
    q: &DVector<f64>,
    v: &DVector<f64>,
) -> Result<DynamicsAt, String> {
    let text = |e: articulated::reference::Error| e.to_string();
    let m = reference.mass_matrix(q.as_slice()).map_err(text)?;
    let nle = reference.bias(q.as_slice(), v.as_slice()).map_err(text)?
        + reference.gravity(q.as_slice()).map_err(text)?;
    let tau = drives.map_or_else(
        || DVector::zeros(v.len()),
        |d| d.force(q, v, &DVector::zeros(v.len())),
    );
    let mut placements = Vec::with_capacity(scene.frames.len());
    let mut jacobians = Vec::with_capacity(scene.frames.len());
    for name in &scene.frames {
        let (rotation, translation) = reference
            .frame_placement(q.as_slice(), name)
            .map_err(text)?;
        placements.push(FramePlacement {
            rotation,
            translation,
        });
        let j = reference
            .frame_jacobian(q.as_slice(), name, ReferenceFrame::Local)
            .map_err(text)?;
        jacobians.push(Matrix6xX::from_fn(j.ncols(), |r, c| {
            j.get((r, c)).copied().unwrap_or(0.0)
        }));
    }
    Ok(DynamicsAt {
        m,
        nle,
        tau,
        placements,
        jacobians,
    })
}

/// What a run with contacts produced.
pub struct Run {
    pub trajectory: Trajectory<f64, Dyn, Dyn>,
    pub forces: Forces,
    /// How it stopped, if it stopped early.
    pub fault: Option<(Outcome, String)>,
    /// The summary's words on how it was stepped.
    pub note: String,
}

/// Steps the chain with contacts from `(q0, v0)` over `simulation`'s grid (`steps` steps),
/// `τ` from the drives if given (else zero).
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    reference: &Reference,
    drives: Option<&ModelDrives>,
    scene: &Scene,
    q0: Vec<f64>,
    v0: Vec<f64>,
    simulation: &Simulation<f64>,
    steps: usize,
    bar: ProgressBar,
) -> Run {
    let coordinates = articulated::interpreted::coordinates_of(reference.model());
    let coordinates = coordinates.as_slice();
    let mut stepper = TimeStepper::new();
    let settings = Settings::default();
    let mut trajectory = Trajectory::new();
    let (mut q, mut v) = (DVector::from_vec(q0), DVector::from_vec(v0));
    trajectory.push(State::new(0.0, q.clone(), v.clone()));
    let mut rows = vec![vec![[0.0; 3]; scene.points.len()]];
    let mut fault = None;
    let (mut unconverged, mut worst, mut iterations) = (0usize, 0.0f64, 0usize);
    let time = |k: usize| {
        if k >= steps {
            simulation.t_end
        } else {
            simulation.t0 + k as f64 * simulation.dt
        }
    };
    for k in 0..steps {
        let (t, t_next) = (time(k), time(k + 1));
        let result = dynamics_at(reference, drives, scene, &q, &v).and_then(|d| {
            stepper
                .step(
                    coordinates,
                    &mut q,
                    &mut v,
                    &At {
                        m: &d.m,
                        nle: &d.nle,
                        tau: &d.tau,
                        placements: &d.placements,
                        jacobians: &d.jacobians,
                        damping: None,
                        limits: &[],
                    },
                    &scene.grounds,
                    &scene.spheres,
                    &settings,
                    t_next - t,
                )
                .map_err(|e| e.to_string())
        });
        match result {
            Ok(report) => {
                iterations += report.iterations;
                if !report.converged {
                    unconverged += 1;
                    worst = worst.max(report.residual);
                }
            }
            Err(message) => {
                fault = Some((
                    Outcome::Fault {
                        t,
                        step: k,
                        message: message.clone(),
                    },
                    format!("at t = {t} (step {k}): {message}"),
                ));
                break;
            }
        }
        let mut row = vec![[0.0; 3]; scene.points.len()];
        for f in stepper.forces() {
            if let Some(r) = row.get_mut(f.sphere) {
                for (a, b) in r.iter_mut().zip(f.force) {
                    *a += b;
                }
            }
        }
        rows.push(row);
        trajectory.push(State::new(t_next, q.clone(), v.clone()));
        if k % 64 == 0 {
            bar.set_position(k as u64);
        }
    }
    if fault.is_some() {
        bar.abandon();
    } else {
        bar.finish_and_clear();
    }
    let done = rows.len().saturating_sub(1).max(1);
    let mut note = format!(
        "with contacts ({} Gauss-Seidel sweeps per step on average)",
        format_args!("{:.1}", iterations as f64 / done as f64)
    );
    if unconverged > 0 {
        eprintln!(
            "warning: the contact solve did not reach its tolerance in {unconverged} of {done} \
             steps (largest residual {worst:.2e} m/s); those steps moved on with the impulses \
             it had"
        );
        note += &format!(", {unconverged} steps not converged");
    }
    let times = trajectory.states().iter().map(|s| s.t).collect();
    Run {
        trajectory,
        forces: Forces {
            points: scene.points.clone(),
            times,
            rows,
            normal: scene
                .grounds
                .first()
                .map_or([0.0, 0.0, 1.0], Ground::normal),
        },
        fault,
        note,
    }
}
