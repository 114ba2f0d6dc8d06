// The binding's families (docs/architecture.md, "The glue"): each bind_<family>.cpp defines its entry points and
// registers them; the module (bindings.cpp) calls the three.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include <cstdint>

#include "boundary.hpp"
#include "model_view.hpp"

namespace fdcore {

namespace nb = nanobind;

// the families' registrations
void bind_dynamics(nb::module_& m);
void bind_constraints(nb::module_& m);
void bind_public_calls(nb::module_& m);

// an array argument: noconvert (no implicit copies or casts); opt: an optional one, which accepts None
inline auto arr(const char* name) { return nb::arg(name).noconvert(); }
inline auto opt(const char* name) { return nb::arg(name).noconvert().none(); }

}  // namespace fdcore
