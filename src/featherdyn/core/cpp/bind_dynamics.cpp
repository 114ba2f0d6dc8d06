// The binding of the dynamics (docs/architecture.md): RNEA, its gravity and bias terms, CRBA and ABA —
// one state into out= (status), one state allocated (the public calls' path), rows of a batch on the pool.
#include "aba.hpp"
#include "counted.hpp"
#include "crba.hpp"
#include "rnea.hpp"
#include "simd_groups.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace fdcore {

std::int64_t rnea1(const ModelData& md, const F64In& q, const F64In& v, const F64In& a, const F64In& f_ext,
                   bool gravity, const F64Out& tau) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(tau, {size_t(mv.nv)}));
  FD_TRY(disjoint(tau, {{&q, ARG_Q}, {&v, ARG_V}, {&a, ARG_A}, {&f_ext, ARG_FEXT}}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), fx));
  rnea(mv, q.data(), v.data(), a.data(), fx, gravity, tau.data());
  return finite_result(tau.data(), mv.nv);
}

std::int64_t nle1(const ModelData& md, const F64In& q, const F64In& v, const F64Out& h) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(exact_shape(h, {size_t(mv.nv)}));
  FD_TRY(disjoint(h, {{&q, ARG_Q}, {&v, ARG_V}}));
  FD_TRY(check_state(mv, q.data(), v.data(), nullptr, nullptr));
  rnea<double>(mv, q.data(), v.data(), nullptr, nullptr, true, h.data());
  return finite_result(h.data(), mv.nv);
}

std::int64_t gravity1(const ModelData& md, const F64In& q, const F64Out& g) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(g, {size_t(mv.nv)}));
  FD_TRY(disjoint(g, {{&q, ARG_Q}}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  rnea<double>(mv, q.data(), nullptr, nullptr, nullptr, true, g.data());
  return finite_result(g.data(), mv.nv);
}

std::int64_t crba1(const ModelData& md, const F64In& q, const F64Out& M) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(M, {size_t(mv.nv), size_t(mv.nv)}));
  FD_TRY(disjoint(M, {{&q, ARG_Q}}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  crba(mv, q.data(), M.data());
  return finite_result(M.data(), std::int64_t(mv.nv) * mv.nv);
}

// Each returns its result, or None for anything the entry point above would refuse with a status (a
// wrong length, a bad state, an overflowed or singular result): the caller's general path words it.

nb::object rnea_new(const ModelData& md, const F64In& q, const F64In& v, const F64In& a, const F64In& f_ext,
                    bool gravity) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK || vec(a, mv.nv, ARG_A) != OK) return nb::none();
  if (f_ext.is_valid() && exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT) != OK) return nb::none();
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  if (check_state(mv, q.data(), v.data(), a.data(), fx) != OK) return nb::none();
  nb::object tau = numpy_alloc({mv.nv});
  rnea(mv, q.data(), v.data(), a.data(), fx, gravity, array_data(tau));
  return finite_result(array_data(tau), mv.nv) == OK ? tau : nb::none();
}

nb::object nle_new(const ModelData& md, const F64In& q, const F64In& v) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK) return nb::none();
  if (check_state(mv, q.data(), v.data(), nullptr, nullptr) != OK) return nb::none();
  nb::object h = numpy_alloc({mv.nv});
  rnea<double>(mv, q.data(), v.data(), nullptr, nullptr, true, array_data(h));
  return finite_result(array_data(h), mv.nv) == OK ? h : nb::none();
}

nb::object gravity_new(const ModelData& md, const F64In& q) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nb::none();
  nb::object g = numpy_alloc({mv.nv});
  rnea<double>(mv, q.data(), nullptr, nullptr, nullptr, true, array_data(g));
  return finite_result(array_data(g), mv.nv) == OK ? g : nb::none();
}

nb::object crba_new(const ModelData& md, const F64In& q) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || check_state(mv, q.data(), nullptr, nullptr, nullptr) != OK) return nb::none();
  nb::object M = numpy_alloc({mv.nv, mv.nv});
  crba(mv, q.data(), array_data(M));
  return finite_result(array_data(M), std::int64_t(mv.nv) * mv.nv) == OK ? M : nb::none();
}

nb::object aba_new(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau, const F64In& f_ext,
                   bool gravity) {
  const ModelView& mv = md.view;
  if (vec(q, mv.nq, ARG_Q) != OK || vec(v, mv.nv, ARG_V) != OK || vec(tau, mv.nv, ARG_A) != OK) return nb::none();
  if (f_ext.is_valid() && exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT) != OK) return nb::none();
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  if (check_state(mv, q.data(), v.data(), tau.data(), fx) != OK) return nb::none();
  nb::object qdd = numpy_alloc({mv.nv});
  const int bad = aba<double>(mv, q.data(), v.data(), tau.data(), fx, gravity, array_data(qdd), nullptr);
  return bad < 0 && finite_result(array_data(qdd), mv.nv) == OK ? qdd : nb::none();
}

// D_singular (36,) receives the singular joint's D_i (row stride 6) when the status is SINGULAR.
std::int64_t aba1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau, const F64In& f_ext,
                  bool gravity, const F64Out& qdd, const F64Out& D_singular) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(qdd, {size_t(mv.nv)}));
  if (D_singular.is_valid()) FD_TRY(exact_shape(D_singular, {36}));
  for (const F64Out* o : {&qdd, &D_singular}) FD_TRY(disjoint(*o, {{&q, ARG_Q}, {&v, ARG_V}, {&tau, ARG_A}, {&f_ext, ARG_FEXT}}));
  if (D_singular.is_valid() && overlaps(qdd.data(), mv.nv, D_singular.data(), 36)) return make_status(OVERLAP, ARG_OUT, 0);
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  const int bad = aba(mv, q.data(), v.data(), tau.data(), fx, gravity, qdd.data(),
                      D_singular.is_valid() ? D_singular.data() : nullptr);
  return bad < 0 ? finite_result(qdd.data(), mv.nv) : make_status(SINGULAR, ARG_Q, bad);
}

}  // namespace fdcore

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

// ---------------------------------------------------------------------------

RowStatus rnea_n(const ModelData& md, const In& q, const In& v, const In& a, const In& f_ext, bool gravity,
                 Out tau) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A, FX;
  FD_TRY_ROWS(out_rows(tau, mv.nv, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  const size_t nf = 6 * static_cast<size_t>(mv.nb);
  FD_TRY_ROWS(rows(f_ext, N, nf, ARG_FEXT, FX));
  double* T = tau.data();
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), A.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        rnea(mv, Q.row(r), V.row(r), A.row(r), FX.row(r), gravity, T + r * mv.nv);
        return OK;
      },
      group_kernels().rnea, {&mv, Q, V, A, FX, gravity, T, mv.nv});
}

RowStatus crba_n(const ModelData& md, const In& q, Out M) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t nv2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(M, nv2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = M.data();
  fdgroup::GroupArgs crba_args{&mv, Q, {}, {}, {}, true, out, nv2};
  crba_args.stream = fdgroup::stream_result(N, nv2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), nullptr, nullptr, nullptr); },
      [&](std::int64_t r) -> std::int64_t {
        crba(mv, Q.row(r), out + r * nv2);
        return OK;
      },
      group_kernels().crba, crba_args);
}

RowStatus aba_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext, bool gravity,
                Out qdd) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  FD_TRY_ROWS(out_rows(qdd, mv.nv, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(tau, N, mv.nv, ARG_A, T));
  const size_t nf = 6 * static_cast<size_t>(mv.nb);
  FD_TRY_ROWS(rows(f_ext, N, nf, ARG_FEXT, FX));
  double* out = qdd.data();
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        const int bad = aba(mv, Q.row(r), V.row(r), T.row(r), FX.row(r), gravity, out + r * mv.nv);
        return bad < 0 ? OK : make_status(SINGULAR, ARG_Q, bad);
      },
      group_kernels().aba, {&mv, Q, V, T, FX, gravity, out, mv.nv});
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
  m.def("rnea", &rnea1, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"), nb::arg("gravity"), arr("out"));
  m.def("nle", &nle1, nb::arg("model"), arr("q"), arr("v"), arr("out"));
  m.def("gravity", &gravity1, nb::arg("model"), arr("q"), arr("out"));
  m.def("crba", &crba1, nb::arg("model"), arr("q"), arr("out"));
  m.def("aba", &aba1, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), nb::arg("gravity"), arr("out"),
        opt("D_singular"));
  m.def("rnea_new", &rnea_new, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"), nb::arg("gravity"));
  m.def("nle_new", &nle_new, nb::arg("model"), arr("q"), arr("v"));
  m.def("gravity_new", &gravity_new, nb::arg("model"), arr("q"));
  m.def("crba_new", &crba_new, nb::arg("model"), arr("q"));
  m.def("aba_new", &aba_new, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), nb::arg("gravity"));
  m.def("rnea_complex", &rnea_complex1, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"), nb::arg("gravity"),
        arr("out"));
  m.def("rnea_batch", &rnea_n, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"), nb::arg("gravity"), arr("out"));
  m.def("crba_batch", &crba_n, nb::arg("model"), arr("q"), arr("out"));
  m.def("aba_batch", &aba_n, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), nb::arg("gravity"), arr("out"));
  m.def("flops", &flops1, nb::arg("model"), nb::arg("kind"), arr("q"), arr("v"), arr("b"),
        "floating-point operations of one RNEA (0), CRBA (1) or ABA (2) call for this state");
}
