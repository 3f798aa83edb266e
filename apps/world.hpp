// SPDX-License-Identifier: MIT
// cifs — the processes of a run: MPI's world under mpirun (built with -DCIFS_MPI=ON), else one.
// The only place the CLI meets MPI; the library knows parts and shares (cifs/render/partial.hpp).
#pragma once

#include "cifs/render/partial.hpp"

namespace cifs::cli {

struct World {
  unsigned rank = 0;
  unsigned size = 1;
};

/// Starts MPI when the process was launched by mpirun (Open MPI's or a PMI launcher's environment)
/// and returns its rank and size; one process otherwise (MPI is not initialised then). Throws
/// InvalidInput when launched on several processes by a cifs built without MPI.
World start_world(int& argc, char**& argv);

/// The world start_world found (one process until it is set).
World& world();

/// Finalises MPI when start_world initialised it.
void end_world();

/// Stops every process of the world with `status` (MPI_Abort): the others may be waiting in a
/// reduction for this one.
[[noreturn]] void abort_world(int status);

/// Combines the shares of every process into the share of rank 0 (experiment::RunOptions::combine):
/// MPI_Reduce with combine_shares as a commutative user operation, tile by tile, so that the
/// buffers beyond the framebuffers stay at two tiles (docs/scaling.md).
void combine_world(render::Share& share);

}  // namespace cifs::cli
