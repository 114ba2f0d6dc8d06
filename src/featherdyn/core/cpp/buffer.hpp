// F64In / F64Out: a borrowed float64 NumPy array for the one-state entry points, and their nanobind casters.
//
// Why not nb::ndarray here: nanobind imports a NumPy array through __dlpack__, which costs about 0.1 µs per
// array (a Python-level call with keyword arguments and a capsule), a third of a panda RNEA call. These read
// the array through NumPy's C API instead (numpy_api.hpp: is_native_f64, PyArray_DATA, PyArray_DIMS): only an
// exact numpy.ndarray of native-endian float64 (any spelling of it: 'd', '<f8' on a little-endian machine,
// '=f8'), aligned and C-contiguous, and writeable for an output. Anything else fails the cast, so nanobind
// raises TypeError and the Python wrapper converts — no memory is reinterpreted. None casts to an invalid
// (absent) array; the entry points check the ones they require.
#pragma once

#include <Python.h>
#include <nanobind/nanobind.h>

#include <cstddef>

#include "numpy_api.hpp"

namespace fdcore {

template <bool Writable>
class F64Buffer {
 public:
  using Scalar = double;
  F64Buffer() = default;
  F64Buffer(const F64Buffer&) = delete;
  F64Buffer& operator=(const F64Buffer&) = delete;

  // Borrow o's memory if it is an exact NumPy array of native, aligned, C-contiguous float64 (writeable if
  // asked); subclasses such as masked arrays carry meaning the memory does not, and go to the wrapper.
  bool acquire(PyObject* o) noexcept {
    if (!is_native_f64(o, Writable)) return false;
    PyArrayObject* a = reinterpret_cast<PyArrayObject*>(o);
    data_ = static_cast<double*>(PyArray_DATA(a));
    ndim_ = PyArray_NDIM(a);
    shape_ = PyArray_DIMS(a);
    valid_ = true;
    return true;
  }

  bool is_valid() const { return valid_; }
  size_t ndim() const { return static_cast<size_t>(ndim_); }
  size_t shape(size_t d) const { return static_cast<size_t>(shape_[d]); }
  size_t size() const {
    size_t n = 1;
    for (int d = 0; d < ndim_; ++d) n *= static_cast<size_t>(shape_[d]);
    return n;
  }
  double* data() const { return data_; }

 private:
  double* data_ = nullptr;
  int ndim_ = 0;
  const npy_intp* shape_ = nullptr;
  bool valid_ = false;
};

using F64In = F64Buffer<false>;
using F64Out = F64Buffer<true>;

}  // namespace fdcore

namespace nanobind::detail {

template <bool Writable>
struct type_caster<fdcore::F64Buffer<Writable>> {
  NB_TYPE_CASTER(fdcore::F64Buffer<Writable>, const_name("numpy.ndarray[float64]"))
  bool from_python(handle src, uint32_t, cleanup_list*) noexcept {
    if (src.is_none()) return true;  // absent
    return value.acquire(src.ptr());
  }
};

}  // namespace nanobind::detail
