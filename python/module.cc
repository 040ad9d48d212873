// The Python extension _msdeform, re-exported by the package msdeform
// (python/msdeform/__init__.py). Each Bind* function is in its own file.

#include "msdeform/core/build_info.h"
#include "python/bindings.h"

PYBIND11_MODULE(_msdeform, m) {
  namespace python = msdeform::python;
  m.doc() =
      "msdeform's C++ library: mesh and handle files, the editing methods (the multi-scale "
      "method of Liu & Su 2008 and the others) and their options, and the experiments' "
      "scenarios, runner and metrics, on NumPy arrays. Import the package msdeform rather than "
      "this module.";
  m.attr("__version__") = msdeform::MsdeformVersion();
  m.attr("COMMIT") = msdeform::MsdeformCommit();
  python::BindIo(m);
  python::BindOptions(m);
  python::BindMethod(m);
  python::BindExperiments(m);
  python::BindFlags(m);
}
