// The binding's families (docs/architecture.md, "The glue"): each bind_<family>.cpp defines its entry points and
// registers them; the module (bindings.cpp) calls them.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include <cstdint>

#include "boundary.hpp"
#include "declare.hpp"
#include "model_view.hpp"

namespace fdcore {

namespace nb = nanobind;

// the families' registrations
void bind_dynamics(nb::module_& m);
void bind_options(nb::module_& m);
void bind_jax(nb::module_& m);  // (bind_jax.cpp: empty without XLA's FFI headers)
void bind_public_calls(nb::module_& m);

// A call's options (declare.hpp) as Python gives them (featherdyn.core._core.Options), with the model its contacts
// were checked against (nullptr: no contacts).
struct CallOptions {
  Options opt;
  const ModelData* model = nullptr;
};
// The options of a call on `md` (nullptr: the defaults); TypeError for contacts made for another model.
const Options& options_of(const ModelData& md, const CallOptions* o);

// an array argument: noconvert (no implicit copies or casts); opt: an optional one, which accepts None
inline auto arr(const char* name) { return nb::arg(name).noconvert(); }
inline auto opt(const char* name) { return nb::arg(name).noconvert().none(); }

}  // namespace fdcore
