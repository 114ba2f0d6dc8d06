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
//
// Faster still, for the common case: an exact numpy.ndarray whose dtype object is NumPy's native
// float64 singleton and whose flags say C-contiguous and aligned (and writeable for an output) is
// read from the array object's fields directly (NumPy's PyArrayObject_fields, its documented and
// stable ABI), ~40 ns less per array than PyObject_GetBuffer, which formats and compares a buffer
// description on every call. init_ndarray_fields() checks that layout once, at import, on arrays it
// makes; if anything differs (another NumPy), only the buffer protocol is used.
#pragma once

#include <Python.h>
#include <nanobind/nanobind.h>

#include <cstdint>
#include <cstring>

namespace fdcore {

// The leading fields of a NumPy array object (numpy/ndarraytypes.h: PyArrayObject_fields).
struct NdarrayFields {
  PyObject_HEAD
  char* data;
  int nd;
  Py_ssize_t* dimensions;
  Py_ssize_t* strides;
  PyObject* base;
  PyObject* descr;
  int flags;
};

// numpy.ndarray and numpy.dtype("float64") when the field layout checked out at import, else nullptr.
struct NdarrayFast {
  PyTypeObject* type = nullptr;
  PyObject* float64 = nullptr;
  // NumPy's NPY_ARRAY_C_CONTIGUOUS, NPY_ARRAY_ALIGNED, NPY_ARRAY_WRITEABLE
  static constexpr int C_CONTIGUOUS = 0x0001, ALIGNED = 0x0100, WRITEABLE = 0x0400;
};
inline NdarrayFast ndarray_fast;

template <bool Writable>
class F64Buffer {
 public:
  using Scalar = double;
  F64Buffer() = default;
  F64Buffer(const F64Buffer&) = delete;
  F64Buffer& operator=(const F64Buffer&) = delete;
  ~F64Buffer() {
    if (view_.obj != nullptr) PyBuffer_Release(&view_);
  }

  // Borrow o's memory if it is a NumPy array (exactly: subclasses such as masked arrays carry
  // meaning the buffer does not, and go to the wrapper) holding native, aligned, C-contiguous
  // float64 (writable if asked).
  bool acquire(PyObject* o) noexcept {
    if (Py_TYPE(o) == ndarray_fast.type) {
      const NdarrayFields* a = reinterpret_cast<const NdarrayFields*>(o);
      constexpr int need = NdarrayFast::C_CONTIGUOUS | NdarrayFast::ALIGNED | (Writable ? NdarrayFast::WRITEABLE : 0);
      if (a->descr == ndarray_fast.float64 && (a->flags & need) == need &&
          reinterpret_cast<std::uintptr_t>(a->data) % alignof(double) == 0) {
        data_ = reinterpret_cast<double*>(a->data);
        ndim_ = a->nd;
        shape_ = a->dimensions;
        valid_ = true;
        return true;
      }
    }
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
    data_ = static_cast<double*>(view_.buf);
    ndim_ = view_.ndim;
    shape_ = view_.shape;
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
  Py_buffer view_{};  // held (view_.obj set) only when taken through the buffer protocol
  double* data_ = nullptr;
  int ndim_ = 0;
  const Py_ssize_t* shape_ = nullptr;
  bool valid_ = false;
};

// Enable F64Buffer's direct path if NumPy's arrays have the expected fields: a (2, 3) float64 array,
// a read-only one and a transposed one must read back as NumPy reports them. Called once at import.
inline void init_ndarray_fields() {
  namespace nb = nanobind;
  try {
    nb::module_ np = nb::module_::import_("numpy");
    nb::object f64 = np.attr("dtype")("float64");
    nb::object a = np.attr("empty")(nb::make_tuple(2, 3), f64);
    nb::object ro = a.attr("copy")();
    ro.attr("setflags")(nb::arg("write") = false);
    nb::object t = a.attr("T");
    auto fields = [](const nb::object& x) { return reinterpret_cast<const NdarrayFields*>(x.ptr()); };
    auto data = [](const nb::object& x) {
      return nb::cast<std::uintptr_t>(x.attr("__array_interface__")["data"][0]);
    };
    const NdarrayFields* fa = fields(a);
    const int need = NdarrayFast::C_CONTIGUOUS | NdarrayFast::ALIGNED | NdarrayFast::WRITEABLE;
    const bool ok = Py_TYPE(a.ptr()) == reinterpret_cast<PyTypeObject*>(np.attr("ndarray").ptr()) &&
                    fa->descr == a.attr("dtype").ptr() && fa->descr == f64.ptr() && fa->nd == 2 &&
                    fa->dimensions[0] == 2 && fa->dimensions[1] == 3 && fa->strides[0] == 24 &&
                    reinterpret_cast<std::uintptr_t>(fa->data) == data(a) && (fa->flags & need) == need &&
                    (fields(ro)->flags & NdarrayFast::WRITEABLE) == 0 &&
                    (fields(t)->flags & NdarrayFast::C_CONTIGUOUS) == 0 && fields(t)->dimensions[0] == 3;
    if (ok) {
      ndarray_fast.type = reinterpret_cast<PyTypeObject*>(np.attr("ndarray").inc_ref().ptr());
      ndarray_fast.float64 = f64.inc_ref().ptr();  // both kept for the life of the process
    }
  } catch (const nb::python_error&) {
    // no direct path: the buffer protocol only
  }
}

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
