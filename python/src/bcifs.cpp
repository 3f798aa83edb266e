// SPDX-License-Identifier: MIT
// cifs Python bindings — bcifs (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_bcifs(py::module_& m) { (void)m; }
void bind_bcifs_io(py::module_& m) { (void)m; }

}  // namespace cifs::python
