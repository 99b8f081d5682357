// Pinocchio's side of the comparison (bench/peers/run.sh builds it, run.py runs it).
//
//   pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states FILE --values MODEL
//   pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states FILE --time [--batches N] [--batch-ms T] MODEL
//   pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states FILE --calls K MODEL OUTPUT
//
// The model comes from pinocchio::urdf::buildModel (with a JointModelFreeFlyer root for
// --floating), gravity (0, 0, -9.81). The states file holds "nq nv count", then per state the
// lines q, v, a, tau in Pinocchio's convention. Each output is what a user calls:
//
//   mass_matrix                        crba(model, data, q)  (default LOCAL convention; fills
//                                      the upper triangle of data.M only)
//   mass_matrix_world                  crba(model, data, q, Convention::WORLD)
//   nonlinear_effects                  nonLinearEffects(model, data, q, v)
//   gravity                            computeGeneralizedGravity(model, data, q)
//   inverse_dynamics                   rnea(model, data, q, v, a)
//   forward_dynamics                   aba(model, data, q, v, tau)  (default LOCAL convention)
//   forward_dynamics_world             aba(model, data, q, v, tau, Convention::WORLD)
//   mass_matrix_and_nonlinear_effects  crba(model, data, q) then nonLinearEffects(model, data, q, v)
//
// and the quantities of the whole system:
//
//   center_of_mass                     centerOfMass(model, data, q, false)  (data.com[0]; false:
//                                      not the centres of mass of the subtrees)
//   center_of_mass_velocity            centerOfMass(model, data, q, v, false)  (data.vcom[0])
//   center_of_mass_jacobian            jacobianCenterOfMass(model, data, q, false)  (data.Jcom)
//   centroidal_momentum                computeCentroidalMomentum(model, data, q, v)  (data.hg)
//   centroidal_momentum_matrix         ccrba(model, data, q, v)  (data.Ag; computes more than
//                                      A_G: also h_G = A_G v and the centroidal inertia Ig)
//   centroidal_map                     computeCentroidalMap(model, data, q)  (data.Ag alone)
//   kinetic_energy                     computeKineticEnergy(model, data, q, v)
//   potential_energy                   computePotentialEnergy(model, data, q)
//   coriolis_matrix                    computeCoriolisMatrix(model, data, q, v)  (data.C)
//
// and the analytical derivatives:
//
//   inverse_dynamics_derivatives       computeRNEADerivatives(model, data, q, v, a)  (data.dtau_dq,
//                                      data.dtau_dv; also fills the upper triangle of data.M)
//   forward_dynamics_derivatives       computeABADerivatives(model, data, q, v, tau)  (data.ddq_dq,
//                                      data.ddq_dv, the upper triangle of data.Minv)
//   mass_matrix_inverse                computeMinverse(model, data, q)  (the upper triangle of
//                                      data.Minv)
//
// and, with --frames (URDF links, Pinocchio's BODY frames, comma-separated), for those frames
// only, all of them in each call:
//
//   frame_placements                   forwardKinematics(model, data, q), then
//                                      updateFramePlacement(model, data, id) per frame
//                                      (data.oMf[id]; not framesForwardKinematics, which
//                                      updates every frame of the model)
//   frame_jacobians_local_world_aligned
//                                      computeFrameJacobian(model, data, q, id,
//                                      LOCAL_WORLD_ALIGNED, J) per frame (the kinematics of
//                                      the frame's support only)
//   frame_jacobians_local_world_aligned_joint_jacobians
//                                      computeJointJacobians(model, data, q), then
//                                      getFrameJacobian(model, data, id, LOCAL_WORLD_ALIGNED, J)
//                                      per frame (the whole tree once: for several frames)
//   frame_jacobian_time_variations_local_world_aligned
//                                      computeJointJacobiansTimeVariation(model, data, q, v),
//                                      then getFrameJacobianTimeVariation(model, data, id,
//                                      LOCAL_WORLD_ALIGNED, dJ) per frame
//
// Each frame has its own J and dJ (6 x nv, zeroed once), as a user keeps them.
//
// and, with --contacts (URDF links, Pinocchio's BODY frames, comma-separated), each a
// six-dimensional contact (CONTACT_6D in LOCAL: the link welded where it is), all of them held
// in each call:
//
//   constrained_forward_dynamics       constraintDynamics(model, data, q, v, tau, contact_models,
//                                      contact_datas, settings)  (data.ddq, and each contact's
//                                      wrench in contact_datas[k].contact_force), with
//                                      ProximalSettings(1e-12, mu = 0, max_iter = 1): no
//                                      regularization, one solve of the KKT system, the exact
//                                      solution (the defaults but for the accuracy, which one
//                                      iteration never reaches: it reads the iterate's change)
//
//   constrained_forward_dynamics_derivatives
//                                      constraintDynamics as above, then
//                                      computeConstraintDynamicsDerivatives(model, data,
//                                      contact_models, contact_datas, settings): q̈ and the
//                                      forces, and their derivatives with respect to q, v and tau
//                                      (data.ddq_dq, ddq_dv, ddq_dtau, dlambda_dq, dlambda_dv,
//                                      dlambda_dtau), which need the solution of the first call
//
// The contact models are built once, as make_pinocchio_constraints.py builds them:
// RigidConstraintModel(CONTACT_6D, model, frame.parentJoint, frame.placement, 0, identity,
// LOCAL) (joint 2 the universe; its placement, the reference, plays no part without Baumgarte
// gains), then initConstraintDynamics once, outside the timing.
//
// In --values mode these are given in articulated's conventions: h_G and the rows of A_G
// angular first (Pinocchio's are linear first), and so the rows of the frames' J and dJ and each
// contact's wrench ([n; f], in the contact frame; Pinocchio's contact_force is [f; n]).
//
// A timed call cycles through the states; the inputs are Eigen::Ref views made once
// (constraintDynamics: the VectorXd they view, the argument type the wheel's library
// instantiates it for), and an empty asm statement with a memory clobber after each call makes the compiler assume the
// result (in data) is read and the inputs may have changed. Each output: --batches batches of
// about --batch-ms (default 200 of 1 ms), the fastest and the median batch, ns per call, as JSON.
//
// Built twice by run.sh: with the algorithms' templates compiled here (-O3 -march=x86-64-v3),
// and with PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION, which makes these calls go to the wheel's
// prebuilt libpinocchio_default (what a CMake user of the pinocchio::pinocchio target gets).

// constraintDynamics and its contact models are marked "unsupported" (the API will change): a
// deprecation warning at every use, which this silences.
#define PINOCCHIO_DISABLE_UNSUPPORTED_WARNINGS

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/center-of-mass.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/constrained-dynamics-derivatives.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/energy.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/parsers/urdf.hpp>
#ifdef _OPENMP
#include <omp.h>
#include <pinocchio/algorithm/parallel/aba.hpp>
#include <pinocchio/algorithm/parallel/rnea.hpp>
#endif

namespace {

using Vec = Eigen::VectorXd;
using Ref = Eigen::Ref<const Vec>;

const char *const USAGE =
    "usage: pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states "
    "FILE --values MODEL\n"
    "       pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states "
    "FILE --time [--batches N] [--batch-ms T] MODEL\n"
    "       pinocchio_timing --urdf FILE [--floating] [--frames F,G] [--contacts C,D] --states "
    "FILE --calls K MODEL OUTPUT\n"
    "       pinocchio_timing --urdf FILE [--floating] --states FILE --throughput T1,T2 "
    "[--batch B] [--rounds R] MODEL   (built with -fopenmp)";

// Tells the compiler that memory (the result in data, the inputs) is read and written here.
inline void clobber() { asm volatile("" ::: "memory"); }

struct State {
  Vec q, v, a, tau;
};

// The ids of the BODY frames of the links `names` (comma-separated; empty: none).
std::vector<pinocchio::FrameIndex> body_frames(const pinocchio::Model &model,
                                               const std::string &names) {
  std::vector<pinocchio::FrameIndex> ids;
  size_t start = 0;
  while (start < names.size()) {
    size_t end = names.find(',', start);
    if (end == std::string::npos) end = names.size();
    const std::string name = names.substr(start, end - start);
    if (!model.existFrame(name, pinocchio::BODY))
      throw std::runtime_error("no link (BODY frame) named " + name);
    ids.push_back(model.getFrameId(name, pinocchio::BODY));
    start = end + 1;
  }
  return ids;
}

// The frames of --frames: their ids, and a Jacobian and its rate per frame (zeroed once).
struct Frames {
  std::vector<pinocchio::FrameIndex> ids;
  std::vector<pinocchio::Data::Matrix6x> J, dJ;

  Frames(const pinocchio::Model &model, const std::string &names)
      : ids(body_frames(model, names)) {
    J.assign(ids.size(), pinocchio::Data::Matrix6x::Zero(6, model.nv));
    dJ = J;
  }
};

// The contacts of --contacts: one six-dimensional contact (CONTACT_6D, LOCAL) per link, their
// models and datas, initConstraintDynamics done (the file header).
struct Contacts {
  std::vector<pinocchio::RigidConstraintModel> models;
  std::vector<pinocchio::RigidConstraintData> datas;
  // mu = 0: the exact solve; one iteration (the file header).
  pinocchio::ProximalSettings settings{1e-12, 0.0, 1};

  Contacts(const pinocchio::Model &model, pinocchio::Data &data, const std::string &names) {
    for (auto id : body_frames(model, names)) {
      const auto &frame = model.frames[id];
      models.emplace_back(pinocchio::CONTACT_6D, model, frame.parentJoint, frame.placement, 0,
                          pinocchio::SE3::Identity(), pinocchio::LOCAL);
      models.back().name = frame.name;
    }
    for (const auto &m : models) datas.emplace_back(m);
    if (!models.empty()) pinocchio::initConstraintDynamics(model, data, models, datas);
  }
};

// Reads "nq nv count", then count times q, v, a, tau.
std::vector<State> read_states(const std::string &path, int nq, int nv) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  int fnq = 0, fnv = 0, count = 0;
  in >> fnq >> fnv >> count;
  if (fnq != nq || fnv != nv)
    throw std::runtime_error(path + ": nq/nv do not match the model's " + std::to_string(nq) +
                             "/" + std::to_string(nv));
  if (count <= 0 || (count & (count - 1)) != 0)
    throw std::runtime_error(path + ": the number of states must be a power of two");
  std::vector<State> states(count);
  auto read = [&](Vec &x, int n) {
    x.resize(n);
    for (int i = 0; i < n; ++i)
      if (!(in >> x[i])) throw std::runtime_error(path + ": too short");
  };
  for (auto &s : states) {
    read(s.q, nq);
    read(s.v, nv);
    read(s.a, nv);
    read(s.tau, nv);
  }
  return states;
}

using Clock = std::chrono::steady_clock;

// Runs f on states 0..n (the index is masked by the caller) and returns the seconds taken.
template <class F> __attribute__((noinline)) double batch(F &f, long n) {
  auto start = Clock::now();
  for (long i = 0; i < n; ++i) {
    f(i);
    clobber();
  }
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// How many calls of f take about target seconds.
template <class F> long calibrate(F &f, double target) {
  long n = 16;
  for (;;) {
    double t = batch(f, n);
    if (t >= target / 4 || n >= (1L << 30)) return std::max(16L, long(target / (t / n)));
    n *= 2;
  }
}

struct Runner {
  enum Mode { Time, Calls } mode = Time;
  int batches = 200;
  double batch_s = 1e-3;
  std::string only;  // Calls: the output
  long calls = 0;    // Calls: how many
  bool found = false;
  std::vector<std::string> json;

  template <class F> void operator()(const char *name, F f) {
    if (mode == Calls) {
      if (only != name) return;
      found = true;
      batch(f, calls);
      return;
    }
    long n = calibrate(f, batch_s);
    std::vector<double> ns(batches);
    for (auto &t : ns) t = batch(f, n) * 1e9 / double(n);
    std::sort(ns.begin(), ns.end());
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "\"%s\": {\"min\": %.3f, \"median\": %.3f, \"calls_per_batch\": %ld}", name,
                  ns[0], ns[ns.size() / 2], n);
    json.push_back(buf);
  }
};

// Hands run the closure of every output.
template <class R>
void each_output(const pinocchio::Model &model, pinocchio::Data &data, Frames &frames,
                 Contacts &contacts, const std::vector<State> &states, const std::vector<Ref> &q, const std::vector<Ref> &v, const std::vector<Ref> &a,
                 const std::vector<Ref> &tau, R &run) {
  using pinocchio::Convention;
  const long mask = long(q.size()) - 1;
  run("mass_matrix", [&](long i) { pinocchio::crba(model, data, q[i & mask]); });
  run("mass_matrix_world",
      [&](long i) { pinocchio::crba(model, data, q[i & mask], Convention::WORLD); });
  run("nonlinear_effects",
      [&](long i) { pinocchio::nonLinearEffects(model, data, q[i & mask], v[i & mask]); });
  run("gravity", [&](long i) { pinocchio::computeGeneralizedGravity(model, data, q[i & mask]); });
  run("inverse_dynamics",
      [&](long i) { pinocchio::rnea(model, data, q[i & mask], v[i & mask], a[i & mask]); });
  run("forward_dynamics",
      [&](long i) { pinocchio::aba(model, data, q[i & mask], v[i & mask], tau[i & mask]); });
  run("forward_dynamics_world", [&](long i) {
    pinocchio::aba(model, data, q[i & mask], v[i & mask], tau[i & mask], Convention::WORLD);
  });
  run("mass_matrix_and_nonlinear_effects", [&](long i) {
    pinocchio::crba(model, data, q[i & mask]);
    pinocchio::nonLinearEffects(model, data, q[i & mask], v[i & mask]);
  });
  run("center_of_mass", [&](long i) { pinocchio::centerOfMass(model, data, q[i & mask], false); });
  run("center_of_mass_velocity",
      [&](long i) { pinocchio::centerOfMass(model, data, q[i & mask], v[i & mask], false); });
  run("center_of_mass_jacobian",
      [&](long i) { pinocchio::jacobianCenterOfMass(model, data, q[i & mask], false); });
  run("centroidal_momentum", [&](long i) {
    pinocchio::computeCentroidalMomentum(model, data, q[i & mask], v[i & mask]);
  });
  run("centroidal_momentum_matrix",
      [&](long i) { pinocchio::ccrba(model, data, q[i & mask], v[i & mask]); });
  run("centroidal_map", [&](long i) { pinocchio::computeCentroidalMap(model, data, q[i & mask]); });
  // The energies return a scalar (also stored in data): kept by the clobber through data.
  run("kinetic_energy",
      [&](long i) { pinocchio::computeKineticEnergy(model, data, q[i & mask], v[i & mask]); });
  run("potential_energy",
      [&](long i) { pinocchio::computePotentialEnergy(model, data, q[i & mask]); });
  run("coriolis_matrix", [&](long i) {
    pinocchio::computeCoriolisMatrix(model, data, q[i & mask], v[i & mask]);
  });
  run("inverse_dynamics_derivatives", [&](long i) {
    pinocchio::computeRNEADerivatives(model, data, q[i & mask], v[i & mask], a[i & mask]);
  });
  run("forward_dynamics_derivatives", [&](long i) {
    pinocchio::computeABADerivatives(model, data, q[i & mask], v[i & mask], tau[i & mask]);
  });
  run("mass_matrix_inverse", [&](long i) { pinocchio::computeMinverse(model, data, q[i & mask]); });
  if (!contacts.models.empty()) {
    // The inputs as the VectorXd the views look at: the wheel's library instantiates
    // constraintDynamics for VectorXd arguments (not for Ref views, as it does the others).
    run("constrained_forward_dynamics", [&](long i) {
      const State &s = states[i & mask];
      pinocchio::constraintDynamics(model, data, s.q, s.v, s.tau, contacts.models, contacts.datas,
                                    contacts.settings);
    });
    // The derivatives need the solution at the state: constraintDynamics first, as a user calls
    // them (the file header).
    run("constrained_forward_dynamics_derivatives", [&](long i) {
      const State &s = states[i & mask];
      pinocchio::constraintDynamics(model, data, s.q, s.v, s.tau, contacts.models, contacts.datas,
                                    contacts.settings);
      pinocchio::computeConstraintDynamicsDerivatives(model, data, contacts.models,
                                                      contacts.datas, contacts.settings);
    });
  }
  if (frames.ids.empty()) return;
  using pinocchio::LOCAL_WORLD_ALIGNED;
  const auto &ids = frames.ids;
  auto &J = frames.J;
  auto &dJ = frames.dJ;
  run("frame_placements", [&](long i) {
    pinocchio::forwardKinematics(model, data, q[i & mask]);
    for (auto id : ids) pinocchio::updateFramePlacement(model, data, id);
  });
  run("frame_jacobians_local_world_aligned", [&](long i) {
    for (size_t k = 0; k < ids.size(); ++k)
      pinocchio::computeFrameJacobian(model, data, q[i & mask], ids[k], LOCAL_WORLD_ALIGNED, J[k]);
  });
  run("frame_jacobians_local_world_aligned_joint_jacobians", [&](long i) {
    pinocchio::computeJointJacobians(model, data, q[i & mask]);
    for (size_t k = 0; k < ids.size(); ++k)
      pinocchio::getFrameJacobian(model, data, ids[k], LOCAL_WORLD_ALIGNED, J[k]);
  });
  run("frame_jacobian_time_variations_local_world_aligned", [&](long i) {
    pinocchio::computeJointJacobiansTimeVariation(model, data, q[i & mask], v[i & mask]);
    for (size_t k = 0; k < ids.size(); ++k)
      pinocchio::getFrameJacobianTimeVariation(model, data, ids[k], LOCAL_WORLD_ALIGNED, dJ[k]);
  });
}

std::string json_vector(const Vec &x) {
  std::string s = "[";
  char buf[32];
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%.17g", i ? ", " : "", x[i]);
    s += buf;
  }
  return s + "]";
}

std::string json_matrix(const Eigen::MatrixXd &m) {
  std::string s = "[";
  for (Eigen::Index r = 0; r < m.rows(); ++r) s += (r ? ", " : "") + json_vector(m.row(r));
  return s + "]";
}

// [angular; linear]: the rows of a linear-first 6-row block swapped (articulated's convention).
Eigen::MatrixXd angular_first(const Eigen::MatrixXd &m) {
  Eigen::MatrixXd out(m.rows(), m.cols());
  out.topRows(3) = m.bottomRows(3);
  out.bottomRows(3) = m.topRows(3);
  return out;
}

std::string json_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// The frame outputs at state s, as JSON members (none without frames): per frame, in the order
// of --frames, the placement (rotation row by row, translation), J and dJ angular rows first.
std::string frame_values(const pinocchio::Model &model, pinocchio::Data &data, Frames &frames,
                         const State &s) {
  if (frames.ids.empty()) return "";
  using pinocchio::LOCAL_WORLD_ALIGNED;
  const auto &ids = frames.ids;
  auto list = [&](auto item) {
    std::string out = "[";
    for (size_t k = 0; k < ids.size(); ++k) out += (k ? ", " : "") + item(k);
    return out + "]";
  };
  pinocchio::forwardKinematics(model, data, s.q);
  for (auto id : ids) pinocchio::updateFramePlacement(model, data, id);
  std::string out = ", \"frame_placements\": " + list([&](size_t k) {
    const auto &m = data.oMf[ids[k]];
    return "{\"rotation\": " + json_matrix(m.rotation()) +
           ", \"translation\": " + json_vector(m.translation()) + "}";
  });
  for (auto &j : frames.J) j.setZero();
  out += ", \"frame_jacobians_local_world_aligned\": " + list([&](size_t k) {
    pinocchio::computeFrameJacobian(model, data, s.q, ids[k], LOCAL_WORLD_ALIGNED, frames.J[k]);
    return json_matrix(angular_first(frames.J[k]));
  });
  for (auto &j : frames.J) j.setZero();
  pinocchio::computeJointJacobians(model, data, s.q);
  out += ", \"frame_jacobians_local_world_aligned_joint_jacobians\": " + list([&](size_t k) {
    pinocchio::getFrameJacobian(model, data, ids[k], LOCAL_WORLD_ALIGNED, frames.J[k]);
    return json_matrix(angular_first(frames.J[k]));
  });
  for (auto &j : frames.dJ) j.setZero();
  pinocchio::computeJointJacobiansTimeVariation(model, data, s.q, s.v);
  out += ", \"frame_jacobian_time_variations_local_world_aligned\": " + list([&](size_t k) {
    pinocchio::getFrameJacobianTimeVariation(model, data, ids[k], LOCAL_WORLD_ALIGNED,
                                             frames.dJ[k]);
    return json_matrix(angular_first(frames.dJ[k]));
  });
  return out;
}

// constrained_forward_dynamics at state s, as a JSON member (none without contacts): q̈, the
// wrench of each contact in the order of --contacts ([n; f], angular first, in the contact
// frame), and the iterations made.
std::string constrained_values(const pinocchio::Model &model, pinocchio::Data &data,
                               Contacts &contacts, const State &s) {
  if (contacts.models.empty()) return "";
  const Vec qdd = pinocchio::constraintDynamics(model, data, s.q, s.v, s.tau, contacts.models,
                                                contacts.datas, contacts.settings);
  std::string forces = "[";
  for (size_t k = 0; k < contacts.datas.size(); ++k)
    forces += (k ? ", " : "") +
              json_vector(angular_first(contacts.datas[k].contact_force.toVector()));
  return ", \"constrained_forward_dynamics\": {\"acceleration\": " + json_vector(qdd) +
         ", \"forces\": " + forces + "], \"iterations\": " +
         std::to_string(contacts.settings.iter) + "}";
}

// The outputs at state s, as JSON; the mass matrices and their inverses as Pinocchio leaves them
// (upper triangle), the centroidal momentum and its matrix angular first.
std::string values(const pinocchio::Model &model, pinocchio::Data &data, Frames &frames,
                   Contacts &contacts, const State &s) {
  using pinocchio::Convention;
  std::string out = "{";
  data.M.setZero();
  out += "\"mass_matrix\": " + json_matrix(pinocchio::crba(model, data, s.q));
  data.M.setZero();
  out += ", \"mass_matrix_world\": " +
         json_matrix(pinocchio::crba(model, data, s.q, Convention::WORLD));
  out += ", \"nonlinear_effects\": " +
         json_vector(pinocchio::nonLinearEffects(model, data, s.q, s.v));
  out += ", \"gravity\": " + json_vector(pinocchio::computeGeneralizedGravity(model, data, s.q));
  out += ", \"inverse_dynamics\": " + json_vector(pinocchio::rnea(model, data, s.q, s.v, s.a));
  out += ", \"forward_dynamics\": " + json_vector(pinocchio::aba(model, data, s.q, s.v, s.tau));
  out += ", \"forward_dynamics_world\": " +
         json_vector(pinocchio::aba(model, data, s.q, s.v, s.tau, Convention::WORLD));
  data.M.setZero();
  pinocchio::crba(model, data, s.q);
  pinocchio::nonLinearEffects(model, data, s.q, s.v);
  out += ", \"mass_matrix_and_nonlinear_effects\": {\"mass_matrix\": " + json_matrix(data.M) +
         ", \"nonlinear_effects\": " + json_vector(data.nle) + "}";
  out += ", \"center_of_mass\": " + json_vector(pinocchio::centerOfMass(model, data, s.q, false));
  pinocchio::centerOfMass(model, data, s.q, s.v, false);
  out += ", \"center_of_mass_velocity\": " + json_vector(data.vcom[0]);
  out += ", \"center_of_mass_jacobian\": " +
         json_matrix(pinocchio::jacobianCenterOfMass(model, data, s.q, false));
  out += ", \"centroidal_momentum\": " +
         json_vector(angular_first(
             pinocchio::computeCentroidalMomentum(model, data, s.q, s.v).toVector()));
  out += ", \"centroidal_momentum_matrix\": " +
         json_matrix(angular_first(pinocchio::ccrba(model, data, s.q, s.v)));
  data.Ag.setZero();
  out += ", \"centroidal_map\": " +
         json_matrix(angular_first(pinocchio::computeCentroidalMap(model, data, s.q)));
  out += ", \"kinetic_energy\": " +
         json_number(pinocchio::computeKineticEnergy(model, data, s.q, s.v));
  out += ", \"potential_energy\": " +
         json_number(pinocchio::computePotentialEnergy(model, data, s.q));
  out += ", \"coriolis_matrix\": " +
         json_matrix(pinocchio::computeCoriolisMatrix(model, data, s.q, s.v));
  pinocchio::computeRNEADerivatives(model, data, s.q, s.v, s.a);
  out += ", \"inverse_dynamics_derivatives\": {\"dtau_dq\": " + json_matrix(data.dtau_dq) +
         ", \"dtau_dv\": " + json_matrix(data.dtau_dv) + "}";
  data.Minv.setZero();
  pinocchio::computeABADerivatives(model, data, s.q, s.v, s.tau);
  out += ", \"forward_dynamics_derivatives\": {\"ddq_dq\": " + json_matrix(data.ddq_dq) +
         ", \"ddq_dv\": " + json_matrix(data.ddq_dv) + ", \"minv\": " + json_matrix(data.Minv) +
         "}";
  data.Minv.setZero();
  out += ", \"mass_matrix_inverse\": " + json_matrix(pinocchio::computeMinverse(model, data, s.q));
  out += frame_values(model, data, frames, s);
  out += constrained_values(model, data, contacts, s);
  return out + "}";
}

#ifdef _OPENMP
// --throughput: states per second at each thread count, over `batch` states (the file's,
// repeated), the best of `rounds` timings of enough calls to take about 50 ms. Forward and
// inverse dynamics by Pinocchio's own parallel algorithms, abaInParallel and rneaInParallel
// (a ModelPool, one Data per thread, OpenMP); the outputs it does not parallelize by the same
// OpenMP loop with one Data per thread. One thread is the same loop on one thread.
std::string throughput(const pinocchio::Model &model, const std::vector<State> &states,
                       const std::vector<int> &threads, long batch, int rounds) {
  const long n = batch;
  Eigen::MatrixXd Q(model.nq, n), V(model.nv, n), A(model.nv, n), T(model.nv, n),
      OUT(model.nv, n);
  for (long i = 0; i < n; ++i) {
    const State &s = states[i % states.size()];
    Q.col(i) = s.q;
    V.col(i) = s.v;
    A.col(i) = s.a;
    T.col(i) = s.tau;
  }
  std::string json;
  for (int t : threads) {
    pinocchio::ModelPool pool(model, t);
    std::vector<pinocchio::Data> datas(t, pinocchio::Data(model));
    auto loop = [&](auto &&f) {
#pragma omp parallel for num_threads(t) schedule(static)
      for (long i = 0; i < n; ++i) f(datas[omp_get_thread_num()], i);
    };
    auto time = [&](const char *name, auto &&call) {
      call();
      long reps = 1;
      for (;;) {
        auto start = Clock::now();
        for (long r = 0; r < reps; ++r) call();
        double s = std::chrono::duration<double>(Clock::now() - start).count();
        if (s > 0.05 || reps > (1L << 20)) break;
        reps *= 2;
      }
      double best = 1e300;
      for (int k = 0; k < rounds; ++k) {
        auto start = Clock::now();
        for (long r = 0; r < reps; ++r) call();
        best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
      }
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "%s{\"output\": \"%s\", \"threads\": %d, \"states_per_second\": %.6g}",
                    json.empty() ? "" : ", ", name, t, double(n * reps) / best);
      json += buf;
    };
    time("mass_matrix", [&] {
      loop([&](pinocchio::Data &d, long i) { pinocchio::crba(model, d, Q.col(i)); });
    });
    time("nonlinear_effects", [&] {
      loop([&](pinocchio::Data &d, long i) {
        pinocchio::nonLinearEffects(model, d, Q.col(i), V.col(i));
      });
    });
    time("inverse_dynamics", [&] { pinocchio::rneaInParallel(t, pool, Q, V, A, OUT); });
    time("forward_dynamics", [&] { pinocchio::abaInParallel(t, pool, Q, V, T, OUT); });
    time("inverse_dynamics_derivatives", [&] {
      loop([&](pinocchio::Data &d, long i) {
        pinocchio::computeRNEADerivatives(model, d, Q.col(i), V.col(i), A.col(i));
      });
    });
    time("forward_dynamics_derivatives", [&] {
      loop([&](pinocchio::Data &d, long i) {
        pinocchio::computeABADerivatives(model, d, Q.col(i), V.col(i), T.col(i));
      });
    });
  }
  return "[" + json + "]";
}
#endif

int run(int argc, char **argv) {
  std::string urdf, states_path, frame_names, contact_names;
  bool floating = false, do_values = false, do_time = false, do_calls = false;
  Runner runner;
  std::string throughput_threads;  // --throughput: the thread counts
  long throughput_batch = 256;
  int throughput_rounds = 7;
  std::vector<std::string> rest;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (++i >= argc) throw std::runtime_error(a + " needs a value\n" + USAGE);
      return argv[i];
    };
    if (a == "--urdf") urdf = next();
    else if (a == "--floating") floating = true;
    else if (a == "--frames") frame_names = next();
    else if (a == "--contacts") contact_names = next();
    else if (a == "--states") states_path = next();
    else if (a == "--values") do_values = true;
    else if (a == "--time") do_time = true;
    else if (a == "--calls") do_calls = true, runner.calls = std::stol(next());
    else if (a == "--batches") runner.batches = std::max(1, std::stoi(next()));
    else if (a == "--batch-ms") runner.batch_s = std::stod(next()) * 1e-3;
    else if (a == "--throughput") throughput_threads = next();
    else if (a == "--batch") throughput_batch = std::stol(next());
    else if (a == "--rounds") throughput_rounds = std::stoi(next());
    else if (a == "-h" || a == "--help") {
      std::puts(USAGE);
      return 0;
    } else rest.push_back(a);
  }
  const bool do_throughput = !throughput_threads.empty();
  if (urdf.empty() || states_path.empty() || do_values + do_time + do_calls + do_throughput != 1 ||
      rest.size() != (do_calls ? 2u : 1u))
    throw std::runtime_error(USAGE);

  pinocchio::Model model;
  if (floating)
    pinocchio::urdf::buildModel(urdf, pinocchio::JointModelFreeFlyer(), model);
  else
    pinocchio::urdf::buildModel(urdf, model);
  model.gravity.linear(Eigen::Vector3d(0, 0, -9.81));
  pinocchio::Data data(model);
  Frames frames(model, frame_names);
  Contacts contacts(model, data, contact_names);
  const auto states = read_states(states_path, model.nq, model.nv);

  if (do_values) {
    std::printf("%s\n", values(model, data, frames, contacts, states[0]).c_str());
    return 0;
  }
  if (do_throughput) {
#ifdef _OPENMP
    std::vector<int> threads;
    size_t start = 0;
    while (start < throughput_threads.size()) {
      size_t end = throughput_threads.find(',', start);
      if (end == std::string::npos) end = throughput_threads.size();
      threads.push_back(std::stoi(throughput_threads.substr(start, end - start)));
      start = end + 1;
    }
    std::printf("%s\n",
                throughput(model, states, threads, throughput_batch, throughput_rounds).c_str());
    return 0;
#else
    throw std::runtime_error("--throughput needs a build with -fopenmp");
#endif
  }
  std::vector<Ref> q, v, a, tau;
  for (const auto &s : states) {
    q.emplace_back(s.q);
    v.emplace_back(s.v);
    a.emplace_back(s.a);
    tau.emplace_back(s.tau);
  }
  if (do_calls) {
    runner.mode = Runner::Calls;
    runner.only = rest[1];
    each_output(model, data, frames, contacts, states, q, v, a, tau, runner);
    if (!runner.found) throw std::runtime_error("unknown output " + rest[1]);
    return 0;
  }
  each_output(model, data, frames, contacts, states, q, v, a, tau, runner);
  std::string out = "{";
  for (size_t i = 0; i < runner.json.size(); ++i) out += (i ? ", " : "") + runner.json[i];
  std::printf("%s}\n", out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "pinocchio_timing: %s\n", e.what());
    return 1;
  }
}
