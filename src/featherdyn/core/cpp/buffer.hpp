// F64In / F64Out: a borrowed float64 NumPy array for the one-state entry points, taken through
// the buffer protocol (PEP 3118), and their nanobind casters.
//
// Why not nb::ndarray here: nanobind imports a NumPy array through __dlpack__, which costs
// about 0.1 µs per array (a Python-level call with keyword arguments and a capsule); the
// buffer protocol costs a fraction of that, which is a third of a panda RNEA call. The rules
// are the same as the ndarray signature's: only native-endian ("d", "=d"), aligned,
// C-contiguous float64 is taken, and an output must be writable. Anything else fails the cast,
// so nanobind raises TypeError and the Python wrapper converts — no memory is reinterpreted.
// None casts to an invalid (absent) array; the entry points check the ones they require.
#pragma once

#include <Python.h>
#include <nanobind/nanobind.h>

#include <cstdint>
#include <cstring>

namespace fdcore {

template <bool Writable>
class F64Buffer {
 public:
  using Scalar = double;
  F64Buffer() = default;
  F64Buffer(const F64Buffer&) = delete;
  F64Buffer& operator=(const F64Buffer&) = delete;
  ~F64Buffer() {
    if (valid_) PyBuffer_Release(&view_);
  }

  // Borrow o's memory if it is a NumPy array (exactly: subclasses such as masked arrays carry
  // meaning the buffer does not, and go to the wrapper) holding native, aligned, C-contiguous
  // float64 (writable if asked).
  bool acquire(PyObject* o) noexcept {
    if (std::strcmp(Py_TYPE(o)->tp_name, "numpy.ndarray") != 0) return false;
    const int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (Writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(o, &view_, flags) != 0) {
      PyErr_Clear();
      return false;
    }
    const char* f = view_.format;
    const bool native_f64 =
        view_.itemsize == 8 && f != nullptr && (std::strcmp(f, "d") == 0 || std::strcmp(f, "=d") == 0);
    const bool aligned = reinterpret_cast<std::uintptr_t>(view_.buf) % alignof(double) == 0;
    if (!native_f64 || !aligned) {
      PyBuffer_Release(&view_);
      return false;
    }
    valid_ = true;
    return true;
  }

  bool is_valid() const { return valid_; }
  size_t ndim() const { return static_cast<size_t>(view_.ndim); }
  size_t shape(size_t d) const { return static_cast<size_t>(view_.shape[d]); }
  size_t size() const { return static_cast<size_t>(view_.len / 8); }
  double* data() const { return static_cast<double*>(view_.buf); }

 private:
  Py_buffer view_{};
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
