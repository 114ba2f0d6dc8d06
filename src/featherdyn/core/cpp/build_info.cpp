// featherdyn.core._core.build_info(): how this binary was built — the compiler, the build type, the instruction
// sets its batched kernels were compiled for and the one chosen at import, NumPy's C API (the headers it was
// compiled with and the oldest NumPy it runs with), nanobind, Python's ABI — for `featherdyn info --build` and for
// bug reports. The strings CMake knows (compiler, build type, NumPy's version) come as FEATHERDYN_BUILD_* macros
// (CMakeLists.txt); the rest from the headers themselves.
#include <Python.h>

#include "numpy_api.hpp"  // (NO_IMPORT_ARRAY here: bindings.cpp imports the API table)

#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>

#include <string>

#include "build_info.hpp"
#include "groups.hpp"

#ifndef FEATHERDYN_BUILD_COMPILER
#define FEATHERDYN_BUILD_COMPILER "unknown"
#endif
#ifndef FEATHERDYN_BUILD_TYPE
#define FEATHERDYN_BUILD_TYPE "unknown"
#endif
#ifndef FEATHERDYN_BUILD_NUMPY
#define FEATHERDYN_BUILD_NUMPY "unknown"
#endif
#ifndef FEATHERDYN_BUILD_PROCESSOR
#define FEATHERDYN_BUILD_PROCESSOR "unknown"
#endif
#ifndef FEATHERDYN_BUILD_JAX_FFI
#define FEATHERDYN_BUILD_JAX_FFI ""
#endif

namespace fdcore {

const fdgroup::GroupKernels& group_kernels();  // bindings.cpp: the kernels chosen at import

namespace {

// The oldest NumPy whose C API has this feature version (numpyconfig.h: NPY_<version>_API_VERSION).
const char* numpy_release(unsigned api) {
  switch (api) {
    case 0x10: return "1.23";
    case 0x11: return "1.25";
    case 0x12: return "2.0";
    case 0x13: return "2.1";
    case 0x14: return "2.3";
    case 0x15: return "2.4";
    default: return "?";
  }
}

std::string hex(unsigned x) {
  static const char digits[] = "0123456789abcdef";
  std::string s;
  do {
    s.insert(s.begin(), digits[x & 15u]);
    x >>= 4;
  } while (x != 0);
  return "0x" + s;
}

nanobind::dict build_info() {
  namespace nb = nanobind;
  nb::dict d;
  d["compiler"] = FEATHERDYN_BUILD_COMPILER;
  d["build_type"] = FEATHERDYN_BUILD_TYPE;
  d["processor"] = FEATHERDYN_BUILD_PROCESSOR;
  d["jax_ffi"] = FEATHERDYN_BUILD_JAX_FFI;  // the jaxlib whose XLA FFI headers built featherdyn.jax's handler, or ""
#if defined(FEATHERDYN_HAVE_AVX2)
  d["simd_compiled"] = nb::make_tuple("baseline", "avx2", "avx512");
#else
  d["simd_compiled"] = nb::make_tuple("baseline");
#endif
  d["simd"] = group_kernels().isa;
  d["simd_lanes"] = group_kernels().width;
  d["numpy_headers"] = FEATHERDYN_BUILD_NUMPY;
  d["numpy_api"] = hex(NPY_API_VERSION);
  d["numpy_target_api"] = hex(NPY_FEATURE_VERSION);
  d["numpy_minimum"] = numpy_release(NPY_FEATURE_VERSION);
  d["nanobind"] = std::to_string(NB_VERSION_MAJOR) + "." + std::to_string(NB_VERSION_MINOR) + "." +
                  std::to_string(NB_VERSION_PATCH);
  d["python"] = PY_VERSION;
#if defined(Py_LIMITED_API)
  d["stable_abi"] = true;
#else
  d["stable_abi"] = false;
#endif
  return d;
}

}  // namespace

void bind_build_info(nanobind::module_& m) {
  m.def("build_info", &build_info,
        nanobind::sig("def build_info() -> dict[str, str | int | bool | tuple[str, ...]]"),
        "How this binary was built: compiler, build_type, processor, simd_compiled (the instruction sets the batched "
        "kernels were compiled for), simd and simd_lanes (the ones chosen at import; FEATHERDYN_SIMD=baseline forces "
        "the portable kernels), numpy_headers, numpy_api, numpy_target_api and numpy_minimum (the NumPy C API: the "
        "headers compiled with and the oldest NumPy the binary runs with), nanobind, python, stable_abi.");
}

}  // namespace fdcore
