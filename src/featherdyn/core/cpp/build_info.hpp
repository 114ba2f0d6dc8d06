// featherdyn.core._core.build_info (build_info.cpp): how this binary was built. The module (bindings.cpp) calls
// bind_build_info once.
#pragma once

#include <nanobind/nanobind.h>

namespace fdcore {
void bind_build_info(nanobind::module_& m);
}  // namespace fdcore
