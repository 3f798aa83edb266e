// SPDX-License-Identifier: MIT
// cifs CLI — `cifs scheme`: curve subdivision schemes (analysis, refinement, catalogue), the local
// subdivision matrices of the mesh schemes at extraordinary vertices (analysis), and the schemes'
// part of the gallery.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cifs::cli {

struct SchemeOptions {
  std::string name;                 // catalogue name (see --list)
  std::vector<std::string> params;  // "k=v"
  bool analyze = false;
  std::filesystem::path refine;  // polygon file
  int steps = 1;
  std::string ends = "auto";    // auto | reflect | keep
  std::string format = "json";  // refine: a writable format of io::formats(Content::polygon);
                                // mesh schemes' analysis: json or table
  bool list = false;
  int max_power = 20;    // analysis: largest power L
  std::string valence;   // mesh schemes: "5"
  std::string valences;  // mesh schemes: "3..16" or "3,5,8"
  std::string boundary;  // mesh schemes: empty (interior vertex), or edge | corner (boundary vertex)
  std::string crease;    // mesh schemes: "K" (or a list, or "all"): sharp edges r_0 and r_K at --valence N
  std::string boundary_valence;  // mesh schemes: "K" (or a list): a boundary vertex with K faces
  bool dart = false;             // mesh schemes: one sharp edge (r_0)
  bool corner = false;           // mesh schemes: the vertex infinitely sharp (with --crease or a boundary)
  bool concave = false;          // a corner meant to span more than 180 degrees
  std::string rules;             // "" or "opensubdiv": OpenSubdiv's; "blz": Biermann–Levin–Zorin's
  std::string interior_corners;  // doo-sabin: "1100": a face touching the boundary, corner by corner
};

/// The text for stdout; InvalidInput / IoError on bad input.
std::string scheme(const SchemeOptions& options);

/// What write_scheme_gallery wrote: the SVG files (under its folder) with their titles, and a
/// one-line-per-file summary.
struct SchemeFigures {
  std::vector<std::filesystem::path> files;
  std::vector<std::string> titles;
  std::string summary;
};

/// Writes the seed figures (seed 000: Lane–Riesenfeld and its 4-/6-point variants on hepta, bone,
/// infinity, sumsign, clover; seed 001: Chaikin open/closed, the generalised 4-point tension
/// sweep, corner cutting with b = 1 − a and b ≠ 1 − a) as SVG into `folder` (created), the seed
/// shapes read from `examples`/shapes.
SchemeFigures write_scheme_gallery(const std::filesystem::path& folder,
                                   const std::filesystem::path& examples);

}  // namespace cifs::cli
