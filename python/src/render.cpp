// SPDX-License-Identifier: MIT
// cifs Python bindings — render (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_render(py::module_& m) { (void)m; }

}  // namespace cifs::python
