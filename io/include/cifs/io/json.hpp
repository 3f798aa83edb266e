// SPDX-License-Identifier: MIT
// cifs — the JSON formats (docs/formats.md, docs/experiments.md, docs/cli.md): shapes, control
// polygons, BC-IFS files, automata (read and written), experiment files (read), and the analysis
// of a subdivision scheme and of a mesh scheme's local matrices (written).
//
// Readers take the text and `where`, the name of its source in messages. Malformed JSON is an
// IoError naming the byte; content problems are InvalidInput with the JSON path of the offending
// value, e.g. "shape.json: curve.knots[3]: …".
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "cifs/automata/automaton.hpp"
#include "cifs/files.hpp"
#include "cifs/io/bcifs_file.hpp"
#include "cifs/io/experiment.hpp"
#include "cifs/io/polygon.hpp"
#include "cifs/io/shape.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/volume.hpp"
#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"

namespace cifs::io {

/// `{"curve": {...}}` or `{"surface": {...}}` (knots in the standard or the Rhino convention), or a
/// geomdl (NURBS-Python) export `{"shape": {"type": "curve" | "surface", "data": [...]}}`: every
/// shape of the file, in order.
std::vector<Shape> parse_shapes_json(std::string_view text, std::string_view where,
                                     const ShapeReadOptions& options = {});
/// The one shape of the file, or the one options.index selects (select_shape).
Shape parse_shape_json(std::string_view text, std::string_view where, const ShapeReadOptions& options = {});
/// Round-trip precision: parse_shape_json reads it back bit for bit.
std::string to_json(const Shape& shape);
/// The same bytes, handed to `out` a chunk at a time (io::write: large shapes never whole in memory).
void write_json(const Shape& shape, ByteSink& out);

/// A trivariate volume: `{"volume": {"degree": [p, q, r], "knots": [[u], [v], [w]], "points": [[[x, …]]],
/// "weights": [[[w]]]}}`, points[i][j][k] the control point (i, j, k) (the surface's layout with a third
/// direction; knots in the standard or the Rhino convention), or a geomdl export of type "volume" (5.x or
/// 6.x layout; `options.index` selects one entry of several). Errors name the JSON path.
nurbs::Volume parse_volume_json(std::string_view text, std::string_view where,
                                const ShapeReadOptions& options = {});
/// Whether `text` is a volume file (`{"volume": …}`, or a geomdl `"shape"` of type "volume"), unvalidated:
/// the commands that read shapes ask it first.
bool is_volume_json(std::string_view text);
/// Round-trip precision: parse_volume_json reads it back bit for bit.
std::string to_json(const nurbs::Volume& volume);
void write_json(const nurbs::Volume& volume, ByteSink& out);

/// `{"polygon": {"points": [[x, y], ...], "closed": true}}`.
Polygon parse_polygon_json(std::string_view text, std::string_view where);
/// One point per line, numbers with round-trip precision; reads back bit for bit.
std::string to_json(const Polygon& polygon);

/// `{"bcifs": {"cells", "transitions", "boundaries", "constraints", "initial"}}`, e.g.
/// "tree.json: bcifs.transitions[2].matrix[1]: 2 entries, expected 3 (size of cell E)"; the
/// structure is then checked by ifs::validate (message prefixed by `where`).
BcifsFile parse_bcifs_json(std::string_view text, std::string_view where);
/// The same format; `nets` (one per initial entry, or none) are written with the initial entries.
/// Cell names must be free of '.' and '/' (unnamed cells are written "s<id>").
std::string to_json(const ifs::Bcifs& system, std::span<const Points> nets = {});

/// An experiment (docs/experiments.md). Relative input paths (shape, automaton) are resolved
/// against `base`; output paths must be relative and stay inside the output directory (no "..",
/// no root); output keys are the formats of io::formats (docs/design.md).
Experiment parse_experiment(std::string_view text, std::string_view where, const std::filesystem::path& base);

/// `{"states": [{"id", "size", "recurrent", "window"?, "name"?}], "transitions": [{"from", "to",
/// "label", "matrix"}], "initial": [{"segment", "state", "interval": [start, end]}]}` (docs/cli.md).
/// Keys are written sorted, on one line. `name` is written only when it is not the default
/// "s<id>", `window` only when the state has one (knot data). Transitions are listed state by state
/// in out-edge order (the order of the children). The initial entries' `interval` is their knot
/// interval ([0, 0] when unset, as for every generic automaton); their `span` is not stored.
std::string to_json(const nurbs::KnotAutomaton& automaton);
/// A generic automaton: to_json(nurbs::without_knots(automaton)).
std::string to_json(const automata::Automaton& automaton);
/// The automaton of to_json: states, sizes, names (default "s<id>"), windows and recurrent flags as
/// written (not recomputed), transitions with their labels and matrices in out-edge order, initial
/// entries with their intervals (`span` = −1). Ids must be 0, 1, … in order; matrices `size(to) by
/// size(from)`. Errors name the JSON path: "a.json: transitions[3].matrix: 2 rows, expected 4 (size
/// of state 1)".
nurbs::KnotAutomaton parse_automaton_json(std::string_view text, std::string_view where);

/// The analysis of a scheme (`cifs scheme NAME --analyze`, docs/cli.md), indented by 2.
std::string analysis_json(const subdivision::Scheme& scheme, const subdivision::SchemeAnalysis& analysis);

/// Local subdivision matrices and their spectra (`cifs scheme MESH-SCHEME --analyze`, docs/cli.md),
/// indented by 2: the first as one object, or all of them as an array when `as_array`. Exact
/// matrices are written as strings ("3/16"), others and every spectrum as numbers. `verdicts` (empty
/// at boundary vertices) adds each C¹ verdict as "c1".
std::string local_analysis_json(std::span<const subdivision::LocalMatrix> matrices,
                                std::span<const subdivision::LocalSpectrum> spectra,
                                std::span<const subdivision::C1Verdict> verdicts, bool as_array);

}  // namespace cifs::io
