// SPDX-License-Identifier: MIT
// cifs — BC-IFS files: the JSON format of docs/formats.md ("bcifs"), read and written.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/ifs/bcifs.hpp"
#include "cifs/types.hpp"

namespace cifs::io {

/// A BC-IFS and the control nets of its initial entries (`size(state) by cols` each; empty when
/// the file gives none).
struct BcifsFile {
  ifs::Bcifs system;
  std::vector<Points> nets;
};

/// `{"bcifs": {"cells", "transitions", "boundaries", "constraints", "initial"}}`. Errors are
/// IoError (syntax) or InvalidInput (content) with the JSON path of the offending value, e.g.
/// "tree.json: bcifs.transitions[2].matrix[1]: 2 entries, expected 3 (size of cell E)"; the
/// structure is then checked by ifs::validate (message prefixed by `where`).
BcifsFile parse_bcifs_json(std::string_view text, std::string_view where);

/// The same format; `nets` (one per initial entry, or none) are written with the initial entries.
/// Cell names must be free of '.' and '/' (unnamed cells are written "s<id>").
std::string to_json(const ifs::Bcifs& system, std::span<const Points> nets = {});

/// parse_bcifs_json of a file (IoError naming the path when it cannot be read).
BcifsFile read_bcifs(const std::filesystem::path& path);

}  // namespace cifs::io
