// The binding of the constraints (docs/architecture.md): the Delassus matrix, the constrained KKT system, contacts
// in one call and Λ of frames (the mass matrix's factor and solve are declared: declarations.hpp).
#include "contacts.hpp"
#include "crba.hpp"
#include "ltl.hpp"
#include "rnea.hpp"
#include "simd_groups.hpp"
#include "entry_points.hpp"

namespace nb = nanobind;
using namespace fdcore;

namespace {

// ---------------------------------------------------------------------------
// the tree-sparse LᵀL factorisation (ltl.hpp)
// ---------------------------------------------------------------------------

// D (N, m²) = J M(q)⁻¹ Jᵀ for J (N or 1, m·nv).
RowStatus delassus_n(const ModelData& md, const In& q, const In& J, int m, Out D) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, JR;
  if (m < 0) throw nb::value_error("delassus: m must be non-negative");
  const int nv = mv.nv;
  FD_TRY_ROWS(out_rows(D, static_cast<size_t>(m) * m, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  FD_TRY_ROWS(rows(J, N, static_cast<size_t>(m) * nv, ARG_A, JR));
  std::vector<int> lambda(nv);
  dof_parents(mv, lambda.data());
  double* out = D.data();
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), nullptr, nullptr, nullptr));
    std::vector<double> L(static_cast<size_t>(nv) * nv), Y;
    crba(mv, Q.row(r), L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    delassus_from_factor(mv, lambda.data(), L.data(), JR.row(r), m, out + r * m * m, Y);
    return finite_result(out + r * m * m, static_cast<std::int64_t>(m) * m);
  });
}

// The rows of a constrained-dynamics batch: outputs q̈ (N, nv), λ (N, m), info (N, 2); inputs q, v, τ, f_ext.
std::int64_t dynamics_batch_rows(const ModelView& mv, int m, const In& q, const In& v, const In& tau, const In& f_ext,
                                 const Out& qdd, const Out& lam, const Out& info, std::int64_t& N, Rows& Q, Rows& V,
                                 Rows& T, Rows& FX) {
  const int nv = mv.nv;
  FD_TRY(out_rows(qdd, nv, N));
  FD_TRY(same_rows(lam, m, N));
  FD_TRY(same_rows(info, 2, N));
  FD_TRY(rows(q, N, mv.nq, ARG_Q, Q));
  require_present(v);
  require_present(tau);
  FD_TRY(rows(v, N, nv, ARG_V, V));
  FD_TRY(rows(tau, N, nv, ARG_A, T));
  return rows(f_ext, N, 6 * static_cast<size_t>(mv.nb), ARG_FEXT, FX);
}

// Constrained dynamics rows: q̈ (N, nv), λ (N, m), [iterations, residual] (N, 2) for M q̈ + h = τ + Jᵀλ,
// J q̈ = c with J (N or 1, m·nv) and c (N or 1, m); h with gravity and f_ext (optional).
RowStatus kkt_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext, const In& J,
                const In& c, int m, double mu, int max_iter, double tol, double singular_tol, Out qdd, Out lam,
                Out info) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX, JR, CR;
  const int nv = mv.nv;
  if (m < 0) throw nb::value_error("kkt: m must be non-negative");
  FD_TRY_ROWS(dynamics_batch_rows(mv, m, q, v, tau, f_ext, qdd, lam, info, N, Q, V, T, FX));
  FD_TRY_ROWS(rows(J, N, static_cast<size_t>(m) * nv, ARG_OUT, JR));
  FD_TRY_ROWS(rows(c, N, static_cast<size_t>(m), ARG_OUT, CR));
  std::vector<int> lambda(nv);
  dof_parents(mv, lambda.data());
  return for_rows(N, [&](std::int64_t r) -> std::int64_t {
    FD_TRY(check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)));
    std::vector<double> L(static_cast<size_t>(nv) * nv), th(nv);
    crba(mv, Q.row(r), L.data());
    const int bad = ltl_factor(mv, lambda.data(), L.data());
    if (bad >= 0) return make_status(SINGULAR, ARG_Q, dof_body(mv, bad));
    rnea(mv, Q.row(r), V.row(r), static_cast<const double*>(nullptr), FX.row(r), true, th.data());
    for (int k = 0; k < nv; ++k) th[k] = T.row(r)[k] - th[k];
    const KktResult res = kkt_solve(mv, lambda.data(), L.data(), th.data(), JR.row(r), CR.row(r), m, mu, max_iter,
                                    tol, singular_tol, qdd.data() + r * nv, lam.data() + r * m);
    info.data()[2 * r] = res.iterations;
    info.data()[2 * r + 1] = res.residual;
    return OK;
  });
}

// Contacts given as specs (nc, 4) rows [rows (3 | 6), frame, reference code, K_d] (contacts.hpp); m = Σ rows.
std::vector<ContactSpec> contact_specs(const ModelView& mv, const double* specs, size_t nc, int& m) {
  std::vector<ContactSpec> out(nc);
  m = 0;
  for (size_t k = 0; k < nc; ++k) {
    const double* s = specs + 4 * k;
    const int rows = static_cast<int>(s[0]), frame = static_cast<int>(s[1]), ref = static_cast<int>(s[2]);
    if (!(rows == 3 || rows == 6) || !(frame >= 0 && frame < mv.nf) || !(ref >= LOCAL && ref <= LOCAL_WORLD_ALIGNED) ||
        !(s[3] >= 0.0 && s[3] < 1e300) || static_cast<double>(frame) != s[1])
      throw nb::value_error("contact specs: rows [3|6, frame index, reference code 0..2, K_d >= 0] expected");
    out[k] = ContactSpec{rows, frame, ref, s[3]};
    m += rows;
  }
  return out;
}

// The specs of one model's contacts (or frames), checked once and kept by the caller's plan cache
// (api/constraints.py), so that a one-state call converts no specs array. `model` is the ModelData it was
// checked against (its address and frame count): a call with another model is refused (TypeError: the caller's
// general path then converts).
struct ContactPlan {
  const ModelData* model;
  int nf;
  std::vector<ContactSpec> specs;
  int m = 0;
};

ContactPlan make_contact_plan(const ModelData& md, const F64In& specs) {
  require_present(specs);
  if (specs.ndim() != 2 || specs.shape(1) != 4) throw nb::value_error("contact specs: expected shape (nc, 4)");
  ContactPlan plan{&md, md.view.nf, {}, 0};
  plan.specs = contact_specs(md.view, specs.data(), specs.shape(0), plan.m);
  return plan;
}

const std::vector<ContactSpec>& plan_specs(const ModelData& md, const ContactPlan& plan) {
  if (plan.model != &md || plan.nf != md.view.nf) throw nb::type_error("contact plan: made for another model");
  return plan.specs;
}

// One state: q̈ (nv,), λ (m,), info (2,) = [iterations (−1: dependent rows, −2: not converged), residual].
std::int64_t contact_dynamics1(const ModelData& md, const F64In& q, const F64In& v, const F64In& tau,
                               const F64In& f_ext, const ContactPlan& plan, double mu, int max_iter, double tol,
                               double singular_tol, const F64Out& qdd, const F64Out& lam, const F64Out& info) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  FD_TRY(vec(v, mv.nv, ARG_V));
  FD_TRY(vec(tau, mv.nv, ARG_A));
  if (f_ext.is_valid()) FD_TRY(exact_shape(f_ext, {size_t(mv.nb), 6}, ARG_FEXT));
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m;
  FD_TRY(exact_shape(qdd, {size_t(mv.nv)}));
  FD_TRY(exact_shape(lam, {size_t(m)}));
  FD_TRY(exact_shape(info, {2}));
  const double* fx = f_ext.is_valid() ? f_ext.data() : nullptr;
  FD_TRY(check_state(mv, q.data(), v.data(), tau.data(), fx));
  ContactResult<double> res;
  FD_TRY(contact_dynamics(mv, q.data(), v.data(), tau.data(), fx, cs.data(), static_cast<int>(cs.size()), mu,
                          max_iter, tol, singular_tol, qdd.data(), lam.data(), res));
  info.data()[0] = res.iterations;
  info.data()[1] = res.residual;
  return OK;
}

// Λ (6k, 6k) of k frames: specs (k, 4) rows [6, frame, reference code, 0] (contacts.hpp).
std::int64_t osi1(const ModelData& md, const F64In& q, const ContactPlan& plan, double mu, double singular_tol,
                  const F64Out& Lambda) {
  const ModelView& mv = md.view;
  FD_TRY(vec(q, mv.nq, ARG_Q));
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m;
  if (m != 6 * static_cast<int>(cs.size())) throw nb::value_error("frame specs: 6 rows per frame expected");
  FD_TRY(exact_shape(Lambda, {size_t(m), size_t(m)}));
  FD_TRY(check_state(mv, q.data(), nullptr, nullptr, nullptr));
  if (!(mu >= 0.0)) throw nb::value_error("mu must be >= 0");
  return operational_space_inertia(mv, q.data(), cs.data(), static_cast<int>(cs.size()), mu, singular_tol,
                                   Lambda.data());
}

// Rows of a batch: q̈ (N, nv), λ (N, m), info (N, 2). Full groups of the kernels' width run contacts.hpp's
// kernel on Packs (simd_groups.hpp: contact_dynamics_group); the tail, and a group with a singular lane, row by row.
RowStatus contact_dynamics_n(const ModelData& md, const In& q, const In& v, const In& tau, const In& f_ext,
                             const In& specs, double mu, int max_iter, double tol, double singular_tol, Out qdd,
                             Out lam, Out info) {
  const ModelView& mv = md.view;
  std::int64_t N = 0;
  Rows Q, V, T, FX;
  const int nv = mv.nv;
  require_present(specs);
  if (specs.ndim() != 2 || specs.shape(1) != 4) throw nb::value_error("contact specs: expected shape (nc, 4)");
  int m = 0;
  const std::vector<ContactSpec> cs = contact_specs(mv, specs.data(), specs.shape(0), m);
  FD_TRY_ROWS(dynamics_batch_rows(mv, m, q, v, tau, f_ext, qdd, lam, info, N, Q, V, T, FX));
  const int nc = static_cast<int>(cs.size());
  const fdgroup::ContactArgs contacts{cs.data(), nc, m, mu, max_iter, tol, singular_tol, lam.data(), info.data()};
  fdgroup::GroupArgs args{&mv, Q, V, T, FX, true, qdd.data(), nv};
  args.contacts = &contacts;
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), V.row(r), T.row(r), FX.row(r)); },
      [&](std::int64_t r) -> std::int64_t {
        ContactResult<double> res;
        FD_TRY(contact_dynamics(mv, Q.row(r), V.row(r), T.row(r), FX.row(r), cs.data(), nc, mu, max_iter, tol,
                                singular_tol, qdd.data() + r * nv, lam.data() + r * m, res));
        info.data()[2 * r] = res.iterations;
        info.data()[2 * r + 1] = res.residual;
        return OK;
      },
      group_kernels().contact_dynamics, args);
}

// Λ of a batch: q (N, nq) → Λ (N, m, m) for the frames of `plan` (6 rows each); full groups on Packs
// (simd_groups.hpp: operational_space_inertia_group), the tail and a group with a singular lane row by row.
RowStatus osi_n(const ModelData& md, const In& q, const ContactPlan& plan, double mu, double singular_tol,
                Out Lambda) {
  const ModelView& mv = md.view;
  const std::vector<ContactSpec>& cs = plan_specs(md, plan);
  const int m = plan.m, nc = static_cast<int>(cs.size());
  if (m != 6 * nc) throw nb::value_error("frame specs: 6 rows per frame expected");
  if (!(mu >= 0.0)) throw nb::value_error("mu must be >= 0");
  const std::int64_t m2 = static_cast<std::int64_t>(m) * m;
  std::int64_t N = 0;
  Rows Q;
  FD_TRY_ROWS(out_rows(Lambda, m2, N));
  FD_TRY_ROWS(rows(q, N, mv.nq, ARG_Q, Q));
  double* out = Lambda.data();
  const fdgroup::ContactArgs frames{cs.data(), nc, m, mu, 0, 0.0, singular_tol, nullptr, nullptr};
  fdgroup::GroupArgs args{&mv, Q, {}, {}, {}, true, out, m2};
  args.contacts = &frames;
  return for_row_groups(
      N, [&](std::int64_t r) { return check_state(mv, Q.row(r), nullptr, nullptr, nullptr); },
      [&](std::int64_t r) {
        return operational_space_inertia(mv, Q.row(r), cs.data(), nc, mu, singular_tol, out + r * m2);
      },
      group_kernels().operational_space_inertia, args);
}

}  // namespace

void fdcore::bind_constraints(nb::module_& m) {
  m.def("delassus_batch", &delassus_n, nb::arg("model"), arr("q"), arr("J"), nb::arg("m"), arr("out"));
  m.def("kkt_batch", &kkt_n, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), arr("J"), arr("c"), nb::arg("m"),
        nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), arr("qdd"), arr("lam"), arr("info"));
  nb::class_<ContactPlan>(m, "ContactPlan").def(nb::new_(&make_contact_plan), nb::arg("model"), arr("specs"))
      .def_prop_ro("m", [](const ContactPlan& p) { return p.m; });
  m.def("contact_dynamics", &contact_dynamics1, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"), nb::arg("plan"),
        nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), arr("qdd"), arr("lam"), arr("info"));
  m.def("operational_space_inertia", &osi1, nb::arg("model"), arr("q"), nb::arg("plan"), nb::arg("mu"),
        nb::arg("singular_tol"), arr("out"));
  m.def("operational_space_inertia_batch", &osi_n, nb::arg("model"), arr("q"), nb::arg("plan"), nb::arg("mu"),
        nb::arg("singular_tol"), arr("out"));
  m.def("contact_dynamics_batch", &contact_dynamics_n, nb::arg("model"), arr("q"), arr("v"), arr("tau"), opt("f_ext"),
        arr("specs"), nb::arg("mu"), nb::arg("max_iter"), nb::arg("tol"), nb::arg("singular_tol"), arr("qdd"), arr("lam"),
        arr("info"));
}
