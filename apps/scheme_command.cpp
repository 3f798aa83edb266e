// SPDX-License-Identifier: MIT
#include "scheme_command.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "cifs/errors.hpp"
#include "cifs/files.hpp"
#include "cifs/format.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/mesh_analysis.hpp"
#include "cifs/subdivision/refine.hpp"
#include "cifs/subdivision/scheme.hpp"
#include "cifs/suggest.hpp"
#include "commands.hpp"

namespace cifs::cli {
namespace {

namespace sd = cifs::subdivision;

/// `--rules NAME`: opensubdiv or blz, the flag named in a refusal.
RuleSet rules_flag(const std::string& name) {
  try {
    return named_rule_set(name);
  } catch (const InvalidInput& e) {
    throw InvalidInput("--rules " + name + ": " + e.what());
  }
}

/// `--boundary NAME` of a local analysis: edge or corner, the flag named in a refusal.
sd::BoundaryRule boundary_flag(const std::string& name) {
  const sd::BoundaryRule rule = name == "none" ? sd::BoundaryRule::none : [&] {
    try {
      return named_boundary_rule(name);
    } catch (const InvalidInput& e) {
      throw InvalidInput("--boundary " + name + ": " + e.what());
    }
  }();
  if (rule == sd::BoundaryRule::none)
    throw InvalidInput(
        "--boundary none: a local analysis takes a boundary vertex with the rule edge or corner");
  return rule;
}
using io::Stroke;
using io::strokes_svg;

std::map<std::string, std::string> parse_params(const std::vector<std::string>& params) {
  std::map<std::string, std::string> out;
  for (const std::string& p : params) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InvalidInput("--param '" + p + "': expected NAME=VALUE, e.g. --param w=0.0625");
    const std::string key = p.substr(0, eq);
    if (out.count(key)) throw InvalidInput("--param " + key + " is given twice");
    out[key] = p.substr(eq + 1);
  }
  return out;
}

std::string catalogue_text() {
  std::ostringstream s;
  for (const sd::SchemeSpec& spec : sd::scheme_catalogue()) {
    s << spec.name;
    for (const sd::ParameterSpec& p : spec.parameters)
      s << " " << p.name << "=" << (p.default_value.empty() ? "(required)" : p.default_value);
    s << "\n    " << spec.summary << "\n";
  }
  return s.str();
}

sd::Ends parse_ends(const std::string& ends) {
  if (ends == "auto") return sd::Ends::automatic;
  if (ends == "reflect") return sd::Ends::reflect;
  if (ends == "keep") return sd::Ends::keep;
  throw InvalidInput("--ends '" + ends + "': auto, reflect or keep");
}

// ------------------------------------------------------------------------------------------------
// Mesh schemes: local subdivision matrices

std::optional<sd::MeshScheme> mesh_scheme_named(const std::string& name) {
  for (const sd::SchemeTraits& t : sd::mesh_schemes())
    if (t.name == name) return t.scheme;
  return std::nullopt;
}

/// Refuses a name that is neither a curve scheme nor a mesh scheme: a typo of a mesh scheme is named here
/// (the curve schemes' refusal, the library's, knows only theirs), anything else by the library.
void check_scheme_name(const std::string& name) {
  std::vector<std::string> curves, all;
  for (const sd::SchemeSpec& s : sd::scheme_catalogue()) curves.push_back(s.name);
  if (mesh_scheme_named(name) || std::find(curves.begin(), curves.end(), name) != curves.end()) return;
  all = curves;
  for (const sd::SchemeTraits& t : sd::mesh_schemes()) all.emplace_back(t.name);
  if (const auto near = nearest(name, all); near && mesh_scheme_named(*near))
    throw InvalidInput("unknown scheme '" + name + "'; did you mean " + *near + "? (see cifs scheme --list)");
  (void)sd::named_scheme(name, {});  // throws the library's "unknown scheme 'NAME'" with its suggestion
}

int integer_text(const std::string& text, const std::string& option, const std::string& given) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size())
    throw InvalidInput(option + " '" + given + "': expected an integer, a range A..B or a list A,B,C");
  return value;
}

/// "5", "3..16", "3-16" or "3,5,8".
std::vector<int> parse_valences(const std::string& text, const std::string& option) {
  std::vector<int> out;
  const auto dots = text.find("..");
  const auto dash = text.find('-', 1);
  if (dots != std::string::npos || dash != std::string::npos) {
    const std::size_t at = dots != std::string::npos ? dots : dash;
    const int first = integer_text(text.substr(0, at), option, text);
    const int last = integer_text(text.substr(at + (dots != std::string::npos ? 2 : 1)), option, text);
    if (first > last)
      throw InvalidInput(option + " '" + text + "': the range is empty (write A..B with A ≤ B)");
    for (int n = first; n <= last; ++n) out.push_back(n);
    return out;
  }
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    out.push_back(integer_text(text.substr(begin, comma - begin), option, text));
    if (comma == std::string::npos) return out;
    begin = comma + 1;
  }
}

/// One line per valence: the numbers `cifs scheme … --analyze` prints as JSON, in columns.
std::string local_table(const std::vector<sd::LocalMatrix>& matrices,
                        const std::vector<sd::LocalSpectrum>& spectra,
                        const std::vector<sd::C1Verdict>& verdicts) {
  const sd::LocalMatrix& first = matrices.front();
  const bool tagged = std::any_of(matrices.begin(), matrices.end(), [](const sd::LocalMatrix& m) {
    return m.options.boundary || !m.options.sharp.empty() || m.options.corner;
  });
  const bool doo_sabin = first.scheme == sd::MeshScheme::doo_sabin;
  std::ostringstream s;
  s << "# " << sd::scheme_name(first.scheme) << ", "
    << (tagged && doo_sabin ? std::string("k-gon faces touching the boundary (class: interior corners, "
                                          "1 = interior; sectors: their runs)")
        : tagged            ? std::string("tagged and boundary vertices (sectors: faces between sharp edges)")
                            : std::string(doo_sabin ? "k-gon faces" : "interior vertices"))
    << ", S_n over " << first.steps << (first.steps == 1 ? " step" : " steps") << "\n";
  s << std::left << std::setw(4) << "n";
  if (tagged) s << std::setw(10) << "class" << std::setw(10) << "sectors";
  s << std::setw(6) << "size" << std::setw(7) << "exact" << std::setw(17) << "lambda1" << std::setw(17)
    << "lambda2" << std::setw(17) << "|mu|" << std::setw(17) << "lambda2^2/|mu|" << std::setw(11)
    << "curvature" << std::setw(24) << "spectral conditions" << (verdicts.empty() ? "" : "C1") << "\n";
  for (std::size_t i = 0; i < matrices.size(); ++i) {
    const sd::LocalSpectrum& sp = spectra[i];
    std::string checks;
    if (!sp.dominant_simple) checks += " lambda0=1-not-simple";
    if (!sp.subdominant_pair) checks += " lambda1!=lambda2";
    if (!sp.gap) checks += " no-gap";
    s << std::setw(4) << matrices[i].valence;
    if (tagged) {
      std::string sectors;
      for (const int k : sd::sector_sizes(matrices[i].valence, matrices[i].options))
        sectors += (sectors.empty() ? "" : ",") + std::to_string(k);
      std::string type = sd::vertex_class(matrices[i].valence, matrices[i].options);
      if (!matrices[i].options.interior_corners.empty()) {
        type.clear();
        for (const char c : matrices[i].options.interior_corners) type += c != 0 ? '1' : '0';
      }
      s << std::setw(10) << type << std::setw(10) << sectors;
    }
    s << std::setw(6) << matrices[i].values.rows() << std::setw(7) << (matrices[i].exact ? "yes" : "no")
      << std::setw(17) << number_text(static_cast<double>(sp.subdominant), 12) << std::setw(17)
      << number_text(static_cast<double>(sp.second), 12) << std::setw(17)
      << number_text(static_cast<double>(std::abs(sp.mu)), 12) << std::setw(17)
      << (sp.curvature_ratio ? number_text(static_cast<double>(*sp.curvature_ratio), 12) : "-")
      << std::setw(11) << sp.curvature << std::setw(24) << (checks.empty() ? "ok" : checks.substr(1));
    if (!verdicts.empty()) {
      const sd::C1Verdict& v = verdicts[i];
      s << (v.c1 ? "yes" : v.decided ? "no" : "undecided");
      if (!matrices[i].options.interior_corners.empty()) {
        s << " (" << (v.method == "bernstein" ? "proved" : "sampled") << " on the interior k-gon"
          << (v.c1 ? "; sector angle " +
                         number_text(static_cast<double>(v.angle * 180 / std::numbers::pi_v<long double>), 4)
                   : ": " + v.reason)
          << ")";
      } else if (!v.sectors.empty()) {
        s << " (sampled; sector angles";
        for (const sd::C1Verdict::Sector& sector : v.sectors)
          s << " "
            << (sector.verdict.spectral && !sector.verdict.through_centre
                    ? number_text(
                          static_cast<double>(sector.verdict.angle * 180 / std::numbers::pi_v<long double>),
                          4)
                    : "-");
        s << ")" << (v.c1 ? "" : ": " + v.reason);
      } else if (v.spectral) {
        s << " (" << (v.method == "bernstein" ? "proved" : "sampled") << ", winding " << v.winding << ")";
      }
    }
    s << "\n";
  }
  return s.str();
}

/// Doo–Sabin faces touching the boundary: `--interior-corners PATTERN` (one face), or every run of
/// 1 … K − 1 interior corners of each K-gon of `--boundary-valence`.
std::vector<std::pair<int, sd::LocalOptions>> doo_sabin_boundary_cases(const SchemeOptions& o) {
  if (!o.valence.empty() || !o.valences.empty() || !o.boundary.empty() || !o.crease.empty() || o.dart ||
      (!o.interior_corners.empty() && !o.boundary_valence.empty()))
    throw InvalidInput(
        "scheme doo-sabin: a face touching the boundary is --boundary-valence K (its corners) "
        "or --interior-corners PATTERN, nothing else");
  std::vector<std::vector<char>> patterns;
  if (!o.interior_corners.empty()) {
    std::vector<char> inner;
    for (const char c : o.interior_corners) {
      if (c != '0' && c != '1')
        throw InvalidInput("--interior-corners '" + excerpt(o.interior_corners) +
                           "': expected 1 (interior) or 0 (boundary) per corner, e.g. 1100");
      inner.push_back(c == '1' ? 1 : 0);
    }
    if (inner.size() < std::size_t{sd::kMinValence} || inner.size() > std::size_t{sd::kMaxValence})
      throw InvalidInput("--interior-corners '" + excerpt(o.interior_corners) + "': a face of " +
                         std::to_string(inner.size()) + " corners; doo-sabin's faces have " +
                         std::to_string(sd::kMinValence) + " to " + std::to_string(sd::kMaxValence) +
                         " corners here");
    patterns.push_back(std::move(inner));
  } else {
    for (const int k : parse_valences(o.boundary_valence, "--boundary-valence")) {
      if (k < sd::kMinValence || k > sd::kMaxValence)
        throw InvalidInput("--boundary-valence " + std::to_string(k) + ": doo-sabin's faces have " +
                           std::to_string(sd::kMinValence) + " to " + std::to_string(sd::kMaxValence) +
                           " corners here");
      for (int m = 1; m < k; ++m) {
        std::vector<char> inner(static_cast<std::size_t>(k), 0);
        std::fill_n(inner.begin(), m, 1);
        patterns.push_back(std::move(inner));
      }
    }
  }
  std::vector<std::pair<int, sd::LocalOptions>> out;
  for (std::vector<char>& inner : patterns) {
    const int k = static_cast<int>(inner.size());
    out.emplace_back(k, sd::LocalOptions{.boundary = true,
                                         .sharp = {},
                                         .corner = o.corner,
                                         .concave = o.concave,
                                         .rules = o.rules.empty() ? RuleSet::opensubdiv : rules_flag(o.rules),
                                         .interior_corners = std::move(inner)});
  }
  return out;
}

/// The (valence, options) pairs the flags ask for, in the order given.
std::vector<std::pair<int, sd::LocalOptions>> local_cases(const std::string& name, const SchemeOptions& o) {
  if (name == "doo-sabin" && (!o.boundary_valence.empty() || !o.interior_corners.empty()))
    return doo_sabin_boundary_cases(o);
  if (!o.interior_corners.empty())
    throw InvalidInput("scheme " + name +
                       ": --interior-corners is said of a doo-sabin face touching the boundary");
  const bool boundary_faces = !o.boundary_valence.empty();
  if (boundary_faces == (!o.valence.empty() || !o.valences.empty()) ||
      (!o.valence.empty() && !o.valences.empty()))
    throw InvalidInput("scheme " + name +
                       ": give --valence N or --valences A..B (one of them), or --boundary-valence K");
  if (boundary_faces && (!o.boundary.empty() || !o.crease.empty() || o.dart))
    throw InvalidInput("scheme " + name + ": --boundary-valence K takes no --boundary, --crease or --dart");
  if (o.dart && (!o.crease.empty() || o.corner || !o.boundary.empty()))
    throw InvalidInput("scheme " + name +
                       ": --dart is one sharp edge at an interior vertex: no --crease, "
                       "--corner or --boundary");
  if (o.corner && o.crease.empty() && !boundary_faces && o.boundary.empty())
    throw InvalidInput("scheme " + name + ": --corner needs --crease K or --boundary-valence K");
  if (o.concave && !o.corner) throw InvalidInput("scheme " + name + ": --concave is said of a --corner");
  if (!o.crease.empty() && !o.boundary.empty())
    throw InvalidInput("scheme " + name + ": --crease is at an interior vertex (no --boundary)");
  sd::LocalOptions base{.boundary = boundary_faces || !o.boundary.empty(),
                        .rule = o.boundary.empty() ? sd::BoundaryRule::edge_only : boundary_flag(o.boundary),
                        .sharp = {},
                        .corner = o.corner,
                        .concave = o.concave,
                        .rules = o.rules.empty() ? RuleSet::opensubdiv : rules_flag(o.rules)};
  if (o.dart) base.sharp = {0};
  std::vector<std::pair<int, sd::LocalOptions>> out;
  if (boundary_faces) {
    for (const int k : parse_valences(o.boundary_valence, "--boundary-valence"))
      out.emplace_back(k + 1, base);
    return out;
  }
  const std::vector<int> valences =
      o.valence.empty() ? parse_valences(o.valences, "--valences") : parse_valences(o.valence, "--valence");
  for (const int n : valences) {
    if (o.crease.empty()) {
      out.emplace_back(n, base);
      continue;
    }
    std::vector<int> sides;
    if (o.crease == "all")
      for (int k = 1; k < n; ++k) sides.push_back(k);
    else
      sides = parse_valences(o.crease, "--crease");
    for (const int k : sides) {
      sd::LocalOptions crease = base;
      crease.sharp = {0, k};
      if (k <= 0 || k >= n)  // the library would name edge K; the flag counts faces
        throw InvalidInput("--crease " + std::to_string(k) + ": expected 1 to " + std::to_string(n - 1) +
                           " faces on one side at valence " + std::to_string(n));
      out.emplace_back(n, crease);
    }
  }
  return out;
}

std::string analyze_mesh_scheme(sd::MeshScheme scheme, const SchemeOptions& o) {
  const std::string name(sd::scheme_name(scheme));
  if (!o.analyze || !o.refine.empty())
    throw InvalidInput(
        "scheme " + name +
        ": a mesh scheme takes --analyze with --valence N, --valences A..B or --boundary-valence K " +
        "(to refine a mesh: cifs subdivide MESH --scheme " + name + ")");
  if (!o.params.empty())
    throw InvalidInput("scheme " + name + ": --param: the mesh schemes take no parameters");
  if (o.format != "json" && o.format != "table")
    throw InvalidInput("--format '" + o.format + "': json or table for a mesh scheme's analysis");
  const auto cases = local_cases(name, o);
  std::vector<sd::LocalMatrix> matrices;
  std::vector<sd::LocalSpectrum> spectra;
  std::vector<sd::C1Verdict> verdicts;
  matrices.reserve(cases.size());
  spectra.reserve(cases.size());
  verdicts.reserve(cases.size());
  for (const auto& [n, local] : cases)  // every case checked before any output
    matrices.push_back(sd::local_matrix(scheme, n, local));
  for (const sd::LocalMatrix& m : matrices) {
    spectra.push_back(sd::local_spectrum(m));
    verdicts.push_back(sd::c1_verdict(m, spectra.back()));
  }
  if (o.format == "table") return local_table(matrices, spectra, verdicts);
  return io::local_analysis_json(matrices, spectra, verdicts, cases.size() > 1 || !o.valences.empty());
}

// ------------------------------------------------------------------------------------------------
// Gallery

Points rows(std::initializer_list<std::pair<double, double>> xy) {
  Points P(static_cast<Eigen::Index>(xy.size()), 2);
  Eigen::Index i = 0;
  for (const auto& [x, y] : xy) P.row(i++) << x, y;
  return P;
}

/// The seed 000 shapes (our own control polygons): examples/shapes/NAME.json.
std::vector<std::pair<std::string, Points>> seed_shapes(const std::filesystem::path& examples) {
  std::vector<std::pair<std::string, Points>> out;
  for (const char* name : {"hepta", "bone", "infinity", "sumsign", "clover"})
    out.emplace_back(name, io::read_polygon(examples / "shapes" / (std::string(name) + ".json")).points);
  return out;
}

Stroke control(const Points& P, bool closed = true) {
  return {P, closed, "#b0b0b0", 1.0, "4 3", "control polygon"};
}

}  // namespace

std::string scheme(const SchemeOptions& o) {
  if (o.list) return catalogue_text();
  if (o.name.empty()) throw InvalidInput("scheme: a scheme name is required (see cifs scheme --list)");
  check_scheme_name(o.name);
  if (const auto mesh = mesh_scheme_named(o.name)) return analyze_mesh_scheme(*mesh, o);
  const bool refine = !o.refine.empty();
  if (o.analyze == refine)
    throw InvalidInput(o.analyze ? "scheme: --analyze and --refine are exclusive"
                                 : "scheme: choose --analyze or --refine POLYGON.json (or --list)");
  if (!o.valence.empty() || !o.valences.empty() || !o.boundary.empty() || !o.boundary_valence.empty() ||
      !o.crease.empty() || o.dart || o.corner || o.concave || !o.rules.empty() || !o.interior_corners.empty())
    throw InvalidInput(
        "scheme " + o.name +
        ": --valence, --valences, --boundary, --boundary-valence, --crease, --dart, --corner, --concave, "
        "--rules and --interior-corners "
        "are for the mesh schemes (catmull-clark, loop, "
        "doo-sabin, butterfly, sqrt3)");
  const sd::Scheme s = sd::named_scheme(o.name, parse_params(o.params));
  if (o.analyze) {
    if (o.max_power < 1 || o.max_power > 26)
      throw InvalidInput("--max-power " + std::to_string(o.max_power) + ": between 1 and 26");
    sd::AnalysisOptions a;
    a.max_power = o.max_power;
    try {
      return io::analysis_json(s, sd::analyze(s, a));
    } catch (const InvalidInput& error) {
      // The analysis's own messages speak of its matrices: name the parameters they came from.
      std::string given;
      for (const std::string& p : o.params) given += (given.empty() ? "" : ", ") + p;
      throw InvalidInput("--analyze of " + o.name + (given.empty() ? "" : " with --param " + given) + ": " +
                         error.what() + (given.empty() ? "" : "; try parameters of moderate size"));
    }
  }
  if (o.steps < 0) throw InvalidInput("--steps " + std::to_string(o.steps) + " is negative");
  io::writable_format(io::Content::polygon, o.format, "--format");
  const io::Polygon polygon = io::read_polygon(o.refine);
  sd::RefineOptions r;
  r.ends = parse_ends(o.ends);
  r.max_points = 50'000'000;
  const Points out = sd::refine(s, polygon.points, polygon.closed, o.steps, r);
  if (o.format == "svg")
    if (std::string w = io::svg_dropped_coordinates(out); !w.empty())
      pending_warnings().push_back(std::move(w));
  return io::encode(io::Polygon{out, polygon.closed}, o.format);
}

namespace {

/// The gallery's folder and what it wrote.
struct SchemeGallery {
  const std::filesystem::path& folder;
  SchemeFigures figures;
  void write(const std::string& name, const std::vector<Stroke>& strokes, const std::string& title) {
    write_file_atomically(folder / name, strokes_svg(strokes, title));
    figures.files.push_back(folder / name);
    figures.titles.push_back(title);
    figures.summary += "scheme gallery: wrote " + (folder / name).string() + "\n";
  }
};

constexpr int kSteps = 5;

/// Seed 000: the Lane-Riesenfeld family and its variants on the example polygons.
void seed_000_figures(SchemeGallery& gallery, const std::filesystem::path& examples) {
  // Seed 000: "degree" = averaging passes + 1 = B-spline degree + 1 = smoothing stages + 1.
  const int seed_degrees[] = {2, 3, 5, 10, 30};
  const char* dashes[] = {"", "10 5", "10 4 2 4", "10 4 2 4 2 4", "2 4"};
  const struct {
    std::string key, title;
    sd::Scheme (*make)(int seed_degree);
  } algorithms[] = {
      {"lr", "Lane-Riesenfeld", [](int d) { return sd::lane_riesenfeld(d - 1); }},
      {"lr4", "Four-point variant", [](int d) { return sd::lr_four_point(d - 1); }},
      {"lr6", "Six-point variant", [](int d) { return sd::lr_six_point(d - 1); }},
  };
  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c"};
  for (const auto& [shape, P] : seed_shapes(examples)) {
    for (const auto& alg : algorithms) {
      gallery.write(
          alg.key + "_" + shape + "_degree3.svg",
          {control(P), {sd::refine(alg.make(3), P, true, kSteps), true, "#1f77b4", 1.8, "", ""}},
          "\"" + shape + "\", seed degree 3, " + std::to_string(kSteps) + " subdivisions, " + alg.title);
      std::vector<Stroke> strokes{control(P)};
      for (int i = 0; i < 5; ++i)
        strokes.push_back({sd::refine(alg.make(seed_degrees[i]), P, true, kSteps), true, "#1f77b4", 1.5,
                           dashes[i], "seed degree " + std::to_string(seed_degrees[i])});
      gallery.write(alg.key + "_" + shape + "_degrees.svg", strokes,
                    "\"" + shape + "\", seed degrees 2, 3, 5, 10, 30, " + std::to_string(kSteps) +
                        " subdivisions, " + alg.title);
    }
    std::vector<Stroke> compare{control(P)};
    for (int a = 0; a < 3; ++a)
      compare.push_back({sd::refine(algorithms[a].make(30), P, true, kSteps), true, colours[a], 1.8, "",
                         algorithms[a].title});
    gallery.write("compare_" + shape + ".svg", compare,
                  "\"" + shape + "\", seed degree 30, " + std::to_string(kSteps) + " subdivisions");
  }
}

/// Seed 001: Chaikin, the 4-point scheme's tension, corner cutting.
void seed_001_figures(SchemeGallery& gallery, const std::filesystem::path& examples) {
  const Points zigzag = rows({{0, 0}, {1, 2}, {2, 0}, {3, 2}, {4, 0}, {5, 1.5}});
  const Points square = rows({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  gallery.write("chaikin_open_closed.svg",
                {control(zigzag, false),
                 {sd::refine(sd::chaikin(), zigzag, false, kSteps), false, "#1f77b4", 1.8, "",
                  "open (end points kept)"},
                 {sd::refine(sd::chaikin(), zigzag, true, kSteps), true, "#ff7f0e", 1.8, "6 3", "closed"}},
                "Chaikin, open and closed, 5 subdivisions");
  {
    std::vector<Stroke> strokes{control(square)};
    const char* ws[] = {"0", "0.03125", "0.0625", "0.1", "0.15", "0.2"};
    const char* cs[] = {"#444444", "#2ca02c", "#1f77b4", "#9467bd", "#ff7f0e", "#d62728"};
    for (int i = 0; i < 6; ++i)
      strokes.push_back(
          {sd::refine(sd::generalized_four_point(sd::parse_rational(ws[i], "w")), square, true, 7), true,
           cs[i], 1.5, "", std::string("w = ") + ws[i] + " (eps = 16w)"});
    gallery.write("four_point_tension.svg", strokes,
                  "Generalised 4-point scheme, tension sweep, 7 subdivisions");
  }
  {
    std::vector<Stroke> strokes{control(square)};
    const char* as[] = {"0.05", "0.15", "0.25", "0.35", "0.45"};
    const char* cs[] = {"#d62728", "#ff7f0e", "#1f77b4", "#2ca02c", "#9467bd"};
    for (int i = 0; i < 5; ++i) {
      const sd::Rational a = sd::parse_rational(as[i], "a");
      strokes.push_back({sd::refine(sd::corner_cutting(a, 1 - a), square, true, 7), true, cs[i], 1.5, "",
                         std::string("a = ") + as[i] + ", b = 1 - a"});
    }
    gallery.write("corner_cutting_symmetric.svg", strokes, "Corner cutting with b = 1 - a, 7 subdivisions");
  }
  {
    std::vector<Stroke> strokes{control(square)};
    const std::pair<const char*, const char*> ab[] = {
        {"0.25", "0.75"}, {"0.1", "0.6"}, {"0.2", "0.5"}, {"0.4", "0.9"}};
    const char* cs[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"};
    for (int i = 0; i < 4; ++i)
      strokes.push_back({sd::refine(sd::corner_cutting(sd::parse_rational(ab[i].first, "a"),
                                                       sd::parse_rational(ab[i].second, "b")),
                                    square, true, 7),
                         true, cs[i], 1.5, "", std::string("a = ") + ab[i].first + ", b = " + ab[i].second});
    gallery.write("corner_cutting_asymmetric.svg", strokes, "Corner cutting with b != 1 - a, 7 subdivisions");
  }
  {
    const Points P = seed_shapes(examples)[0].second;
    gallery.write(
        "approximating_interpolating.svg",
        {control(P),
         {sd::refine(sd::chaikin(), P, true, 6), true, "#1f77b4", 1.8, "", "Chaikin (approximating)"},
         {sd::refine(sd::four_point(), P, true, 6), true, "#ff7f0e", 1.8, "", "4-point (interpolating)"}},
        "\"hepta\": approximating vs interpolating");
  }
}

}  // namespace

SchemeFigures write_scheme_gallery(const std::filesystem::path& folder,
                                   const std::filesystem::path& examples) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw IoError(folder.string() + ": cannot create the folder (" + ec.message() + ")");
  SchemeGallery gallery{folder, {}};
  seed_000_figures(gallery, examples);
  seed_001_figures(gallery, examples);
  return std::move(gallery.figures);
}

}  // namespace cifs::cli
