// SPDX-License-Identifier: MIT
// cifs — STEP (.step, .stp) and IGES (.igs, .iges) shape files. io knows their extensions (its format
// table lists them) but not how to read or write them: that is OpenCASCADE's work, in the optional
// component cifs::occt, which io never links (OCCT is LGPL and large). The component plugs its codec in
// here (occt::enable_cad_formats(), called by the Python package when built with it; the CLI loads it as a
// plugin when a STEP or IGES file is first met, set_cad_loader); until then every STEP or IGES read or
// write is an InvalidInput "built without OpenCASCADE: …".
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/io/shape.hpp"

namespace cifs::io {

enum class CadFormat { step, iges };

/// The CAD format of a path's extension (.step and .stp: STEP; .igs and .iges: IGES; any case), if any.
std::optional<CadFormat> cad_format(const std::filesystem::path& path);

/// What cifs::occt plugs in. `read`: every curve and surface of the file at `path`, whose bytes are
/// `bytes` (read by io::read_file: checked and recorded as an input of the run; OpenCASCADE reads IGES
/// from the path again); the options as for the other shape readers. `write`: the bytes of a file
/// holding `shapes`.
struct CadCodec {
  std::vector<Shape> (*read)(std::string_view bytes, const std::filesystem::path& path, CadFormat format,
                             const ShapeReadOptions& options) = nullptr;
  std::string (*write)(std::span<const Shape> shapes, CadFormat format) = nullptr;
};

/// Installs the codec for the whole process (not thread-safe against concurrent reads: call it first).
void set_cad_codec(const CadCodec& codec);

/// Installs a function that supplies the codec the first time a STEP or IGES file is met: the CLI loads
/// OpenCASCADE (a plugin, dlopen) only then, since loading its 20 libraries at every start costs 0.1 s
/// of CPU per command. The loader throws InvalidInput when it cannot.
void set_cad_loader(CadCodec (*loader)());

/// The installed codec (from the loader, the first time, when one is set); InvalidInput "`where`: built
/// without OpenCASCADE: STEP and IGES files need the cifs::occt component (…)" when there is none.
const CadCodec& cad_codec(std::string_view where);

}  // namespace cifs::io
