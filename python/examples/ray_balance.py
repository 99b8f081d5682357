"""A Monte Carlo of the two-link's balance over pushes and payloads, spread over a Ray cluster.

The model (``two_link_payload.chain``) is Hemami's two-link standing person, legs and trunk on
spherical ankle and hip joints, carrying a payload on the shoulders whose mass is a runtime
parameter. The controller is the runtime's: a linear-quadratic regulator designed once, about
the upright equilibrium at the nominal payload (``Model.lqr``), applied through the joints'
drives, which saturate the ankle's torque at 150 N·m (what the feet can press) and the hip's at
400 N·m (``Model.simulate(gain=…, drives=True)``).

Each run draws a payload (uniform, 0 to 60 kg) and a push at the shoulders: a horizontal
impulse (uniform, 0 to 60 N·s) in a random direction, which starts the upright body with the
velocity ``v0 = M(q0)⁻¹·Jᵀ·p`` (``J`` the shoulders' linear Jacobian). It is simulated for a
few seconds (RK4, 10 ms steps) and judged:

- **fell**: the ankle's or the hip's roll or pitch went past 0.5 rad, or the run faulted (a
  fallen body tumbles through the Euler angles' singularity);
- **balanced**: not fallen, and back upright at the end (those angles within 0.05 rad, their
  rates within 0.2 rad/s; yaw, which gravity does not act on, is not judged);
- neither: still on its way at the end; mostly payloads above 50 kg, near the 57 kg where the
  regulator designed for 10 kg stops holding even the upright (its linearization turns
  unstable there), which the ankle's saturated torque then cannot catch.

The study is cut into tasks. Task ``k`` draws its samples from its own seed
(``SeedSequence(seed, spawn_key=(k,))``, which is ``SeedSequence(seed).spawn(n)[k]`` for any
``n > k``), simulates them as large batches (``Model.simulate`` runs a batch on all of its
process's cores, each run alone) and returns per-run outcomes; the outcomes are joined in task
order. So the result depends on ``(tasks, runs, seed)`` only: run serially in this process or
as Ray tasks on any number of machines, it is the same, bit for bit (``--check`` verifies it).

Run it (see README.md)::

    python python/examples/ray_balance.py                   # a local Ray instance
    python python/examples/ray_balance.py --address auto    # a running cluster
    python python/examples/ray_balance.py --serial          # no Ray: a loop in this process
    python python/examples/ray_balance.py --check           # Ray, then serial: bitwise equal?
"""

import argparse
import os
import sys
import tempfile
import time

import numpy as np

import articulated

#: The model: two_link_payload.chain beside this file.
MODEL_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "two_link_payload.chain")

#: The sampled ranges: payload (kg) and the push's impulse (N·s).
PAYLOAD = (0.0, 60.0)
IMPULSE = (0.0, 60.0)
#: The payload the regulator is designed for (kg): the model's default.
NOMINAL_PAYLOAD = 10.0
#: Simulated time (s) and step (s) of each run.
HORIZON = 3.0
DT = 1e-2
#: A tilt past this has fallen (rad); back upright: angles and rates within these at the end.
FALL_TILT = 0.5
UPRIGHT_ANGLE = 0.05
UPRIGHT_RATE = 0.2
#: At most this many runs per `simulate` call (its result holds every step of every run).
BATCH = 2500
#: The tilt coordinates: the ankle's and the hip's roll and pitch (not their yaw).
TILTS = [0, 1, 3, 4]

#: The per-run outcomes `study` returns, each an array of `tasks · runs`: the draws (kg, N·s,
#: rad from the x axis), the largest roll or pitch of the run (rad; past `FALL_TILT` it only
#: says how far a fallen body tumbled), the largest at the end (NaN after a fault), and the
#: verdicts.
FIELDS = ("payload", "impulse", "direction", "max_tilt", "final", "faulted", "fell", "balanced")


def regulator(model):
    """The LQR about the upright equilibrium at the nominal payload: ``(q_eq, gain, tau_eq)``."""
    q_eq = model.neutral()
    nominal = model.with_params([NOMINAL_PAYLOAD])
    # Weights: roll and pitch angles and rates (ankle then hip) matter; yaw hardly (no gravity
    # acts on it, and a stiff yaw loop would only demand smaller steps).
    q_weight = np.diag([400.0, 400.0, 10.0, 400.0, 400.0, 10.0, 10.0, 10.0, 1.0, 10.0, 10.0, 1.0])
    r_weight = np.diag([0.01, 0.01, 1.0, 0.01, 0.01, 1.0])
    gain, tau_eq = nominal.lqr(q_eq, q_weight, r_weight)
    return q_eq, gain, tau_eq


def load(source):
    """The model from its description's text (each task reads its own: a Model is not
    picklable, and the text travels where a path on this machine might not exist)."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "two_link_payload.chain")
        with open(path, "w") as f:
            f.write(source)
        return articulated.Model.load(path)


def samples(seed, task, runs):
    """Task `task`'s draws: payload (kg), impulse (N·s), direction (rad), from its own seed."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(task,)))
    payload = rng.uniform(*PAYLOAD, size=runs)
    impulse = rng.uniform(*IMPULSE, size=runs)
    direction = rng.uniform(0.0, 2.0 * np.pi, size=runs)
    return payload, impulse, direction


def push_velocities(model, q0, payload, impulse, direction):
    """The velocity a horizontal impulse at the shoulders gives the body at rest at `q0`:
    ``M(q0)⁻¹·Jᵀ·p``, with the mass matrix of each run's payload."""
    jacobian = model.frame_jacobian(q0, "load", reference="local_world_aligned")[3:6]
    v0 = np.empty((len(payload), model.nv))
    for k, (m, j, a) in enumerate(zip(payload, impulse, direction)):
        p = np.array([j * np.cos(a), j * np.sin(a), 0.0])
        v0[k] = model.with_params([m]).mass_matrix_inverse(q0) @ (jacobian.T @ p)
    return v0


def outcomes(model, payload, impulse, direction, horizon=HORIZON, dt=DT):
    """Simulates the runs of these payloads and pushes under the regulator and the drives;
    returns their outcomes (a dict of arrays, `FIELDS`)."""
    q_eq, gain, tau_eq = regulator(model)
    v0 = push_velocities(model, q_eq, payload, impulse, direction)
    runs = len(payload)
    max_tilt = np.empty(runs)
    final = np.empty(runs)
    faulted = np.empty(runs, dtype=bool)
    upright = np.empty(runs, dtype=bool)
    for start in range(0, runs, BATCH):
        part = slice(start, min(start + BATCH, runs))
        n = part.stop - part.start
        result = model.simulate(
            np.tile(q_eq, (n, 1)),
            v0[part],
            horizon,
            dt,
            integrator="rk4",
            gain=gain,
            q_ref=q_eq,
            tau_ref=tau_eq,
            params=payload[part, None],
            drives=True,
        )
        q, v = result["q"], result["v"]
        # A faulted run's states are NaN after the fault: its largest tilt is the largest
        # before it (its first state, upright, is always there).
        max_tilt[part] = np.nanmax(np.abs(q[:, :, TILTS]), axis=(1, 2))
        final[part] = np.abs(q[:, -1, TILTS]).max(axis=1)
        faulted[part] = [f is not None for f in result["faults"]]
        rates = np.abs(v[:, -1, TILTS]).max(axis=1)
        upright[part] = (final[part] < UPRIGHT_ANGLE) & (rates < UPRIGHT_RATE)
    fell = faulted | ~(max_tilt <= FALL_TILT)
    return {
        "payload": np.asarray(payload, dtype=float),
        "impulse": np.asarray(impulse, dtype=float),
        "direction": np.asarray(direction, dtype=float),
        "max_tilt": max_tilt,
        "final": final,
        "faulted": faulted,
        "fell": fell,
        "balanced": ~fell & upright,
    }


def run_task(source, seed, task, runs, horizon=HORIZON, dt=DT):
    """One task: `runs` samples from the task's seed, simulated; returns their outcomes (a
    dict of arrays of `runs`, `FIELDS`)."""
    payload, impulse, direction = samples(seed, task, runs)
    return outcomes(load(source), payload, impulse, direction, horizon, dt)


def reduce(outcomes):
    """The tasks' outcomes joined in task order (the order given, whatever order they finished
    in): a dict of arrays of `tasks · runs`."""
    return {name: np.concatenate([o[name] for o in outcomes]) for name in FIELDS}


def study(tasks, runs_per_task, seed, use_ray, horizon=HORIZON, dt=DT):
    """The Monte Carlo: `tasks` tasks of `runs_per_task` runs each, serially in this process
    (`use_ray=False`: a loop over the tasks, each batch on all cores) or as Ray tasks
    (`use_ray=True`: `ray.init` must have been called). The same arrays either way."""
    with open(MODEL_PATH) as f:
        source = f.read()
    if not use_ray:
        return reduce([run_task(source, seed, k, runs_per_task, horizon, dt) for k in range(tasks)])
    import ray

    if __name__ != "__main__":
        # Imported as a module (the tests): send its code to the workers, which cannot import
        # it (this folder is not on their path).
        ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
    # One core per task, and one thread per task's batch: the worker's pool would otherwise
    # take every core of the machine for each of the tasks running there at once.
    remote = ray.remote(num_cpus=1, runtime_env={"env_vars": {"RAYON_NUM_THREADS": "1"}})(run_task)
    futures = [remote.remote(source, seed, k, runs_per_task, horizon, dt) for k in range(tasks)]
    # `ray.get` of a list returns the results in the list's order: the fixed reduction order.
    return reduce(ray.get(futures))


def identical(a, b):
    """Whether two studies' outcomes are the same, bit for bit."""
    return a.keys() == b.keys() and all(
        a[k].dtype == b[k].dtype and a[k].shape == b[k].shape and a[k].tobytes() == b[k].tobytes()
        for k in a
    )


def summary(outcomes, bins=6):
    """The table: the fraction balanced per payload bin (rows) and impulse bin (columns)."""
    payload, impulse = outcomes["payload"], outcomes["impulse"]
    balanced, fell = outcomes["balanced"], outcomes["fell"]
    p_edges = np.linspace(*PAYLOAD, bins + 1)
    j_edges = np.linspace(*IMPULSE, bins + 1)
    p_bin = np.clip(np.searchsorted(p_edges, payload, side="right") - 1, 0, bins - 1)
    j_bin = np.clip(np.searchsorted(j_edges, impulse, side="right") - 1, 0, bins - 1)
    lines = [
        f"{len(payload)} runs: {balanced.sum()} balanced, {fell.sum()} fell "
        f"({outcomes['faulted'].sum()} faulted), {(~balanced & ~fell).sum()} still recovering",
        "fraction balanced, payload (kg) by push at the shoulders (N·s):",
        "payload  " + "".join(f"{f'{a:.0f}-{b:.0f}':>8}" for a, b in zip(j_edges, j_edges[1:]))
        + "     all",
    ]
    for i in range(bins):
        row = p_bin == i
        cells = []
        for j in range(bins):
            cell = row & (j_bin == j)
            cells.append(f"{balanced[cell].mean():8.2f}" if cell.any() else f"{'-':>8}")
        total = f"{balanced[row].mean():8.2f}" if row.any() else f"{'-':>8}"
        lines.append(f"{f'{p_edges[i]:.0f}-{p_edges[i + 1]:.0f}':<9}" + "".join(cells) + total)
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--address", help="a Ray cluster's address (`auto`, `HOST:6379`, "
                        "`ray://HOST:10001`); default: start a local Ray instance")
    parser.add_argument("--tasks", type=int, default=4, help="Ray tasks (default 4)")
    parser.add_argument("--runs", type=int, default=2000, help="runs per task (default 2000)")
    parser.add_argument("--seed", type=int, default=2024, help="the study's seed (default 2024)")
    parser.add_argument("--horizon", type=float, default=HORIZON,
                        help=f"simulated seconds per run (default {HORIZON})")
    parser.add_argument("--serial", action="store_true", help="no Ray: a loop in this process")
    parser.add_argument("--check", action="store_true",
                        help="run with Ray, then serially, and compare the outcomes bit for bit")
    args = parser.parse_args()
    if args.serial and args.check:
        parser.error("--check runs both (Ray, then serially): give it without --serial")

    results = {}
    if not args.serial:
        import ray

        start = time.perf_counter()
        if args.address:
            ray.init(address=args.address)
        else:
            ray.init(include_dashboard=False)
        cpus = ray.cluster_resources().get("CPU", 0)
        print(f"Ray: {cpus:.0f} CPUs, started in {time.perf_counter() - start:.1f} s")
        start = time.perf_counter()
        results["ray"] = study(args.tasks, args.runs, args.seed, True, args.horizon)
        print(f"Ray: {args.tasks} tasks x {args.runs} runs in {time.perf_counter() - start:.1f} s")
    if args.serial or args.check:
        start = time.perf_counter()
        results["serial"] = study(args.tasks, args.runs, args.seed, False, args.horizon)
        print(f"serial: {args.tasks} tasks x {args.runs} runs in "
              f"{time.perf_counter() - start:.1f} s")
    print(summary(next(iter(results.values()))))
    if args.check:
        same = identical(results["ray"], results["serial"])
        print("Ray and serial outcomes bitwise identical:", same)
        if not same:
            sys.exit(1)


if __name__ == "__main__":
    main()
