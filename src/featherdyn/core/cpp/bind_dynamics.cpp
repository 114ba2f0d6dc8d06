// The binding of the dynamics' tools (docs/architecture.md): RNEA in complex arithmetic and its derivatives by
// forward-mode differentiation (the tests' independent checks), and the operation counts of RNEA, CRBA and ABA.
// The algorithms themselves are declared (declarations.hpp).
#include "aba.hpp"
#include "counted.hpp"
#include "crba.hpp"
#include "derivatives.hpp"
#include "rnea.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace {

// RNEA on complex input (complex-step checks); no finiteness or quaternion checks.
std::int64_t rnea_complex1(const ModelData& md, const InC& q, const InC& v, const InC& a, const InC& f_ext,
                           bool gravity, OutC tau) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  require_aligned(tau);
  if (tau.size() != static_cast<size_t>(mv.nv)) return make_status(LENGTH, ARG_OUT, tau.size());
  rnea(mv, q.data(), v.data(), a.data(), f_ext.is_valid() ? f_ext.data() : nullptr, gravity, tau.data());
  return OK;
}

// ∂τ/∂q, ∂τ/∂q̇ of one complex state (the analytical first order in complex arithmetic: complex-step checks of the
// second order); no finiteness or quaternion checks.
std::int64_t rnea_derivatives_complex1(const ModelData& md, const InC& q, const InC& v, const InC& a, OutC dq,
                                       OutC dv) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  require_aligned(dq);
  require_aligned(dv);
  const size_t n2 = static_cast<size_t>(mv.nv) * mv.nv;
  if (dq.size() != n2 || dv.size() != n2) return make_status(LENGTH, ARG_OUT, -1);
  rnea_derivatives(mv, q.data(), v.data(), a.data(), static_cast<const std::complex<double>*>(nullptr), true,
                   dq.data(), dv.data());
  return OK;
}

// ∂τ/∂q, ∂τ/∂q̇ of one state by forward-mode differentiation (Dual numbers).
std::int64_t rnea_derivatives_dual1(const ModelData& md, const In& q, const In& v, const In& a, Out dq, Out dv) {
  const ModelView& mv = md.view;
  const size_t n2 = static_cast<size_t>(mv.nv) * mv.nv;
  if (q.size() != size_t(mv.nq) || v.size() != size_t(mv.nv) || a.size() != size_t(mv.nv) || dq.size() != n2 ||
      dv.size() != n2)
    return make_status(LENGTH, ARG_OUT, -1);
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), nullptr));
  rnea_derivatives_dual(mv, q.data(), v.data(), a.data(), nullptr, true, dq.data(), dv.data());
  return OK;
}

// The floating-point operations (+, −, ×, ÷, √) one call of a kernel does for this model and state:
// the kernel template instantiated for Counted. kind: 0 RNEA, 1 CRBA, 2 ABA (b = q̇, c = q̈ or τ).
std::int64_t flops1(const ModelData& md, int kind, const In& q, const In& v, const In& b) {
  const ModelView& mv = md.view;
  require_present(q);
  require_present(v);
  require_present(b);
  if (q.size() != size_t(mv.nq) || v.size() != size_t(mv.nv) || b.size() != size_t(mv.nv))
    throw nb::value_error("flops: q, v and the third vector must have lengths nq, nv, nv");
  std::vector<Counted> Q(q.data(), q.data() + mv.nq), V(v.data(), v.data() + mv.nv), B(b.data(), b.data() + mv.nv);
  std::vector<Counted> out(static_cast<size_t>(mv.nv) * mv.nv);
  Counted::ops() = 0;
  if (kind == 0) {
    rnea(mv, Q.data(), V.data(), B.data(), static_cast<const Counted*>(nullptr), true, out.data());
  } else if (kind == 1) {
    crba(mv, Q.data(), out.data());
  } else if (kind == 2) {
    aba(mv, Q.data(), V.data(), B.data(), static_cast<const Counted*>(nullptr), true, out.data());
  } else {
    throw nb::value_error("flops: kind must be 0 (RNEA), 1 (CRBA) or 2 (ABA)");
  }
  return Counted::ops();
}

}  // namespace

void fdcore::bind_dynamics(nb::module_& m) {
  m.def("rnea_complex", &rnea_complex1, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"), nb::arg("gravity"),
        arr("out"));
  m.def("rnea_derivatives_complex", &rnea_derivatives_complex1, nb::arg("model"), arr("q"), arr("v"), arr("a"),
        arr("dtau_dq"), arr("dtau_dv"));
  m.def("rnea_derivatives_dual", &rnea_derivatives_dual1, nb::arg("model"), arr("q"), arr("v"), arr("a"), arr("dtau_dq"),
        arr("dtau_dv"));
  m.def("flops", &flops1, nb::arg("model"), nb::arg("kind"), arr("q"), arr("v"), arr("b"),
        "floating-point operations of one RNEA (0), CRBA (1) or ABA (2) call for this state");
}
