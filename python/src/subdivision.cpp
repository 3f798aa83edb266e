// SPDX-License-Identifier: MIT
// cifs Python bindings — subdivision (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_subdivision(py::module_& m) { (void)m; }

}  // namespace cifs::python
