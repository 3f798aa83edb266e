// SPDX-License-Identifier: MIT
// cifs — the slot where the optional OpenCASCADE component plugs its STEP/IGES codec in (cifs/io/cad.hpp).
#include "cifs/io/cad.hpp"

#include "cifs/errors.hpp"
#include "cifs/files.hpp"

namespace cifs::io {
namespace {

CadCodec& installed() {
  static CadCodec codec;
  return codec;
}

CadCodec (*&loader())() {
  static CadCodec (*function)() = nullptr;
  return function;
}

}  // namespace

std::optional<CadFormat> cad_format(const std::filesystem::path& path) {
  const std::string extension = extension_of(path);
  if (extension == ".step" || extension == ".stp") return CadFormat::step;
  if (extension == ".igs" || extension == ".iges") return CadFormat::iges;
  return std::nullopt;
}

void set_cad_codec(const CadCodec& codec) {
  installed() = codec;
}

void set_cad_loader(CadCodec (*function)()) {
  loader() = function;
}

const CadCodec& cad_codec(std::string_view where) {
  CadCodec& codec = installed();
  if ((codec.read == nullptr || codec.write == nullptr) && loader() != nullptr) {
    try {
      codec = loader()();
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(where) + ": " + e.what());
    }
  }
  if (codec.read == nullptr || codec.write == nullptr)
    throw InvalidInput(
        std::string(where) +
        ": built without OpenCASCADE: STEP and IGES files need the cifs::occt component "
        "(install libocct-data-exchange-dev and configure with -DCIFS_OCCT=ON, docs/install.md)");
  return codec;
}

}  // namespace cifs::io
