// SPDX-License-Identifier: MIT
// cifs::occt — STEP and IGES B-spline curves and surfaces through OpenCASCADE (OCCT, LGPL 2.1, linked
// dynamically). An optional component: built when OCCT is found (CIFS_OCCT), never linked by the other
// modules; `find_package(cifs COMPONENTS occt)`. No OCCT type appears here: the conversions take and
// give cifs's plain curves and surfaces (docs/formats.md, "STEP and IGES").
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cifs/io/cad.hpp"
#include "cifs/io/shape.hpp"

namespace cifs::occt {

/// Every B-spline curve and surface of a STEP or IGES file: its faces first (their surfaces), then the
/// curves of its edges that bound no face, in the order OpenCASCADE lists them. `bytes` are the file's
/// (STEP is parsed from them; IGES from `path`, which also names the file in messages).
/// Read exactly: B-spline and Bézier curves and surfaces, lines and planes (as degree-1 B-splines over
/// the edge's range or the face's parameter rectangle); a curve used over part of its range is cut
/// there by knot insertion; a periodic curve used over one period becomes a closed cifs curve, a
/// periodic surface its clamped equivalent. Not read (a warning each, never silently): circles,
/// conics, cylinders, cones, spheres, tori, offset, swept and other surfaces — their B-spline forms
/// change the parametrization. A face trimmed by anything but its parameter rectangle is refused
/// (InvalidInput naming it) unless options.ignore_trim: then its whole surface is read, with a warning.
/// InvalidInput when the file does not parse or holds no curve or surface cifs reads.
std::vector<io::Shape> read_cad(std::string_view bytes, const std::filesystem::path& path,
                                io::CadFormat format, const io::ShapeReadOptions& options = {});

/// The bytes of a STEP (AP214, curves as a geometric curve set, surfaces as untrimmed faces) or IGES
/// (entities 126 and 128) file holding `shapes`, reals written with 17 significant digits (OCCT's
/// default keeps 12 in STEP and 9 in IGES). Curves and surfaces of dimension 1 or 2 get zero
/// coordinates up to 3; closed curves are written as their expanded unclamped B-splines (the same
/// points). InvalidInput for a dimension above 3, or what OCCT refuses (an interior knot of multiplicity
/// degree + 1).
std::string write_cad(std::span<const io::Shape> shapes, io::CadFormat format);

/// read_cad and write_cad as io's codec, OpenCASCADE's message printers silenced (they write transfer
/// statistics to standard output).
io::CadCodec cad_codec();

/// Plugs read_cad and write_cad into io (io::set_cad_codec): io::read_shapes, io::write … then take
/// .step, .stp, .igs and .iges (the Python package calls it; the CLI loads the plugin
/// libcifs_occt_plugin.so, whose `cifs_occt_codec` returns cad_codec(), when it first needs it).
void enable_cad_formats();

}  // namespace cifs::occt
