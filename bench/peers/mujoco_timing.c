// MuJoCo's side of the comparison (bench/peers/run.sh builds it, run.py runs it), through
// MuJoCo's C API from the pip wheel's libmujoco.
//
//   mujoco_timing --mjb FILE --states FILE --values MODEL
//   mujoco_timing --mjb FILE --states FILE --time [--batches N] [--batch-ms T] MODEL
//   mujoco_timing --mjb FILE --states FILE --calls K MODEL OUTPUT
//
// The model is the binary .mjb run.py compiles from the URDF (exact doubles; contacts,
// constraints, limits, springs, dampers and actuation disabled). The states file holds
// "nq nv count", then per state the lines qpos, qvel, qacc, qfrc in MuJoCo's convention (a
// free joint's linear velocity in the world frame); run.py converts them from the common
// states. Each call first copies its inputs into mjData (qpos, and qvel, qacc or
// qfrc_applied as needed), which is how MuJoCo takes them. The outputs, each the smallest set
// of pipeline stages that yields the quantity:
//
//   mass_matrix                        mj_kinematics, mj_comPos, mj_crb (M in MuJoCo's sparse
//                                      storage, d->M)
//   mass_matrix_dense                  the same, then mj_fullM into a dense nv x nv array
//   nonlinear_effects                  mj_kinematics, mj_comPos, mj_comVel,
//                                      mj_rne(flg_acc = 0) into d->qfrc_bias
//   gravity                            mj_kinematics, mj_comPos, mj_rne(flg_acc = 0) with zero
//                                      velocity (cvel and cdof_dot zeroed once, outside the loop)
//   inverse_dynamics                   mj_kinematics, mj_comPos, mj_comVel, mj_rne(flg_acc = 1)
//   forward_dynamics                   mj_kinematics, mj_comPos, mj_crb, mj_factorM, mj_comVel,
//                                      mj_rne(flg_acc = 0), qfrc_applied - qfrc_bias, mj_solveM
//   mass_matrix_and_nonlinear_effects  mj_kinematics, mj_comPos, mj_crb, mj_comVel,
//                                      mj_rne(flg_acc = 0)
//   mj_forward                         the whole mj_forward (what a simulation step calls)
//   mj_inverse                         the whole mj_inverse
//
// Timing as in the other programs: the states cycled, an empty asm statement with a memory
// clobber after each call, --batches batches of about --batch-ms (default 200 of 1 ms), the
// fastest and the median batch in ns per call, as JSON.

#define _POSIX_C_SOURCE 199309L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mujoco/mujoco.h>

static const char *USAGE =
    "usage: mujoco_timing --mjb FILE --states FILE --values MODEL\n"
    "       mujoco_timing --mjb FILE --states FILE --time [--batches N] [--batch-ms T] MODEL\n"
    "       mujoco_timing --mjb FILE --states FILE --calls K MODEL OUTPUT\n";

static void die(const char *what) {
  fprintf(stderr, "mujoco_timing: %s\n", what);
  exit(1);
}

// Tells the compiler that memory (the results in d, the inputs) is read and written here.
static inline void clobber(void) { __asm__ volatile("" ::: "memory"); }

// The states: count blocks of qpos (nq), qvel, qacc, qfrc (nv each).
typedef struct {
  int nq, nv, count;
  double *qpos, *qvel, *qacc, *qfrc;
} States;

static States read_states(const char *path, const mjModel *m) {
  FILE *f = fopen(path, "r");
  if (!f) die("cannot open the states file");
  States s;
  if (fscanf(f, "%d %d %d", &s.nq, &s.nv, &s.count) != 3) die("bad states header");
  if (s.nq != m->nq || s.nv != m->nv) die("the states' nq/nv are not the model's");
  if (s.count <= 0 || (s.count & (s.count - 1)) != 0) die("the number of states must be a power of two");
  s.qpos = malloc(sizeof(double) * s.nq * s.count);
  s.qvel = malloc(sizeof(double) * s.nv * s.count);
  s.qacc = malloc(sizeof(double) * s.nv * s.count);
  s.qfrc = malloc(sizeof(double) * s.nv * s.count);
  for (int k = 0; k < s.count; ++k) {
    double *blocks[4] = {s.qpos + k * s.nq, s.qvel + k * s.nv, s.qacc + k * s.nv, s.qfrc + k * s.nv};
    int sizes[4] = {s.nq, s.nv, s.nv, s.nv};
    for (int b = 0; b < 4; ++b)
      for (int i = 0; i < sizes[b]; ++i)
        if (fscanf(f, "%lf", &blocks[b][i]) != 1) die("the states file is too short");
  }
  fclose(f);
  return s;
}

// Everything one call needs.
typedef struct {
  const mjModel *m;
  mjData *d;
  const States *s;
  double *dense;  // nv x nv, for mass_matrix_dense
  double *tmp;    // nv, for forward_dynamics
} Ctx;

enum Output {
  MASS_MATRIX,
  MASS_MATRIX_DENSE,
  NONLINEAR_EFFECTS,
  GRAVITY,
  INVERSE_DYNAMICS,
  FORWARD_DYNAMICS,
  MASS_MATRIX_AND_NONLINEAR_EFFECTS,
  MJ_FORWARD,
  MJ_INVERSE,
  N_OUTPUTS
};

static const char *NAMES[N_OUTPUTS] = {
    "mass_matrix",      "mass_matrix_dense", "nonlinear_effects",
    "gravity",          "inverse_dynamics",  "forward_dynamics",
    "mass_matrix_and_nonlinear_effects", "mj_forward", "mj_inverse"};

static inline void set_qpos(Ctx *c, int k) {
  memcpy(c->d->qpos, c->s->qpos + k * c->s->nq, sizeof(double) * c->s->nq);
}
static inline void set_nv(double *dst, const double *all, int k, int nv) {
  memcpy(dst, all + k * nv, sizeof(double) * nv);
}

// One call of output o on state k. The switch costs a few cycles per call, next to MuJoCo's
// calls into its shared library.
static __attribute__((noinline)) void call(Ctx *c, enum Output o, int k) {
  const mjModel *m = c->m;
  mjData *d = c->d;
  const int nv = c->s->nv;
  switch (o) {
    case MASS_MATRIX:
      set_qpos(c, k);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_crb(m, d);
      break;
    case MASS_MATRIX_DENSE:
      set_qpos(c, k);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_crb(m, d);
      mj_fullM(m, d, c->dense);
      break;
    case NONLINEAR_EFFECTS:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_comVel(m, d);
      mj_rne(m, d, 0, d->qfrc_bias);
      break;
    case GRAVITY:
      set_qpos(c, k);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_rne(m, d, 0, d->qfrc_bias);
      break;
    case INVERSE_DYNAMICS:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      set_nv(d->qacc, c->s->qacc, k, nv);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_comVel(m, d);
      mj_rne(m, d, 1, d->qfrc_inverse);
      break;
    case FORWARD_DYNAMICS:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      set_nv(d->qfrc_applied, c->s->qfrc, k, nv);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_crb(m, d);
      mj_factorM(m, d);
      mj_comVel(m, d);
      mj_rne(m, d, 0, d->qfrc_bias);
      mju_sub(c->tmp, d->qfrc_applied, d->qfrc_bias, nv);
      mj_solveM(m, d, d->qacc, c->tmp, 1);
      break;
    case MASS_MATRIX_AND_NONLINEAR_EFFECTS:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_crb(m, d);
      mj_comVel(m, d);
      mj_rne(m, d, 0, d->qfrc_bias);
      break;
    case MJ_FORWARD:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      set_nv(d->qfrc_applied, c->s->qfrc, k, nv);
      mj_forward(m, d);
      break;
    case MJ_INVERSE:
      set_qpos(c, k);
      set_nv(d->qvel, c->s->qvel, k, nv);
      set_nv(d->qacc, c->s->qacc, k, nv);
      mj_inverse(m, d);
      break;
    default:
      break;
  }
}

// Zero velocity terms for the gravity output: qvel = 0, then cvel and cdof_dot from mj_comVel
// are zero at any configuration, and the gravity loop never recomputes them.
static void prepare(Ctx *c, enum Output o) {
  if (o == GRAVITY) {
    mju_zero(c->d->qvel, c->m->nv);
    set_qpos(c, 0);
    mj_kinematics(c->m, c->d);
    mj_comPos(c->m, c->d);
    mj_comVel(c->m, c->d);
  }
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// Runs n calls of o, the states cycled, and returns the seconds taken.
static double batch(Ctx *c, enum Output o, long n) {
  const int mask = c->s->count - 1;
  double start = now();
  for (long i = 0; i < n; ++i) {
    call(c, o, (int)(i & mask));
    clobber();
  }
  return now() - start;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static void print_vector(const char *name, const double *x, int n) {
  printf("\"%s\": [", name);
  for (int i = 0; i < n; ++i) printf("%s%.17g", i ? ", " : "", x[i]);
  printf("]");
}

static void print_matrix(const char *name, const double *x, int n) {
  printf("\"%s\": [", name);
  for (int r = 0; r < n; ++r) {
    printf("%s[", r ? ", " : "");
    for (int i = 0; i < n; ++i) printf("%s%.17g", i ? ", " : "", x[r * n + i]);
    printf("]");
  }
  printf("]");
}

// The outputs at state 0, in MuJoCo's convention, as JSON.
static void values(Ctx *c) {
  const int nv = c->s->nv;
  printf("{");
  call(c, MASS_MATRIX_DENSE, 0);
  print_matrix("mass_matrix", c->dense, nv);
  printf(", ");
  call(c, NONLINEAR_EFFECTS, 0);
  print_vector("nonlinear_effects", c->d->qfrc_bias, nv);
  printf(", ");
  prepare(c, GRAVITY);
  call(c, GRAVITY, 0);
  print_vector("gravity", c->d->qfrc_bias, nv);
  printf(", ");
  call(c, INVERSE_DYNAMICS, 0);
  print_vector("inverse_dynamics", c->d->qfrc_inverse, nv);
  printf(", ");
  call(c, FORWARD_DYNAMICS, 0);
  print_vector("forward_dynamics", c->d->qacc, nv);
  printf(", ");
  call(c, MJ_FORWARD, 0);
  print_vector("mj_forward", c->d->qacc, nv);
  printf(", ");
  call(c, MJ_INVERSE, 0);
  print_vector("mj_inverse", c->d->qfrc_inverse, nv);
  printf("}\n");
}

int main(int argc, char **argv) {
  const char *mjb = NULL, *states_path = NULL, *rest[2] = {NULL, NULL};
  int do_values = 0, do_time = 0, do_calls = 0, nrest = 0, batches = 200;
  long calls = 0;
  double batch_s = 1e-3;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    int more = i + 1 < argc;
    if (!strcmp(a, "--mjb") && more) mjb = argv[++i];
    else if (!strcmp(a, "--states") && more) states_path = argv[++i];
    else if (!strcmp(a, "--values")) do_values = 1;
    else if (!strcmp(a, "--time")) do_time = 1;
    else if (!strcmp(a, "--calls") && more) do_calls = 1, calls = atol(argv[++i]);
    else if (!strcmp(a, "--batches") && more) batches = atoi(argv[++i]);
    else if (!strcmp(a, "--batch-ms") && more) batch_s = atof(argv[++i]) * 1e-3;
    else if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      fputs(USAGE, stdout);
      return 0;
    } else if (nrest < 2) rest[nrest++] = a;
    else die(USAGE);
  }
  if (!mjb || !states_path || do_values + do_time + do_calls != 1 || nrest != (do_calls ? 2 : 1))
    die(USAGE);
  if (batches < 1) batches = 1;

  mjModel *m = mj_loadModel(mjb, NULL);
  if (!m) die("cannot load the .mjb model");
  mjData *d = mj_makeData(m);
  States s = read_states(states_path, m);
  Ctx c = {m, d, &s, malloc(sizeof(double) * m->nv * m->nv), malloc(sizeof(double) * m->nv)};

  if (do_values) {
    values(&c);
    return 0;
  }
  if (do_calls) {
    for (int o = 0; o < N_OUTPUTS; ++o)
      if (!strcmp(rest[1], NAMES[o])) {
        prepare(&c, (enum Output)o);
        batch(&c, (enum Output)o, calls);
        return 0;
      }
    die("unknown output");
  }
  double *ns = malloc(sizeof(double) * batches);
  printf("{");
  for (int o = 0; o < N_OUTPUTS; ++o) {
    prepare(&c, (enum Output)o);
    long n = 16;
    for (;;) {  // calibrate: n calls take about batch_s
      double t = batch(&c, (enum Output)o, n);
      if (t >= batch_s / 4 || n >= (1L << 30)) {
        n = (long)(batch_s / (t / (double)n));
        if (n < 16) n = 16;
        break;
      }
      n *= 2;
    }
    for (int b = 0; b < batches; ++b) ns[b] = batch(&c, (enum Output)o, n) * 1e9 / (double)n;
    qsort(ns, batches, sizeof(double), cmp);
    printf("%s\"%s\": {\"min\": %.3f, \"median\": %.3f, \"calls_per_batch\": %ld}", o ? ", " : "",
           NAMES[o], ns[0], ns[batches / 2], n);
  }
  printf("}\n");
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
