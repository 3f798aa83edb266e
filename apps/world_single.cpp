// SPDX-License-Identifier: MIT
// cifs — the world of a cifs built without MPI: one process; several launched by mpirun are refused.
#include <cstdlib>
#include <string>

#include "cifs/errors.hpp"
#include "world.hpp"

namespace cifs::cli {

World start_world(int& /*argc*/, char**& /*argv*/) {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* size = std::getenv(name); size != nullptr && std::string(size) != "1")
      throw InvalidInput("this cifs was built without MPI (configure with -DCIFS_MPI=ON) and cannot run on " +
                         std::string(size) + " processes");
  return {};
}

World& world() {
  static World current;
  return current;
}

void end_world() {}

void abort_world(int status) {
  std::exit(status);
}

void combine_world(render::Share& /*share*/) {
  throw InvalidInput("this cifs was built without MPI");
}

}  // namespace cifs::cli
