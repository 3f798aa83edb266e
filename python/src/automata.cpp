// SPDX-License-Identifier: MIT
// cifs Python bindings — automata (to be written).
#include "bindings.hpp"

namespace cifs::python {

void bind_automata(py::module_& m) { (void)m; }

}  // namespace cifs::python
