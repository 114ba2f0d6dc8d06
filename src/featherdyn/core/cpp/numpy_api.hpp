// NumPy's C API, through its headers (docs/architecture.md, "The boundary"): the one place the core
// includes them. The API table is imported once, at the module's import (import_numpy, called by the
// translation unit that defines FEATHERDYN_NUMPY_IMPORT); every other file sees the same table through
// PY_ARRAY_UNIQUE_SYMBOL, as NumPy's documentation prescribes for extensions of several files.
//
// Built against NumPy 2's headers for NumPy 1.23 and later (NPY_TARGET_VERSION): one binary for
// NumPy 1.23-1.26 and 2.x. Only documented functions and macros (PyArray_CheckExact, PyArray_TYPE,
// PyArray_CHKFLAGS, PyArray_DATA, PyArray_SimpleNew, PyArray_NewFromDescr, PyArray_SetBaseObject, ...): no struct is read by
// hand and no table entry is taken by its index.
#pragma once

#include <Python.h>

#define NPY_NO_DEPRECATED_API NPY_1_23_API_VERSION
#define NPY_TARGET_VERSION NPY_1_23_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL featherdyn_ARRAY_API
#ifndef FEATHERDYN_NUMPY_IMPORT
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

namespace fdcore {

#ifdef FEATHERDYN_NUMPY_IMPORT
// Import NumPy's C API (0, or -1 with a Python exception set).
inline int import_numpy() { return PyArray_ImportNumPyAPI(); }
#endif

// An exact numpy.ndarray of native-endian float64, C-contiguous and aligned (and writeable if asked): the
// arrays whose memory the core reads and writes as they are. Anything else (a subclass, another dtype or
// byte order, a strided view) is for the Python wrapper to convert.
inline bool is_native_f64(PyObject* o, bool writeable) noexcept {
  if (!PyArray_CheckExact(o)) return false;
  PyArrayObject* a = reinterpret_cast<PyArrayObject*>(o);
  const int need = NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED | (writeable ? NPY_ARRAY_WRITEABLE : 0);
  return PyArray_TYPE(a) == NPY_DOUBLE && PyArray_ISNOTSWAPPED(a) && PyArray_CHKFLAGS(a, need);
}

// A fresh C-contiguous float64 array of this shape (new reference; nullptr with an exception set).
inline PyObject* new_f64(int nd, const npy_intp* dims) {
  return PyArray_SimpleNew(nd, const_cast<npy_intp*>(dims), NPY_DOUBLE);
}

// Where a one-state result of at least `min_bytes` takes its memory: `fn(shape)`, the batches' reused memory
// (core/_result_pool.py's result_array, set at import: set_result_allocator; a strong reference, kept).
struct ResultAllocator {
  PyObject* fn = nullptr;
  npy_intp min_bytes = 0;
};
inline ResultAllocator result_allocator;

// A C-contiguous float64 array of this shape for a result (new reference; nullptr with an exception set): from
// result_allocator when it is set and the array that large, else fresh (new_f64).
inline PyObject* result_f64(int nd, const npy_intp* dims) {
  npy_intp n = 1;
  for (int d = 0; d < nd; ++d) n *= dims[d];
  if (result_allocator.fn == nullptr || 8 * n < result_allocator.min_bytes) return new_f64(nd, dims);
  PyObject* shape = PyTuple_New(nd);
  for (int d = 0; shape != nullptr && d < nd; ++d) {
    PyObject* length = PyLong_FromSsize_t(dims[d]);
    if (length == nullptr) Py_CLEAR(shape);
    else PyTuple_SET_ITEM(shape, d, length);
  }
  PyObject* a = shape != nullptr ? PyObject_CallOneArg(result_allocator.fn, shape) : nullptr;
  Py_XDECREF(shape);
  if (a == nullptr) return nullptr;
  bool right = is_native_f64(a, true) && PyArray_NDIM(reinterpret_cast<PyArrayObject*>(a)) == nd;
  for (int d = 0; right && d < nd; ++d) right = PyArray_DIM(reinterpret_cast<PyArrayObject*>(a), d) == dims[d];
  if (right) return a;
  Py_DECREF(a);
  PyErr_SetString(PyExc_RuntimeError, "featherdyn.core: the result allocator did not return a float64 array of the shape");
  return nullptr;
}

// A read-only float64 array over `data`, kept alive by `owner` (new reference; nullptr with an exception set).
inline PyObject* f64_view(int nd, const npy_intp* dims, char* data, PyObject* owner) {
  PyObject* a = PyArray_NewFromDescr(&PyArray_Type, PyArray_DescrFromType(NPY_DOUBLE), nd,
                                     const_cast<npy_intp*>(dims), nullptr, data, NPY_ARRAY_CARRAY_RO, nullptr);
  if (a == nullptr) return nullptr;
  Py_INCREF(owner);
  if (PyArray_SetBaseObject(reinterpret_cast<PyArrayObject*>(a), owner) != 0) {  // (steals owner)
    Py_DECREF(a);
    return nullptr;
  }
  return a;
}

// Make an array read-only (a record's results: NumPy's documented flag, cleared as ndarray.flags.writeable = False does).
inline void make_read_only(PyObject* a) { PyArray_CLEARFLAGS(reinterpret_cast<PyArrayObject*>(a), NPY_ARRAY_WRITEABLE); }

inline double* f64_data(PyObject* a) { return static_cast<double*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(a))); }

}  // namespace fdcore
