// SPDX-License-Identifier: MIT
// cifs — the CLI opens OpenCASCADE (libcifs_occt_plugin.so) when it first needs it (occt_plugin.cpp).
#pragma once

#include "cifs/io/cad.hpp"

namespace cifs::cli {

/// Makes io open the plugin the first time a STEP or IGES file is read or written.
void load_occt_on_demand();

}  // namespace cifs::cli
