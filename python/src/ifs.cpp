// SPDX-License-Identifier: MIT
// cifs Python bindings — ifs (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_ifs(py::module_& m) { (void)m; }

}  // namespace cifs::python
