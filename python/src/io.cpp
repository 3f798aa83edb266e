// SPDX-License-Identifier: MIT
// cifs Python bindings — io (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_io(py::module_& m) { (void)m; }
void bind_verify(py::module_& m) { (void)m; }
void bind_experiment(py::module_& m) { (void)m; }

}  // namespace cifs::python
