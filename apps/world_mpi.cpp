// SPDX-License-Identifier: MIT
// cifs — the MPI world: start, abort, and the tiled reduction of framebuffer shares.
#include <mpi.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "cifs/errors.hpp"
#include "world.hpp"

namespace cifs::cli {
namespace {

bool started = false;

/// Pixels per MPI_Reduce: 64 Ki pixels, 3.5 MiB of shares.
constexpr std::size_t kTilePixels = std::size_t{1} << 16;

/// The MPI_User_function: inout ← in ⊕ inout.
void reduce_shares(void* in, void* inout, int* length, MPI_Datatype* /*type*/) {
  const auto n = static_cast<std::size_t>(*length);
  render::combine_shares({static_cast<const render::PixelShare*>(in), n},
                         {static_cast<render::PixelShare*>(inout), n});
}

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

}  // namespace

World start_world(int& argc, char**& argv) {
  if (!launched_by_mpirun()) return {};
  if (MPI_Init(&argc, &argv) != MPI_SUCCESS) throw InvalidInput("MPI_Init failed");
  started = true;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return {static_cast<unsigned>(rank), static_cast<unsigned>(size)};
}

World& world() {
  static World current;
  return current;
}

void end_world() {
  if (started) MPI_Finalize();
  started = false;
}

void abort_world(int status) {
  if (started) MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

void combine_world(render::Share& share) {
  MPI_Datatype type = MPI_DATATYPE_NULL;
  MPI_Type_contiguous(static_cast<int>(sizeof(render::PixelShare)), MPI_BYTE, &type);
  MPI_Type_commit(&type);
  MPI_Op op = MPI_OP_NULL;
  MPI_Op_create(&reduce_shares, /*commute=*/1, &op);
  const std::size_t pixels = share.image.width * share.image.height;
  std::vector<render::PixelShare> mine(std::min(pixels, kTilePixels)),
      all(share.part.index == 0 ? mine.size() : 0);
  for (std::size_t first = 0; first < pixels; first += kTilePixels) {
    const std::size_t n = std::min(kTilePixels, pixels - first);
    render::pack(share, first, {mine.data(), n});
    MPI_Reduce(mine.data(), all.data(), static_cast<int>(n), type, op, 0, MPI_COMM_WORLD);
    if (share.part.index == 0) render::unpack(share, first, {all.data(), n});
  }
  MPI_Op_free(&op);
  MPI_Type_free(&type);
}

}  // namespace cifs::cli
