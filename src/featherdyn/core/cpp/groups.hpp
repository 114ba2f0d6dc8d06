// What a batch hands to the SIMD kernels of one group of rows (simd_groups.hpp), independent of
// the instruction set those kernels were compiled for (bindings.cpp picks one at import).
#pragma once

#include <cstdint>

#include "contact_spec.hpp"
#include "model_view.hpp"

namespace fdgroup {

// A batch input: (R, n) rows with R = N, or R = 1 broadcast to every row (stride 0).
struct Rows {
  const double* p = nullptr;
  std::int64_t stride = 0;
  const double* row(std::int64_t r) const { return p ? p + r * stride : nullptr; }
};

// (constrained dynamics) the contacts and the solver's settings; λ (rows of m) and info (rows of 2: iterations,
// residual) next to q̈ (GroupArgs::outs[0]). (Λ of frames: specs, nc, m, mu and singular_tol; Λ in GroupArgs::outs[0].
// Impulses: specs, nc, m, singular_tol and the restitution.)
struct ContactArgs {
  const fdcore::ContactSpec* specs;
  int nc, m;
  double mu;
  int max_iter;
  double tol, singular_tol;
  double* lam;
  double* info;
  double restitution = 0.0;
};

struct GroupArgs {
  const fdcore::ModelView* mv;
  Rows Q, V, A, FX;  // A: q̈ or τ; V, A, FX may be absent
  bool gravity;
  // every output in the declaration's order (DECLARED_MAX entries: nullptr for one not formed, and past the
  // declaration's), row r of output o at outs[o] + r * out_stride: the first output's row length, which the others
  // share (∂τ/∂q, ∂τ/∂q̇ and M; a kernel whose other outputs differ reads them where its ContactArgs say)
  double* const* outs;
  std::int64_t out_stride;
  const ContactArgs* contacts = nullptr;  // (constrained dynamics)
  bool stream = false;  // write the result with non-temporal stores (stream_result)
  Rows W{};  // (vector–Jacobian products) the cotangent w
  int frame = -1, reference = 0;  // (a frame's derivatives) the frame and the reference of the result
};

// Whether a batch's result is too large to be read back from the caches: then writing it with non-temporal
// stores (simd_groups.hpp's scatter_lines) saves reading every output line from memory first.
inline bool stream_result(std::int64_t rows, std::int64_t doubles_per_row) {
  return rows * doubles_per_row >= (std::int64_t{1} << 20);  // 8 MB
}

// One group of `width` rows from row r0: 0, or non-zero when some lane failed (ABA: singular; constrained
// dynamics: M singular, or D with mu = 0).
using GroupFn = std::int64_t (*)(const GroupArgs&, std::int64_t r0);

// One-state kernels whose inner loops are wide (derivatives.hpp, contact_derivatives.hpp), compiled per instruction
// set too.
using RneaDerivativesFn = void (*)(const fdcore::ModelView&, const double* q, const double* qd, const double* qdd,
                                   const double* f_ext, bool gravity, double* dtau_dq, double* dtau_dv,
                                   double* M);
using MinverseFn = int (*)(const fdcore::ModelView&, const double* q, double* Minv);
using AbaDerivativesFn = int (*)(const fdcore::ModelView&, const int* lambda_d, const double* q, const double* qd,
                                 const double* tau, const double* f_ext, bool gravity, double* qdd, double* dq,
                                 double* dv, double* Minv, double* scratch);
using ContactDerivativesFn = std::int64_t (*)(const fdcore::ModelView&, const double* q, const double* qd,
                                              const double* f_ext, const double* qdd, const double* lam,
                                              const fdcore::ContactSpec* specs, int nc, int m, double singular_tol,
                                              double* const* out);
using SecondDerivativesFn = bool (*)(const fdcore::ModelView&, const double* q, const double* qd, const double* qdd,
                                     const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                     double* dM);
using AbaSecondDerivativesFn = int (*)(const fdcore::ModelView&, const double* q, const double* qd, const double* tau,
                                       const double* f_ext, bool gravity, double* d2q, double* d2v, double* dqdv,
                                       double* dqdtau);
using FiniteFn = bool (*)(const double* x, std::int64_t n);
using ImpulseDerivativesFn = std::int64_t (*)(const fdcore::ModelView&, const double* q, const double* vm,
                                              const fdcore::ContactSpec* specs, int nc, int m, double e,
                                              double singular_tol, double* const* out);

struct GroupKernels {
  const char* isa;
  int width;
  GroupFn rnea, crba, aba, fk, rnea_derivatives_group;
  RneaDerivativesFn rnea_derivatives;
  MinverseFn minverse;
  AbaDerivativesFn aba_derivatives;
  GroupFn aba_derivatives_group;
  GroupFn contact_dynamics, impulse_dynamics, operational_space_inertia;
  GroupFn kinetic_energy_derivatives;
  GroupFn rnea_vjp, aba_vjp, crba_vjp;
  GroupFn kinematics_derivatives, center_of_mass_derivatives, centroidal_dynamics_derivatives;
  ContactDerivativesFn contact_dynamics_derivatives;  // (contact_derivatives.hpp: one state, dense products)
  ImpulseDerivativesFn impulse_dynamics_derivatives;
  SecondDerivativesFn rnea_second_derivatives;  // (second_order.hpp: one state; false: scan the outputs)
  AbaSecondDerivativesFn aba_second_derivatives;
  GroupFn contact_dynamics_derivatives_group, impulse_dynamics_derivatives_group;
  FiniteFn all_finite;  // (checks.hpp: the scan of the outputs, boundary.hpp's finite_result)
};

}  // namespace fdgroup
