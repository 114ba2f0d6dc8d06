// The binding of a call's options (declare.hpp: Options; docs/architecture.md, "One declaration per algorithm"): the
// parameters a declared algorithm takes besides its arrays, given to a Kernel's front ends by name, and the contacts'
// plan they may carry (its specs checked once, kept by the caller's plan cache: featherdyn/constraints.py).
#include "declare.hpp"
#include "frames.hpp"
#include "entry_points.hpp"

#include <string>

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

Options fdcore::options_of(const ModelData& md, const nb::kwargs& given) {
  Options o;
  for (auto [key, value] : given) {
    const std::string name = nb::cast<std::string>(key);
    try {
      if (name == "gravity") o.gravity = nb::cast<bool>(value);
      else if (name == "frame") o.frame = nb::cast<int>(value);
      else if (name == "reference") o.reference = nb::cast<int>(value);
      else if (name == "rows") o.rows = nb::cast<int>(value);
      else if (name == "mu") o.mu = nb::cast<double>(value);
      else if (name == "max_iter") o.max_iter = nb::cast<int>(value);
      else if (name == "tol") o.tol = nb::cast<double>(value);
      else if (name == "singular_tol") o.singular_tol = nb::cast<double>(value);
      else if (name != "plan") throw nb::type_error(("featherdyn.core: no option " + name).c_str());
    } catch (const nb::cast_error&) {
      throw nb::type_error(("featherdyn.core: option " + name + " of another type").c_str());
    }
  }
  if (given.contains("plan") && !given["plan"].is_none()) {  // (after `rows`: the plan's m wins)
    const ContactPlan* plan = nullptr;
    if (!nb::try_cast(given["plan"], plan) || plan == nullptr) throw nb::type_error("featherdyn.core: plan: a ContactPlan");
    if (plan->model != &md) throw nb::type_error("featherdyn.core: a contact plan made for another model");
    o.contacts = plan->specs.data();
    o.nc = static_cast<int>(plan->specs.size());
    o.rows = plan->m;
  }
  return o;
}

void fdcore::bind_options(nb::module_& m) {
  nb::class_<ContactPlan>(m, "ContactPlan", "contacts (nc, 4) specs checked for one model (contacts.hpp)")
      .def(nb::new_(&make_contact_plan), nb::arg("model"), arr("specs"))
      .def_prop_ro("m", [](const ContactPlan& p) { return p.m; });
}
