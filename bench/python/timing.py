"""Speed from Python: nanoseconds per state of inverse and forward dynamics, ours against Pinocchio.

For each model (arm7, fixed base; the humanoid, quaternion free base) and each output
(inverse dynamics: Pinocchio's `rnea`; forward dynamics: `aba`) and each batch size B, it times,
per state:

- **ours, interpreted**: `articulated.Model.load(...).inverse_dynamics(Q, V, A)` on a `(B, n)`
  batch (rayon over the states, the GIL released);
- **ours, generated**: the same call on `articulated.generate(...)` (the generated
  `_batch` functions, SIMD lanes across states, on groups of states over rayon's threads);
- **Pinocchio, Python loop**: `pin.rnea(model, data, q, v, a)` called state by state from a
  Python `for` loop over the rows;
- **Pinocchio, in parallel**: `pin.rneaInParallel(T, pool, Q, V, A)` (`abaInParallel`), a
  `pin.ModelPool` of T datas and `(nq, B)` arrays (the transposes of the row-major batches:
  column-major, no copy), at the same thread count T as rayon's.

Every method gets the same random states (drawn once in our layout and converted to
Pinocchio's with `to_pinocchio_q`/`to_pinocchio_v`), and every method's results at the first
100 states are checked against `pin.rnea`/`pin.aba` (relative to each state's largest entry)
before any timing. A figure is the fastest of R rounds (`--repeats`, default 7) after one
warm-up call; each round times the four methods one after the other, in a rotating order, 5 ms
apart; a timing runs the call as many times as it takes to last `--min-time` seconds (default
0.02) and is divided by that count. Slow methods are timed on fewer states at the
largest batches and reported per state: the Python loop on at most `--loop-cap` states
(default 10,000) and the interpreter on at most `--interp-cap` states of a model
(default `humanoid=10000`); the output says where.

T is `--threads`, else `RAYON_NUM_THREADS`, else `os.cpu_count()`; it is exported as
`RAYON_NUM_THREADS` before `articulated` (and each generated module) starts its thread pool. The script also finds out whether the wheel's parallel functions use
OpenMP: the Python module's links (`ldd`: libgomp), its symbols (`GOMP_parallel`), and
`rneaInParallel` at 1 thread against T threads.

Usage (from the repository root, in a Python with `articulated` and `pin` installed):

    python bench/python/timing.py OUT.json [--batches 1,100,100000] [--repeats 7] [--threads T]

writes OUT.json (every figure, the machine and the versions) and prints a Markdown section
(`section()`, which `bench/peers/run.py` puts into BENCHMARKS.md as "From Python").
"""

import argparse
import datetime
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# (name, URDF, floating base).
MODELS = [
    ("arm7", "models/arm7.urdf", None),
    ("humanoid", "models/humanoid.urdf", "quaternion"),
]
# (our output, Pinocchio's function, its parallel twin).
OUTPUTS = [
    ("inverse_dynamics", "rnea", "rneaInParallel"),
    ("forward_dynamics", "aba", "abaInParallel"),
]
METHODS = ["interpreted", "generated", "pin_loop", "pin_parallel"]
SEED = 0x5EED_2024
TOL = 1e-9
CHECK_STATES = 100


def log(msg):
    print(f"[timing.py] {msg}", file=sys.stderr, flush=True)


def sh(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, shell=True).stdout.strip()
    except OSError:
        return ""


def time_together(calls, repeats, min_time, pause=0.005):
    """Nanoseconds per state of each of `calls` (name -> (function, states it computes)),
    timed together: one warm-up call each, then `repeats` rounds, each timing every function
    once in a rotating order (so that a busy moment of a shared machine falls on all of them
    alike), `pause` seconds apart (the threads of the one before, rayon's or OpenMP's, back
    asleep). A timing runs the function `inner` times, as many as last `min_time` seconds.
    Per name: the fastest round (`best_ns`) and the median."""
    inner = {}
    for name, (fn, _states) in calls.items():
        fn()
        t0 = time.perf_counter()
        fn()
        once = time.perf_counter() - t0
        inner[name] = max(1, int(min_time / once)) if once > 0 else 1000
    per = {name: [] for name in calls}
    names = list(calls)
    for r in range(repeats):
        for name in names[r % len(names):] + names[:r % len(names)]:
            fn, states = calls[name]
            time.sleep(pause)
            n = inner[name]
            t0 = time.perf_counter()
            for _ in range(n):
                fn()
            per[name].append((time.perf_counter() - t0) / n / states)
    return {
        name: dict(best_ns=min(per[name]) * 1e9, median_ns=statistics.median(per[name]) * 1e9,
                   inner=inner[name], states=calls[name][1], repeats=repeats)
        for name in calls
    }


def draw(model, floating, n, rng):
    """`n` random states in our layout: q in [-1, 1] per joint coordinate (a free base: a
    position in [-1, 1]^3 and a random unit quaternion [w, x, y, z]), v in [-2, 2], a in [-5, 5]."""
    import numpy as np

    q = rng.uniform(-1.0, 1.0, (n, model.nq))
    if floating == "quaternion":
        quat = rng.normal(size=(n, 4))
        quat /= np.linalg.norm(quat, axis=1)[:, None]
        q[:, 3:7] = quat
    v = rng.uniform(-2.0, 2.0, (n, model.nv))
    a = rng.uniform(-5.0, 5.0, (n, model.nv))
    return q, v, a


def worst(x, ref):
    """The largest difference of each state, relative to that state's largest entry; the worst."""
    import numpy as np

    x, ref = np.atleast_2d(x), np.atleast_2d(ref)
    scale = np.maximum(np.abs(ref).max(axis=1), 1e-300)
    return float((np.abs(x - ref).max(axis=1) / scale).max())


def openmp_facts(pin, threads, model, q, v, a, repeats, min_time):
    """Whether the wheel's Python module uses OpenMP: its libgomp link, its GOMP symbols, and
    `rneaInParallel` on 1 thread against `threads` threads (arm7, the largest batch)."""
    wrap = getattr(sys.modules.get(type(pin.Model()).__module__), "__file__", "") or ""
    links = sh(f"ldd '{wrap}'")
    gomp = re.search(r"^\s*(libgomp\S*) => (\S+)", links, re.M)
    symbols = sh(f"nm -D '{wrap}' | grep -c ' U GOMP_parallel'")
    pool = pin.ModelPool(model, max(threads, 1))
    timed = time_together(
        {str(t): ((lambda t=t: pin.rneaInParallel(t, pool, q, v, a)), q.shape[1]) for t in sorted({1, threads})},
        repeats, min_time,
    )
    per_thread = {t: f["best_ns"] for t, f in timed.items()}
    speedup = per_thread["1"] / per_thread[str(threads)] if threads > 1 else None
    return dict(
        module=os.path.relpath(wrap, ROOT) if wrap.startswith(ROOT) else wrap,
        libgomp=gomp.group(2) if gomp else None,
        gomp_parallel_symbol=symbols.strip() not in ("", "0"),
        rnea_in_parallel_ns_per_state_by_threads=per_thread,
        speedup=speedup,
        states=int(q.shape[1]),
    )


def environment(threads):
    import numpy as np
    import pinocchio as pin

    import articulated

    lscpu = sh("lscpu")
    cpu = re.search(r"Model name:\s*(.*)", lscpu)
    mem = re.search(r"MemTotal:\s*(\d+) kB", open("/proc/meminfo").read())
    commit = sh(f"git -C '{ROOT}' rev-parse --short HEAD")
    dirty = sh(f"git -C '{ROOT}' status --porcelain --untracked-files=no -- . ':!BENCHMARKS.md'")
    return dict(
        cpu=cpu.group(1).strip() if cpu else "?",
        nproc=os.cpu_count(),
        ram=f"{int(mem.group(1)) / 1024 / 1024:.0f} GiB" if mem else "?",
        kernel=platform.release(),
        python=platform.python_version(),
        numpy=np.__version__,
        pinocchio=pin.__version__,
        articulated=articulated.__version__,
        rustc=sh("rustc --version"),
        rustflags=os.environ.get("RUSTFLAGS", ""),
        threads=threads,
        commit=commit + (" (with uncommitted changes)" if dirty else ""),
        date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        load=open("/proc/loadavg").read().split()[:3],
    )


def cpu_clock():
    """(the machine's busy seconds, all seconds, over all CPUs; this process's CPU seconds)."""
    ticks = os.sysconf("SC_CLK_TCK")
    fields = [int(x) for x in open("/proc/stat").readline().split()[1:9]]
    idle = fields[3] + fields[4]
    mine = os.times()
    return (sum(fields) - idle) / ticks, sum(fields) / ticks, mine.user + mine.system


def parse_caps(text):
    caps = {}
    for item in filter(None, (text or "").split(",")):
        name, _, n = item.partition("=")
        caps[name] = int(n)
    return caps


def measure(args):
    threads = args.threads
    import numpy as np
    import pinocchio as pin

    import articulated

    env = environment(threads)
    clock0 = cpu_clock()
    log(f"threads {threads} (RAYON_NUM_THREADS={os.environ['RAYON_NUM_THREADS']}); "
        f"batches {args.batches}; repeats {args.repeats}")
    interp_caps = parse_caps(args.interp_cap)
    top = max(args.batches)
    results, checks, shapes, omp = {}, {}, {}, None
    for name, urdf, floating in MODELS:
        if args.models and name not in args.models:
            continue
        path = os.path.join(ROOT, urdf)
        ours = articulated.Model.load(path, floating=floating)
        log(f"{name}: generating (cached in {args.cache_dir})")
        gen = articulated.generate(path, outputs=[o for o, _, _ in OUTPUTS], floating=floating,
                                   cache_dir=args.cache_dir, verbose=False)
        theirs = (pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating
                  else pin.buildModelFromUrdf(path))
        data = theirs.createData()
        pool = pin.ModelPool(theirs, threads)
        shapes[name] = dict(nq=ours.nq, nv=ours.nv, urdf=urdf, floating=floating)

        rng = np.random.default_rng(SEED)
        q, v, a = draw(ours, floating, top, rng)
        tau = ours.inverse_dynamics(q, v, a)  # the forward dynamics' input: a comes back
        qp = np.ascontiguousarray(ours.to_pinocchio_q(q))
        vp = np.ascontiguousarray(ours.to_pinocchio_v(v))
        ap = np.ascontiguousarray(ours.to_pinocchio_v(a))
        taup = np.ascontiguousarray(ours.to_pinocchio_v(tau))
        ins = {"inverse_dynamics": (q, v, a), "forward_dynamics": (q, v, tau)}
        ins_pin = {"inverse_dynamics": (qp, vp, ap), "forward_dynamics": (qp, vp, taup)}

        # Values: every method at the first CHECK_STATES states against pin.rnea / pin.aba.
        checks[name] = {}
        k = min(CHECK_STATES, top)
        for out, fn, par in OUTPUTS:
            x, y, z = (w_[:k] for w_ in ins[out])
            px, py, pz = (w_[:k] for w_ in ins_pin[out])
            ref = np.array([getattr(pin, fn)(theirs, data, px[i], py[i], pz[i]) for i in range(k)])
            to_pin = ours.to_pinocchio_v
            got = {
                "interpreted": to_pin(getattr(ours, out)(x, y, z)),
                "generated": to_pin(getattr(gen, out)(x, y, z)),
                "pin_parallel": getattr(pin, par)(threads, pool, px.T, py.T, pz.T).T,
            }
            errs = {m: worst(g, ref) for m, g in got.items()}
            checks[name][out] = errs
            log(f"{name} {out}: worst relative difference from pin.{fn}: "
                + ", ".join(f"{m} {e:.1e}" for m, e in errs.items()))
            bad = {m: e for m, e in errs.items() if not e <= TOL}
            if bad:
                raise SystemExit(f"{name} {out}: values differ from pin.{fn} beyond {TOL:g}: {bad}")

        if omp is None:
            log(f"{name}: rneaInParallel at 1 and {threads} threads (OpenMP?)")
            omp = openmp_facts(pin, threads, theirs, qp.T, vp.T, ap.T, args.repeats, args.min_time)

        results[name] = {}
        for out, fn, par in OUTPUTS:
            results[name][out] = {}
            pfn, pparallel = getattr(pin, fn), getattr(pin, par)
            for b in args.batches:
                x, y, z = (w_[:b] for w_ in ins[out])
                px, py, pz = (w_[:b] for w_ in ins_pin[out])
                n_int = min(b, interp_caps.get(name, b))
                xi, yi, zi = x[:n_int], y[:n_int], z[:n_int]
                call, gcall = getattr(ours, out), getattr(gen, out)
                n_loop = min(b, args.loop_cap)
                rows = list(zip(list(px[:n_loop]), list(py[:n_loop]), list(pz[:n_loop])))

                def loop(rows=rows, pfn=pfn):
                    for qi, vi, zi_ in rows:
                        pfn(theirs, data, qi, vi, zi_)

                # (nq, B) and (nv, B): the transposes of the row-major batches (column-major).
                pxt, pyt, pzt = px.T, py.T, pz.T
                row = time_together({
                    "interpreted": ((lambda: call(xi, yi, zi)), n_int),
                    "generated": ((lambda: gcall(x, y, z)), b),
                    "pin_loop": (loop, n_loop),
                    "pin_parallel": ((lambda: pparallel(threads, pool, pxt, pyt, pzt)), b),
                }, args.repeats, args.min_time)
                results[name][out][str(b)] = row
                log(f"{name} {out} B={b}: " + ", ".join(
                    f"{m} {row[m]['best_ns']:.0f} ns" + (f" ({row[m]['states']} states)" if row[m]['states'] != b else "")
                    for m in METHODS))
    env["load_end"] = open("/proc/loadavg").read().split()[:3]
    clock1 = cpu_clock()
    # What other processes took of the machine while this ran (a shared VM): busy CPU time
    # not ours, over all the CPUs' time.
    env["others_cpu_share"] = max(0.0, ((clock1[0] - clock0[0]) - (clock1[2] - clock0[2]))
                                  / max(clock1[1] - clock0[1], 1e-9))
    return dict(
        env=env, models=shapes, batches=args.batches, repeats=args.repeats,
        min_time=args.min_time, loop_cap=args.loop_cap, interp_caps=interp_caps,
        tolerance=TOL, checks=checks, openmp=omp, results=results,
    )


def fmt_ns(x):
    return "–" if x is None else (f"{x:,.0f}" if x >= 100 else f"{x:.1f}")


def fmt_ratio(x):
    return "–" if x is None else f"{x:.1f}×"


def section(d):
    """The section "From Python" of BENCHMARKS.md, as lines, from `measure`'s figures."""
    env, omp = d["env"], d["openmp"]
    t = env["threads"]
    L = []
    w = L.append
    w("## From Python")
    w("")
    w("Nanoseconds per state from Python (`bench/python/timing.py`, run by `run.py`; `run.py")
    w("--python-only` reruns only this section), for batches of B states: **ours, interpreted** is")
    w("`articulated.Model.load(path).inverse_dynamics(Q, V, A)` on `(B, n)` arrays (the reference,")
    w("rayon over the states with the GIL released); **ours, generated** the same call on")
    w("`articulated.generate(path, outputs=[\"inverse_dynamics\", \"forward_dynamics\"])` (its")
    w("`_batch` functions, four states per SIMD vector, on groups of 256 states over rayon's threads;")
    w("C-ordered inputs read where they lie, results written into arrays allocated once; built by")
    w(f"`generate()` with cargo for the default target{', RUSTFLAGS ' + repr(env['rustflags']) if env['rustflags'] else ''});")
    w("**Pinocchio, Python loop** is `pin.rnea(model, data, q, v, a)` (`pin.aba`) called state by")
    w("state from a Python `for` loop over the rows; **Pinocchio, in parallel** is")
    w(f"`pin.rneaInParallel({t}, pool, Q, V, A)` (`pin.abaInParallel`) on a `pin.ModelPool` and")
    w("`(nq, B)` arrays (column-major views of the same batches). Both sides use")
    w(f"**{t} threads** (`RAYON_NUM_THREADS={t}`; Pinocchio's `num_threads` argument), the whole")
    w("machine. Every call takes numpy arrays and returns a new one; the same random states")
    w("for every method (converted to Pinocchio's layout with `to_pinocchio_q`/`to_pinocchio_v`),")
    w(f"each method's values at the first {CHECK_STATES} states checked against `pin.rnea`/`pin.aba`")
    w(f"to {d['tolerance']:g} relative before any timing. A figure is the fastest of {d['repeats']} rounds, each")
    w("timing the four methods one after the other in a rotating order (a timing calls as many times")
    w(f"as fill {d['min_time'] * 1e3:g} ms; one warm-up call before).")
    w("Ratios: Pinocchio over ours, generated (above 1: ours faster).")
    w("")
    gomp = omp["libgomp"]
    speed = omp["speedup"]
    by = omp["rnea_in_parallel_ns_per_state_by_threads"]
    w(f"The wheel (`pin` {env['pinocchio']}) is built with OpenMP: "
      + ("its Python module links " + f"`{os.path.basename(gomp)}`" if gomp else "its Python module links no libgomp")
      + (" and calls `GOMP_parallel`" if omp["gomp_parallel_symbol"] else "")
      + (f"; `rneaInParallel` on arm7 ({omp['states']:,} states) takes "
         + " and ".join(f"{fmt_ns(by[k])} ns per state at {k} thread{'s' if k != '1' else ''}" for k in sorted(by, key=int))
         + f" ({fmt_ratio(speed)})." if speed else "."))
    w("")
    w(f"- {env['cpu']}, `nproc` {env['nproc']}, Linux {env['kernel']}; Python {env['python']}, numpy "
      f"{env['numpy']}, `articulated` {env['articulated']}, {env['rustc']}")
    w(f"- measured {env['date']} at commit `{env['commit']}`; load average at the start "
      f"{' '.join(env['load'])}, at the end {' '.join(env.get('load_end', ['?']))}"
      + (f"; other processes took {env['others_cpu_share']:.0%} of the CPUs' time during the run"
         if "others_cpu_share" in env else ""))
    for name, shape in d["models"].items():
        res = d["results"][name]
        w("")
        w(f"### {name} from Python ({'floating base, ' if shape['floating'] else ''}nq {shape['nq']}, "
          f"nv {shape['nv']}; `{shape['urdf']}`)")
        w("")
        w(f"| output | states per call | ours, interpreted (ns per state) | ours, generated (ns per state) | "
          f"Pinocchio, Python loop (ns per state) | Pinocchio, in parallel, {t} threads (ns per state) | "
          f"Pinocchio loop / ours generated | Pinocchio in parallel / ours generated |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|")
        notes = []
        for out, fn, par in OUTPUTS:
            for b in d["batches"]:
                row = res[out][str(b)]
                cells = []
                for m in METHODS:
                    cell = fmt_ns(row[m]["best_ns"])
                    if row[m]["states"] != b:
                        cell += "*"
                        notes.append((m, b, row[m]["states"]))
                    cells.append(cell)
                g = row["generated"]["best_ns"]
                w(f"| `{out}` (`{fn}`, `{par}`) | {b:,} | " + " | ".join(cells) + " | "
                  f"{fmt_ratio(row['pin_loop']['best_ns'] / g)} | {fmt_ratio(row['pin_parallel']['best_ns'] / g)} |")
        w("")
        marked = sorted({(m, b, n) for m, b, n in notes})
        if marked:
            label = {"interpreted": "the interpreter", "pin_loop": "the Python loop"}
            w("\\* timed on fewer states, per state: "
              + "; ".join(f"{label.get(m, m)} at B = {b:,} on the first {n:,}" for m, b, n in marked) + ".")
            w("")
        c = d["checks"][name]
        w("Values at the first states against Pinocchio's (worst relative difference): "
          + "; ".join(f"{out} " + ", ".join(f"{m} {e:.1e}" for m, e in errs.items()) for out, errs in c.items())
          + ".")
    return L


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="the JSON file to write")
    ap.add_argument("--batches", default="1,100,100000", help="states per call (comma-separated)")
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--min-time", type=float, default=0.02, help="seconds per repeat, at least")
    ap.add_argument("--threads", type=int, default=None,
                    help="threads of both sides (default: RAYON_NUM_THREADS, else os.cpu_count())")
    ap.add_argument("--loop-cap", type=int, default=10000, help="states of the timed Python loop, at most")
    ap.add_argument("--interp-cap", default="humanoid=10000",
                    help="MODEL=N,...: states of the timed interpreter call, at most")
    ap.add_argument("--models", default=None, help="comma-separated subset of arm7,humanoid")
    ap.add_argument("--cache-dir", default=os.path.join(ROOT, "target", "pycache"),
                    help="generate()'s cache (default target/pycache)")
    args = ap.parse_args()
    args.batches = [int(b) for b in args.batches.split(",")]
    args.models = args.models.split(",") if args.models else None
    threads = args.threads or int(os.environ.get("RAYON_NUM_THREADS") or 0) or os.cpu_count()
    args.threads = threads
    # Before `articulated` (the extension and every generated module) starts rayon's pool.
    os.environ["RAYON_NUM_THREADS"] = str(threads)
    d = measure(args)
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(d, f, indent=1)
    os.replace(tmp, args.out)
    log(f"wrote {args.out}; other processes took {d['env']['others_cpu_share']:.0%} of the CPUs' time meanwhile")
    print("\n".join(section(d)))


if __name__ == "__main__":
    main()
