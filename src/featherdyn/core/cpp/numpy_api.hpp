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

inline double* f64_data(PyObject* a) { return static_cast<double*>(PyArray_DATA(reinterpret_cast<PyArrayObject*>(a))); }

}  // namespace fdcore
