// The binding of the derivatives (docs/architecture.md): of RNEA and ABA, M⁻¹, of frame motion, the regressor.
#include "derivatives.hpp"
#include "frame_derivatives.hpp"
#include "ltl.hpp"
#include "regressor.hpp"
#include "scratch.hpp"
#include "simd_groups.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace {

// ---------------------------------------------------------------------------
// derivatives (derivatives.hpp): rows of a batch, on the pool
// ---------------------------------------------------------------------------

// ∂τ/∂q, ∂τ/∂q̇ (N, nv²) for rows of (q, q̇, q̈, f_ext).
RowStatus rnea_derivatives_n(const ModelData& md, const In& q, const In& v, const In& a, const In& f_ext,
                             bool gravity, Out dq, Out dv, Out M) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A, FX;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(dq, n2, N));
  FD_TRY_ROWS(same_rows(dv, n2, N));
  FD_TRY_ROWS(same_rows(M, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(a);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  FD_TRY_ROWS(rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX));
  double *DQ = dq.data(), *DV = dv.data(), *MM = M.data();
  fdgroup::GroupArgs args{&mv, Q, V, A, FX, gravity, DQ, n2};
  args.out2 = DV;
  args.out3 = MM;
  args.stream = fdgroup::stream_result(N, (MM ? 3 : 2) * n2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), A.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {  // a row alone: also the rows of a group that overflowed
        group_kernels().rnea_derivatives(mv, Q.row(r), V.row(r), A.row(r), FX.row(r), gravity, DQ + r * n2,
                                         DV + r * n2, MM + r * n2);
        FD_TRY(finite_result(DQ + r * n2, n2));  // results that finite input overflowed
        return finite_result(DV + r * n2, n2);
      },
      group_kernels().rnea_derivatives_group, args);  // (a group checks its own results while they are cached)
}

// One state (the public functions' fast path): ∂τ/∂q, ∂τ/∂q̇ (nv, nv) and ∂τ/∂q̈ = M (nv, nv), with f_ext.
std::int64_t rnea_derivatives1(const ModelData& md, const F64In& q, const F64In& v, const F64In& a,
                               const F64In& f_ext, const F64Out& dq, const F64Out& dv, const F64Out& M) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(a, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  for (const F64Out* o : {&dq, &dv, &M}) FD_TRY(exact_shape(*o, {nv, nv}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), a.data(), fx));
  group_kernels().rnea_derivatives(mv, q.data(), v.data(), a.data(), fx, true, dq.data(), dv.data(), M.data());
  FD_TRY(finite_result(dq.data(), static_cast<std::int64_t>(nv * nv)));
  return finite_result(dv.data(), static_cast<std::int64_t>(nv * nv));
}

// One state: ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹ (nv, nv) and q̈ (nv,), with f_ext.
std::int64_t aba_derivatives1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau,
                              const F64In& f_ext, const F64Out& qdd, const F64Out& dq, const F64Out& dv,
                              const F64Out& Minv) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  FD_TRY(exact_shape(qdd, {nv}));
  for (const F64Out* o : {&dq, &dv, &Minv}) FD_TRY(exact_shape(*o, {nv, nv}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  const int* lambda = dof_tree(mv).lambda.data();
  const int bad = group_kernels().aba_derivatives(mv, lambda, q.data(), v.data(), tau.data(), fx, true,
                                                  qdd.data(), dq.data(), dv.data(), Minv.data(),
                                                  aligned_scratch(aba_derivatives_scratch(mv.nv)));
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
  FD_TRY(finite_result(dq.data(), static_cast<std::int64_t>(nv * nv)));
  return finite_result(dv.data(), static_cast<std::int64_t>(nv * nv));
}

// ∂τ/∂q, ∂τ/∂q̇ of one state by forward-mode differentiation (Dual numbers): the tests' independent check.
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

// One state: M⁻¹ (nv, nv).
std::int64_t minverse1(const ModelData& md, const F64In& q, const F64Out& Minv) {
  const ModelView& mv = md.view;
  const size_t nv = static_cast<size_t>(mv.nv);
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(exact_shape(Minv, {nv, nv}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  const int bad = group_kernels().minverse(mv, q.data(), Minv.data());
  if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
  return finite_result(Minv.data(), static_cast<std::int64_t>(nv * nv));
}

// M⁻¹ (N, nv²) for rows of q.
RowStatus minverse_n(const ModelData& md, const In& q, Out Minv) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(Minv, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = Minv.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    const int bad = group_kernels().minverse(mv, Q.row(r), out + r * n2);
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
    return finite_result(out + r * n2, n2);
  });
}

// q̈ (N, nv), ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹ (N, nv²) for rows of (q, q̇, τ, f_ext).
RowStatus aba_derivatives_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext,
                            bool gravity, Out qdd, Out dq, Out dv, Out Minv) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  const std::int64_t n2 = static_cast<std::int64_t>(mv.nv) * mv.nv;
  FD_TRY_ROWS(out_rows(qdd, mv.nv, N));
  for (const Out* o : {&dq, &dv, &Minv}) FD_TRY_ROWS(same_rows(*o, n2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(tau);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(tau, N, mv.nv, ARG_A, T));
  FD_TRY_ROWS(rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX));
  double *QDD = qdd.data(), *DQ = dq.data(), *DV = dv.data(), *MI = Minv.data();
  std::vector<int> lambda(mv.nv);
  dof_parents(mv, lambda.data());
  fdgroup::GroupArgs args{&mv, Q, V, T, FX, gravity, DQ, n2};
  args.out2 = DV;
  args.out3 = MI;
  args.out_qdd = QDD;
  args.lambda_d = lambda.data();
  args.stream = fdgroup::stream_result(N, 3 * n2);
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        const int bad = group_kernels().aba_derivatives(mv, lambda.data(), Q.row(r), V.row(r), T.row(r), FX.row(r),
                                                        gravity, QDD + r * mv.nv, DQ + r * n2, DV + r * n2,
                                                        MI + r * n2, aligned_scratch(aba_derivatives_scratch(mv.nv)));
        if (bad >= 0) return make_status(SINGULAR, ARG_Q, bad);
        FD_TRY(finite_result(DQ + r * n2, n2));  // results that finite input overflowed
        return finite_result(DV + r * n2, n2);
      },
      group_kernels().aba_derivatives_group, args);  // (a group checks its own results while they are cached)
}

// A frame's velocity derivatives (N, 6 nv) twice and, with A, its acceleration derivatives three times.
RowStatus frame_motion_derivatives_n(const ModelData& md, const In& q, const In& v, const In& a, int frame, int ref,
                                     Out dv_dq, Out dv_dv, Out da_dq, Out da_dv, Out da_da) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A;
  const std::int64_t n = 6 * static_cast<std::int64_t>(mv.nv);
  FD_TRY_ROWS(out_rows(dv_dq, n, N));
  FD_TRY_ROWS(same_rows(dv_dv, n, N));
  if (a.is_valid())
    for (const Out* o : {&da_dq, &da_dv, &da_da}) FD_TRY_ROWS(same_rows(*o, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  if (frame < 0 || frame >= mv.nf) return {-1, make_status(LENGTH, ARG_FRAME, frame < 0 ? 0 : frame)};
  if (ref < LOCAL || ref > LOCAL_WORLD_ALIGNED) throw nb::value_error("reference code must be 0, 1 or 2");
  const bool acc = a.is_valid();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), A.row(r), nullptr));
    frame_motion_derivatives(mv, Q.row(r), V.row(r), A.row(r), frame, ref, dv_dq.data() + r * n,
                             dv_dv.data() + r * n, acc ? da_dq.data() + r * n : nullptr,
                             acc ? da_dv.data() + r * n : nullptr, acc ? da_da.data() + r * n : nullptr);
    FD_TRY(finite_result(dv_dq.data() + r * n, n));
    return acc ? finite_result(da_dq.data() + r * n, n) : OK;
  });
}

// The joint torque regressor Y (N, nv · 10 nb) for rows of (q, q̇, q̈).
RowStatus regressor_n(const ModelData& md, const In& q, const In& v, const In& a, Out Y) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, A;
  const std::int64_t n = static_cast<std::int64_t>(mv.nv) * 10 * mv.nb;
  FD_TRY_ROWS(out_rows(Y, n, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(a);
  FD_TRY_ROWS(rows(v, N, mv.nv, ARG_V, V));
  FD_TRY_ROWS(rows(a, N, mv.nv, ARG_A, A));
  double* out = Y.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), A.row(r), nullptr));
    joint_torque_regressor(mv, Q.row(r), V.row(r), A.row(r), out + r * n);
    return finite_result(out + r * n, n);
  });
}

}  // namespace

void fdcore::bind_derivatives(nb::module_& m) {
  m.def("rnea_derivatives", &rnea_derivatives1, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"),
        arr("dtau_dq"), arr("dtau_dv"), arr("M"));
  m.def("aba_derivatives", &aba_derivatives1, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), arr("qdd"),
        arr("dqdd_dq"), arr("dqdd_dv"), arr("Minv"));
  m.def("rnea_derivatives_batch", &rnea_derivatives_n, nb::arg("model"), arr("q"), arr("v"), arr("a"), opt("f_ext"),
        nb::arg("gravity"), arr("dtau_dq"), arr("dtau_dv"), arr("M"));
  m.def("rnea_derivatives_dual", &rnea_derivatives_dual1, nb::arg("model"), arr("q"), arr("v"), arr("a"), arr("dtau_dq"),
        arr("dtau_dv"));
  m.def("minverse_batch", &minverse_n, nb::arg("model"), arr("q"), arr("out"));
  m.def("mass_matrix_inverse", &minverse1, nb::arg("model"), arr("q"), arr("Minv"));
  m.def("aba_derivatives_batch", &aba_derivatives_n, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"),
        nb::arg("gravity"), arr("qdd"), arr("dqdd_dq"), arr("dqdd_dv"), arr("Minv"));
  m.def("frame_motion_derivatives_batch", &frame_motion_derivatives_n, nb::arg("model"), arr("q"), arr("v"), opt("a"),
        nb::arg("frame"), nb::arg("reference"), arr("dv_dq"), arr("dv_dv"), opt("da_dq"), opt("da_dv"), opt("da_da"));
  m.def("regressor_batch", &regressor_n, nb::arg("model"), arr("q"), arr("v"), arr("a"), arr("out"));
}
