// The binding of a call's options (declare.hpp: Options; docs/architecture.md, "One declaration per algorithm"): the
// parameters a declared algorithm takes besides its arrays, given to a Kernel's front ends as one `Options` object
// (made once where a loop calls again: one argument to pass, nothing to parse per call), and the contacts' plan they
// may carry (its specs checked once, kept by the caller's plan cache: featherdyn/constraints.py).
#include "declare.hpp"
#include "frames.hpp"
#include "entry_points.hpp"


namespace nb = nanobind;
using namespace fdcore;

namespace {

// Contacts given as specs (nc, 4) rows [rows (3 | 6), frame, reference code, K_d] (contacts.hpp), checked against
// the model they were made for.
struct ContactPlan {
  const ModelData* model;
  std::vector<ContactSpec> specs;
  int m = 0;
};

ContactPlan make_contact_plan(const ModelData& md, const F64In& specs) {
  require_present(specs);
  if (specs.ndim() != 2 || specs.shape(1) != 4) throw nb::value_error("contact specs: expected shape (nc, 4)");
  ContactPlan plan{&md, std::vector<ContactSpec>(specs.shape(0)), 0};
  for (size_t k = 0; k < plan.specs.size(); ++k) {
    const double* s = specs.data() + 4 * k;
    const int rows = static_cast<int>(s[0]), frame = static_cast<int>(s[1]), ref = static_cast<int>(s[2]);
    if (!(rows == 3 || rows == 6) || !(frame >= 0 && frame < md.view.nf) || !(ref >= LOCAL && ref <= LOCAL_WORLD_ALIGNED) ||
        !(s[3] >= 0.0 && s[3] < 1e300) || static_cast<double>(frame) != s[1])
      throw nb::value_error("contact specs: rows [3|6, frame index, reference code 0..2, K_d >= 0] expected");
    plan.specs[k] = ContactSpec{rows, frame, ref, s[3]};
    plan.m += rows;
  }
  return plan;
}

}  // namespace

const Options& fdcore::options_of(const ModelData& md, const CallOptions* o) {
  static const Options defaults{};
  if (o == nullptr) return defaults;
  if (o->model != nullptr && o->model != &md) throw nb::type_error("featherdyn.core: a contact plan made for another model");
  return o->opt;
}

void fdcore::bind_options(nb::module_& m) {
  nb::class_<ContactPlan>(m, "ContactPlan", "contacts (nc, 4) specs checked for one model (contacts.hpp)")
      .def(nb::new_(&make_contact_plan), nb::arg("model"), arr("specs"))
      .def_prop_ro("m", [](const ContactPlan& p) { return p.m; });
  nb::class_<CallOptions>(m, "Options", "a call's options (core/cpp/declare.hpp: Options), made once and reused")
      .def("__init__",
           [](CallOptions* o, bool gravity, int frame, int reference, int rows, const ContactPlan* plan, double mu,
              int max_iter, double tol, double singular_tol, double restitution) {
             new (o) CallOptions{Options{gravity, frame, reference, rows, nullptr, 0, mu, max_iter, tol, singular_tol,
                                         restitution},
                                 nullptr};
             if (plan != nullptr) {  // (the plan's m wins over `rows`)
               o->opt.contacts = plan->specs.data();
               o->opt.nc = static_cast<int>(plan->specs.size());
               o->opt.rows = plan->m;
               o->model = plan->model;
             }
           },
           nb::kw_only(), nb::arg("gravity") = true, nb::arg("frame") = 0, nb::arg("reference") = 0,
           nb::arg("rows") = 0, nb::arg("plan").none() = nb::none(), nb::arg("mu") = 0.0, nb::arg("max_iter") = 50,
           nb::arg("tol") = 1e-12, nb::arg("singular_tol") = 0.0, nb::arg("restitution") = 0.0,
           nb::keep_alive<1, 6>())
      .def_prop_ro("rows", [](const CallOptions& o) { return o.opt.rows; });
}
