// SPDX-License-Identifier: MIT
// cifs Python bindings — nurbs (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_nurbs(py::module_& m) { (void)m; }

}  // namespace cifs::python
