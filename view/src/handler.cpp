// SPDX-License-Identifier: MIT
// The request handler of `cifs view`: a pure function of the session and the request.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <variant>

#include "cifs/errors.hpp"
#include "cifs/experiment/dimension.hpp"
#include "cifs/experiment/run.hpp"
#include "cifs/files.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/bcifs.hpp"
#include "cifs/ifs/mesh.hpp"
#include "cifs/ifs/shape_attractor.hpp"
#include "cifs/io/io.hpp"
#include "cifs/io/json.hpp"
#include "cifs/io/svg.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/nurbs/tensor_automaton.hpp"
#include "cifs/subdivision/mesh.hpp"
#include "cifs/subdivision/rules.hpp"
#include "cifs/view/server.hpp"
#include "web_files.hpp"

namespace cifs::view {

namespace {

using nlohmann::json;

/// A refusal: status and the one-line message.
struct Refusal {
  int status;
  std::string message;
};

Response text(int status, std::string body) {
  return {.status = status, .content_type = "text/plain; charset=utf-8", .body = std::move(body) + "\n"};
}

Response json_response(const json& value) {
  return {.status = 200, .content_type = "application/json", .body = value.dump()};
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// Percent-decoding ('+' stays: these are paths and tokens, not form fields).
std::string decode(std::string_view s, std::string_view where) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      out += s[i];
      continue;
    }
    const int hi = i + 2 < s.size() ? hex_digit(s[i + 1]) : -1,
              lo = i + 2 < s.size() ? hex_digit(s[i + 2]) : -1;
    if (hi < 0 || lo < 0) throw Refusal{400, std::string(where) + ": a bad percent escape"};
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return out;
}

/// The value of `key` in the query, decoded; empty when absent.
std::string query_value(std::string_view query, std::string_view key) {
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const std::size_t eq = pair.find('=');
    if (pair.substr(0, eq) == key)
      return eq == std::string_view::npos ? "" : decode(pair.substr(eq + 1), "query");
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return {};
}

/// Equal in time independent of where they differ.
bool same_token(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned>(a[i] ^ b[i]);
  return diff == 0;
}

/// `name` as a file of the session's folder: a plain name (no folder part, no leading dot), and no
/// symbolic link out of the folder.
std::filesystem::path in_folder(const Session& s, const std::string& name, std::string_view where) {
  const bool plain = !name.empty() && name.size() < 256 && name.front() != '.' &&
                     name.find_first_of("/\\%:") == std::string::npos && name.find('\0') == std::string::npos;
  if (!plain)
    throw Refusal{
        403, std::string(where) + ": '" + name + "' is not a plain file name of the opened file's folder"};
  std::filesystem::path path = s.folder / name;
  std::error_code ec;
  if (std::filesystem::is_symlink(path, ec)) {
    const std::filesystem::path target = std::filesystem::weakly_canonical(path, ec);
    if (ec || target.parent_path() != std::filesystem::weakly_canonical(s.folder, ec))
      throw Refusal{403, std::string(where) + ": '" + name + "' links outside the opened file's folder"};
  }
  return path;
}

json parse_body(const Request& r, std::string_view where) {
  try {
    json body = json::parse(r.body);
    if (!body.is_object()) throw Refusal{400, std::string(where) + ": the body is not a JSON object"};
    return body;
  } catch (const json::parse_error& e) {
    throw Refusal{400, std::string(where) + ": malformed JSON at byte " + std::to_string(e.byte)};
  } catch (const json::exception& e) {  // a number beyond a double (1e400): out_of_range
    throw Refusal{400, std::string(where) + ": " + e.what()};
  }
}

int int_field(const json& j, const char* key, int fallback, std::string_view where) {
  if (!j.contains(key)) return fallback;
  const json& v = j.at(key);
  if (!v.is_number_integer() || v.get<std::int64_t>() < -1000000 || v.get<std::int64_t>() > 1000000)
    throw Refusal{400,
                  std::string(where) + ": " + key + " is not an integer (" + v.dump().substr(0, 40) + ")"};
  return v.get<int>();
}

/// Params from the body's "params" object (absent keys: default_params).
Params parse_params(const Document& d, const json& body, std::string_view where) {
  Params p = default_params(d);
  if (!body.contains("params")) return p;
  const json& j = body.at("params");
  if (!j.is_object()) throw Refusal{400, std::string(where) + ": params is not an object"};
  for (const auto& [key, value] : j.items())
    if (key != "depth" && key != "scheme" && key != "levels" && key != "points" && key != "amplitude" &&
        key != "seed" && key != "values" && key != "weights" && key != "knots" && key != "nets")
      throw Refusal{400,
                    std::string(where) + ": unknown parameter '" + key +
                        "' (depth, scheme, levels, points, weights, knots, nets, amplitude, seed, values)"};
  if (j.contains("values")) {
    const json& values = j.at("values");
    if (!values.is_object())
      throw Refusal{400, std::string(where) + ": values is not an object (coefficient name: number)"};
    p.values.clear();  // the page sends every value it sets
    for (const auto& [name, value] : values.items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        throw Refusal{400,
                      std::string(where) + ": values: " + name.substr(0, 80) + " is not a finite number"};
      p.values[name] = value.get<double>();
    }
  }
  if (j.contains("amplitude")) {
    if (!j.at("amplitude").is_number())
      throw Refusal{400, std::string(where) + ": amplitude is not a number"};
    p.amplitude = j.at("amplitude").get<double>();
  }
  if (j.contains("seed")) {
    if (!j.at("seed").is_number_unsigned())
      throw Refusal{400, std::string(where) + ": seed is not an integer ≥ 0"};
    p.seed = j.at("seed").get<std::uint64_t>();
  }
  p.depth = int_field(j, "depth", p.depth, where);
  p.levels = int_field(j, "levels", p.levels, where);
  if (j.contains("scheme")) {
    if (!j.at("scheme").is_string()) throw Refusal{400, std::string(where) + ": scheme is not a string"};
    p.scheme = j.at("scheme").get<std::string>();
  }
  if (j.contains("points")) {
    const json& points = j.at("points");
    if (!points.is_array()) throw Refusal{400, std::string(where) + ": points is not an array"};
    for (const json& e : points) {
      if (!e.is_array() || e.size() < 2 || e.size() > 4 || !e[0].is_number_unsigned() ||
          !std::all_of(e.begin() + 1, e.end(), [](const json& x) { return x.is_number(); }))
        throw Refusal{400, std::string(where) + ": each edit of points is [index, x, y(, z)]"};
      PointEdit edit{.index = e[0].get<std::size_t>(), .position = {}};
      for (auto x = e.begin() + 1; x != e.end(); ++x) edit.position.push_back(x->get<double>());
      p.points.push_back(std::move(edit));
    }
  }
  if (j.contains("weights")) {
    const json& weights = j.at("weights");
    if (!weights.is_array()) throw Refusal{400, std::string(where) + ": weights is not an array"};
    for (const json& e : weights) {
      if (!e.is_array() || e.size() != 2 || !e[0].is_number_unsigned() || !e[1].is_number())
        throw Refusal{400, std::string(where) + ": each edit of weights is [index, weight]"};
      p.weights.push_back({.index = e[0].get<std::size_t>(), .weight = e[1].get<double>()});
    }
  }
  if (j.contains("knots")) {  // one list per direction; the library checks the values (edited_shape)
    const json& knots = j.at("knots");
    const auto numbers = [](const json& list) {
      return list.is_array() &&
             std::all_of(list.begin(), list.end(), [](const json& x) { return x.is_number(); });
    };
    if (!knots.is_array() || !std::all_of(knots.begin(), knots.end(), numbers))
      throw Refusal{400,
                    std::string(where) + ": knots is not a list of lists of numbers (one per direction)"};
    p.knots.clear();
    for (const json& list : knots) p.knots.push_back(list.get<std::vector<double>>());
  }
  if (j.contains("nets")) {  // a BC-IFS file's nets; edited_nets checks the net, point and coordinates
    const json& nets = j.at("nets");
    if (!nets.is_array()) throw Refusal{400, std::string(where) + ": nets is not an array"};
    for (const json& e : nets) {
      if (!e.is_array() || e.size() < 3 || e.size() > 10 || !e[0].is_number_unsigned() ||
          !e[1].is_number_unsigned() ||
          !std::all_of(e.begin() + 2, e.end(), [](const json& x) { return x.is_number(); }))
        throw Refusal{400, std::string(where) + ": each edit of nets is [net, index, x, y(, z)]"};
      NetEdit edit{.net = e[0].get<std::size_t>(), .index = e[1].get<std::size_t>(), .position = {}};
      for (auto x = e.begin() + 2; x != e.end(); ++x) edit.position.push_back(x->get<double>());
      p.nets.push_back(std::move(edit));
    }
  }
  if (!p.nets.empty() && (d.kind != Kind::bcifs || d.experiment))
    throw Refusal{400, std::string(where) + ": nets: " + d.path.filename().string() +
                           (d.experiment ? " is an experiment: open the BC-IFS file it names to edit its nets"
                                         : " has no BC-IFS nets (its control points are edited as points)")};
  if (!p.points.empty() && (d.kind == Kind::subdivision || d.kind == Kind::junction || d.kind == Kind::ifs))
    throw Refusal{400, std::string(where) + ": points: " + d.path.filename().string() +
                           " is an experiment on a " + std::string(kind_name(d.kind)) +
                           ": its points are not edited here"};
  if (!p.points.empty() && d.kind == Kind::bcifs)
    throw Refusal{400, std::string(where) +
                           ": points: a BC-IFS file's control points are edited as nets "
                           "([net, index, x, y(, z)])"};
  if ((!p.knots.empty() || !p.weights.empty()) && !d.shape)
    throw Refusal{400,
                  std::string(where) + ": knots, weights: " + d.path.filename().string() +
                      " has none (a curve's or surface's, or those of an experiment on one, are edited)"};
  return p;
}

json params_json(const Params& p) {
  return {{"depth", p.depth},         {"scheme", p.scheme}, {"levels", p.levels},
          {"amplitude", p.amplitude}, {"seed", p.seed},     {"values", p.values}};
}

int shape_dimension(const Document& d) {
  switch (d.kind) {
    case Kind::mesh:
      return static_cast<int>(d.mesh.vertices.cols());
    case Kind::bcifs:
      return static_cast<int>(d.bcifs->nets.front().cols());
    case Kind::subdivision:
      return static_cast<int>(d.experiment->mesh->mesh.vertices.cols());
    case Kind::ifs:
      return 2;
    case Kind::junction: {  // both sides have A's dimension (join checks it)
      const io::JunctionSideSpec& a = d.experiment->junction->a;
      if (a.shape) return std::visit([](const auto& s) { return nurbs::dimension(s); }, *a.shape);
      return static_cast<int>(a.points.cols());
    }
    case Kind::curve:
    case Kind::surface:
      break;
  }
  return std::visit([](const auto& s) { return nurbs::dimension(s); }, *d.shape);
}

int max_depth(const Session& s) {
  return view::max_depth(s.document, s.limits);
}

/// The files of the session's folder that the page may open: plain names (in_folder's rule) with an
/// extension cifs view reads (document_extensions: io's format table), regular files or links to one inside
/// the folder, sorted; at most Limits::max_files of them. What each holds is not read here: opening one that
/// cifs view does not show is refused then, with the reason.
std::vector<std::string> folder_files(const Session& s) {
  const std::vector<std::string_view> extensions = document_extensions();
  std::vector<std::string> names;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator(s.folder, ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (std::find(extensions.begin(), extensions.end(), extension_of(it->path())) == extensions.end())
      continue;
    std::error_code regular;
    if (!std::filesystem::is_regular_file(it->path(), regular)) continue;
    try {
      (void)in_folder(s, name, "files");
    } catch (const Refusal&) {
      continue;
    }
    names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  if (names.size() > s.limits.max_files) names.resize(s.limits.max_files);
  return names;
}

json document_json(const Session& s) {
  const Document& d = s.document;
  json j = {{"name", d.path.filename().string()},
            {"kind", kind_name(d.kind)},
            {"dimension", shape_dimension(d)},
            {"params", params_json(default_params(d))},
            {"files", folder_files(s)}};
  if (d.shape) {  // the knots and weights the page edits (the distinct points of a closed curve)
    j["knots"] = shape_knots(*d.shape);
    std::vector<double> weights;
    if (const auto* c = std::get_if<nurbs::Curve>(&*d.shape)) {
      const Eigen::VectorXd w = nurbs::weights(*c);
      weights.assign(w.data(), w.data() + w.size());
      j["degree"] = {c->degree};
      j["closed"] = c->closed;
    } else {
      const auto& surface = std::get<nurbs::Surface>(*d.shape);
      const Eigen::VectorXd w = nurbs::weights(surface);
      weights.assign(w.data(), w.data() + w.size());
      j["degree"] = surface.degree;
    }
    j["weights"] = weights;
  }
  if (d.kind == Kind::subdivision || d.kind == Kind::junction || d.kind == Kind::ifs) {
    // Drawn by the runner's scene: its levels or depth, and the perturbation where the runner takes one
    // (a junction; a Catmull–Clark or Loop mesh: its fractal surface).
    const bool fractal =
        d.kind == Kind::junction || (d.kind == Kind::subdivision &&
                                     (d.experiment->mesh->scheme == subdivision::MeshScheme::catmull_clark ||
                                      d.experiment->mesh->scheme == subdivision::MeshScheme::loop));
    j["ranges"] = d.kind == Kind::subdivision ? json{{"levels", {0, s.limits.max_levels}}}
                                              : json{{"depth", {0, max_depth(s)}}};
    if (fractal) j["ranges"]["amplitude"] = {0, max_amplitude(d)};
    j["points_editable"] = false;
    j["automaton"] = d.kind == Kind::junction;  // its states are the pieces' (a mesh's and an IFS's are not)
    j["experiment"] = true;
  } else if (d.kind == Kind::mesh) {
    json schemes = json::array();
    for (const char* name : {"catmull-clark", "loop", "doo-sabin", "butterfly", "sqrt3", "bilinear"})
      schemes.push_back(name);
    j["schemes"] = schemes;
    j["ranges"] = {{"levels", {0, s.limits.max_levels}}};
  } else {
    j["ranges"] = {{"depth", {0, max_depth(s)}}, {"amplitude", {0, 0.5}}};
    json coefficients = json::array();
    for (const CoefficientRange& c : d.coefficients)
      coefficients.push_back(
          {{"name", c.name}, {"value", c.value}, {"low", c.low}, {"high", c.high}, {"capped", c.capped}});
    j["coefficients"] = coefficients;
    if (d.bcifs) {
      j["free_coefficients"] = d.bcifs->names.size();
      std::vector<Eigen::Index> sizes;  // the page's net buffer holds the nets one after another
      for (const Points& net : d.bcifs->nets) sizes.push_back(net.rows());
      j["nets"] = sizes;
    }
    if (!d.refusal.empty()) j["refusal"] = d.refusal;
    // A BC-IFS file's nets are dragged in the plane or in space (other column counts are not drawn as such);
    // an experiment on a BC-IFS file names the file that holds them.
    j["points_editable"] =
        d.kind != Kind::bcifs || (!d.experiment && (shape_dimension(d) == 2 || shape_dimension(d) == 3));
    if (d.experiment) j["experiment"] = true;
  }
  return j;
}

/// The automaton drawn beside the geometry: the BC-IFS file's, or the knot or tensor automaton of the
/// shape with the page's knots (`params`).
automata::Automaton document_automaton(const Document& d, const Params& params) {
  if (d.kind == Kind::bcifs) return d.bcifs->system.automaton;
  if (d.kind == Kind::junction) {  // the joined automaton: a perturbation changes its matrices, not its graph
    io::Experiment e = *d.experiment;
    e.perturbation.reset();
    return experiment::draw(e, 0).automaton;
  }
  const io::Shape shape = edited_shape(d, params);
  if (const auto* c = std::get_if<nurbs::Curve>(&shape)) return nurbs::knot_automaton(*c).automaton;
  return nurbs::tensor_automaton(std::get<nurbs::Surface>(shape)).product;
}

/// A BC-IFS document's system with the edits: ifs::perturb's result when perturbed, else the file's.
ifs::Bcifs edited_system(const Document& d, const Params& params) {
  if (!perturbed(d, params)) return d.bcifs->system;
  ifs::PerturbOptions o;
  o.amplitude = params.amplitude;
  o.seed = params.seed;
  o.values = params.values;
  o.contraction.bound = false;
  return ifs::perturb(d.bcifs->system, d.bcifs->space, o).system;
}

/// The experiment file's text with the view's depth and perturbation, and its shape inline when its points,
/// weights or knots were edited (the rest as written), checked by the experiment reader before it is written.
std::string edited_experiment(const Session& s, const Params& params, const std::string& name) {
  const Document& d = s.document;
  if (params.depth < 0 || params.depth > max_depth(s))
    throw InvalidInput("depth " + std::to_string(params.depth) + " is outside 0.." +
                       std::to_string(max_depth(s)));
  nlohmann::ordered_json e = nlohmann::ordered_json::parse(d.experiment_text);
  if (d.kind == Kind::subdivision) {  // a mesh is refined, not evaluated: its levels
    if (params.levels < 0 || params.levels > s.limits.max_levels)
      throw InvalidInput("levels " + std::to_string(params.levels) + " is outside 0.." +
                         std::to_string(s.limits.max_levels));
    e["subdivision"]["levels"] = params.levels;
  } else if (d.experiment->evaluation.mode == io::EvaluationSpec::Mode::depth) {
    e["evaluation"]["depth"] = params.depth;
  }
  if (!params.points.empty() || !params.weights.empty() || !params.knots.empty())
    e["shape"] = nlohmann::ordered_json::parse(io::to_json(edited_shape(d, params)));
  if (perturbed(d, params)) {
    auto& p = e["perturbation"];
    p["amplitude"] = params.amplitude;
    p["seed"] = params.seed;
    if (params.values.empty())
      p.erase("values");
    else
      p["values"] = params.values;
  }
  std::string text = e.dump(2) + "\n";
  (void)io::parse_experiment(text, name, s.folder);  // what cifs render will read
  return text;
}

Response save(Session& s, const Request& r) {
  const json body = parse_body(r, "/api/save");
  if (!body.contains("name") || !body.at("name").is_string())
    throw Refusal{400, "/api/save: name (a file name in the opened file's folder) is missing"};
  const std::string name = body.at("name").get<std::string>();
  const std::filesystem::path path = in_folder(s, name, "/api/save");
  const Params params = parse_params(s.document, body, "/api/save");
  const std::string ext = extension_of(path);
  if (s.document.kind == Kind::mesh) {
    if (ext == ".obj" || ext == ".ply") {  // the refined mesh, as cifs subdivide writes it
      const Mesh control = edited_mesh(s.document, params);
      subdivision::MeshOptions options;
      options.max_bytes = 64 * s.limits.max_points;
      if (params.levels < 0 || params.levels > s.limits.max_levels)
        throw InvalidInput("levels " + std::to_string(params.levels) + " is outside 0.." +
                           std::to_string(s.limits.max_levels));
      io::write(path, subdivision::subdivide(control, subdivision::named_mesh_scheme(params.scheme),
                                             params.levels, options));
    } else {
      throw InvalidInput(name + ": a mesh is saved as .obj or .ply");
    }
  } else if (ext == ".json" && s.document.experiment) {
    write_file_atomically(path, edited_experiment(s, params, name));
  } else if (ext == ".json" && s.document.kind == Kind::bcifs) {
    // The edited system with its nets, as cifs fit --fractal writes one (the view's checks first).
    Params check = params;  // the values' ranges and contractivity, at depth 0
    check.depth = 0;
    (void)geometry(s.document, check, s.limits);
    io::write(path, io::BcifsFile{edited_system(s.document, params), edited_nets(s.document, params)});
  } else if (ext == ".json") {
    io::write(path, edited_shape(s.document, params));
  } else if ((ext == ".obj" || ext == ".ply") && s.document.kind == Kind::surface) {
    if (params.depth < 0 || params.depth > s.limits.max_depth_surface)
      throw InvalidInput("depth " + std::to_string(params.depth) + " is outside 0.." +
                         std::to_string(s.limits.max_depth_surface));
    io::write(path, ifs::attractor(std::get<nurbs::Surface>(edited_shape(s.document, params)), params.depth,
                                   ifs::mesh_bytes(s.limits.max_points, 3, s.limits.max_points)));
  } else {
    throw InvalidInput(
        name + ": a " + std::string(kind_name(s.document.kind)) + " is saved as .json" +
        (s.document.kind == Kind::surface ? " (the shape), .obj or .ply (its attractor mesh)" : ""));
  }
  return json_response({{"written", name}});
}

/// The document with `params` as an experiment (the runner's input): the edited shape at the depth, the
/// BC-IFS file, the experiment file with the view's depth and perturbation, or the edited mesh with its
/// scheme and levels; `control_net` drawn.
io::Experiment as_experiment(const Session& s, const Params& params) {
  const Document& d = s.document;
  if (d.experiment || d.kind == Kind::bcifs) {
    if (params.depth < 0 || params.depth > max_depth(s))
      throw InvalidInput("depth " + std::to_string(params.depth) + " is outside 0.." +
                         std::to_string(max_depth(s)));
    io::Experiment e;
    if (d.experiment) {
      e = *d.experiment;
      e.outputs = {};
      if (d.shape) e.shape = edited_shape(d, params);
    } else {
      e.name = d.path.stem().string();
      e.automaton = std::filesystem::absolute(d.path);
      e.inputs = {d.path};
    }
    // Moved nets go to the runner in memory beside the file's system, which it perturbs as it would the
    // saved file's.
    if (!params.nets.empty()) {
      std::vector<Points> nets = edited_nets(d, params);  // first: it refuses a document without nets
      e.bcifs = io::BcifsFile{d.bcifs->system, std::move(nets)};
    }
    if (e.mesh) {  // refined, not evaluated
      if (params.levels < 0 || params.levels > s.limits.max_levels)
        throw InvalidInput("levels " + std::to_string(params.levels) + " is outside 0.." +
                           std::to_string(s.limits.max_levels));
      e.mesh->levels = params.levels;
    } else {
      e.evaluation.mode = io::EvaluationSpec::Mode::depth;
      e.evaluation.depth = params.depth;
    }
    e.perturbation.reset();
    if (perturbed(d, params))
      e.perturbation = io::PerturbationSpec{.amplitude = params.amplitude,
                                            .seed = params.seed,
                                            .values = params.values,
                                            .keep_vertices = d.perturbation.keep_vertices,
                                            .fractal_curves = d.perturbation.fractal_curves};
    e.render.width = 1024;
    e.render.height = 768;
    e.render.control_net = true;
    return e;
  }
  io::Experiment e;
  e.name = s.document.path.stem().string();
  if (s.document.kind == Kind::mesh) {
    if (params.levels < 0 || params.levels > s.limits.max_levels)
      throw InvalidInput("levels " + std::to_string(params.levels) + " is outside 0.." +
                         std::to_string(s.limits.max_levels));
    e.mesh = io::MeshSource{.path = s.document.path,
                            .mesh = edited_mesh(s.document, params),
                            .scheme = subdivision::named_mesh_scheme(params.scheme),
                            .levels = params.levels,
                            .limit = false};
  } else {
    const int high = s.document.kind == Kind::curve ? s.limits.max_depth_curve : s.limits.max_depth_surface;
    if (params.depth < 0 || params.depth > high)
      throw InvalidInput("depth " + std::to_string(params.depth) + " is outside 0.." + std::to_string(high));
    e.shape = edited_shape(s.document, params);
    e.evaluation.depth = params.depth;
    if (perturbed(d, params))
      e.perturbation = io::PerturbationSpec{.amplitude = params.amplitude,
                                            .seed = params.seed,
                                            .values = params.values,
                                            .keep_vertices = true,
                                            .fractal_curves = std::nullopt};
  }
  e.render.width = 1024;
  e.render.height = 768;
  e.render.control_net = true;
  e.inputs = {s.document.path};
  return e;
}

/// The dimension readout: experiment::measure_dimension at a small budget (2^16 points).
Response dimension(const Session& s, const Request& r) {
  const json body = parse_body(r, "/api/dimension");
  const io::Experiment e = as_experiment(s, parse_params(s.document, body, "/api/dimension"));
  experiment::DimensionOptions options;
  options.max_points = std::size_t{1} << 16;
  options.min_boxes = 100;
  const experiment::DimensionMeasurement m = experiment::measure_dimension(e, options);
  return json_response({{"dimension", m.fit.dimension},
                        {"uncertainty", m.uncertainty},
                        {"range", m.range},
                        {"route", m.description}});
}

/// Render PNG or EXR through the experiment runner (cifs render's), into the folder.
Response render_image(const Session& s, const Request& r) {
  const json body = parse_body(r, "/api/render");
  if (!body.contains("name") || !body.at("name").is_string())
    throw Refusal{400, "/api/render: name (a .png or .exr of the opened file's folder) is missing"};
  const std::string name = body.at("name").get<std::string>();
  const std::filesystem::path path = in_folder(s, name, "/api/render");
  io::Experiment e = as_experiment(s, parse_params(s.document, body, "/api/render"));
  if (extension_of(path) == ".png")
    e.outputs.png = path;
  else if (extension_of(path) == ".exr")
    e.outputs.exr = path;
  else
    throw InvalidInput(name + ": an image is rendered as .png or .exr");
  experiment::RunOptions options;
  options.out_dir = s.folder;
  options.quiet = true;
  experiment::run(e, options);
  return json_response({{"written", name}});
}

Response route(Session& s, const Request& r) {
  const std::size_t question = r.target.find('?');
  const std::string path = decode(std::string_view(r.target).substr(0, question), "path");
  const std::string_view query =
      question == std::string::npos ? std::string_view() : std::string_view(r.target).substr(question + 1);
  if (path.find("..") != std::string::npos || path.find('\0') != std::string::npos)
    throw Refusal{403, path.substr(0, 80) + ": no path outside the page"};
  if (r.method == "GET") {
    if (path == "/" || path == "/index.html")
      return {200, "text/html; charset=utf-8", std::string(web::kIndexHtml)};
    if (path == "/view.js") return {200, "text/javascript; charset=utf-8", std::string(web::kViewJs)};
    if (path == "/three/three.min.js")
      return {200, "text/javascript", read_file(web::three_file("three.min.js"))};
    if (path == "/three/OrbitControls.js")
      return {200, "text/javascript", read_file(web::three_file("OrbitControls.js"))};
  }
  if (!path.starts_with("/api/")) throw Refusal{404, path.substr(0, 80) + ": no such page"};
  if (!same_token(query_value(query, "token"), s.token))
    throw Refusal{403, path + ": a missing or wrong token (use the URL cifs view printed)"};
  if (r.body.size() > s.max_body)
    throw Refusal{413, path + ": a body of " + std::to_string(r.body.size()) + " bytes, above the limit of " +
                           std::to_string(s.max_body)};
  if (r.method == "GET" && path == "/api/document") {
    const std::scoped_lock lock(s.document_mutex);
    return json_response(document_json(s));
  }
  if ((r.method == "GET" || r.method == "POST") && path == "/api/automaton.svg") {
    // POST: the automaton of the shape with the body's knots (a knot edit changes it).
    const std::scoped_lock lock(s.document_mutex);
    if (s.document.kind == Kind::mesh || s.document.kind == Kind::subdivision || s.document.kind == Kind::ifs)
      throw Refusal{404, path + ": a " + std::string(kind_name(s.document.kind)) + " has no automaton here"};
    const Params params =
        r.method == "GET" ? default_params(s.document) : parse_params(s.document, parse_body(r, path), path);
    return {200, "image/svg+xml", io::to_svg(document_automaton(s.document, params))};
  }
  if (r.method == "POST" && path == "/api/geometry") {
    const json body = parse_body(r, path);
    const std::uint64_t ticket = ++s.latest;
    const std::scoped_lock evaluating(s.evaluating);
    // Superseded by a newer edit: 204 (no content), which the page ignores.
    if (ticket != s.latest) return {204, "text/plain; charset=utf-8", ""};
    const std::scoped_lock lock(s.document_mutex);
    geometry(s.document, parse_params(s.document, body, path), s.limits, &s.cache, s.geometry);
    return {200, "application/octet-stream", encode_geometry(s.geometry)};
  }
  if (r.method == "POST" && path == "/api/save") {
    const std::scoped_lock lock(s.document_mutex);
    return save(s, r);
  }
  if (r.method == "POST" && path == "/api/dimension") {
    const std::scoped_lock lock(s.document_mutex);
    return dimension(s, r);
  }
  if (r.method == "POST" && path == "/api/render") {
    const std::scoped_lock lock(s.document_mutex);
    return render_image(s, r);
  }
  if (r.method == "POST" && path == "/api/open") {
    const json body = parse_body(r, path);
    if (!body.contains("name") || !body.at("name").is_string())
      throw Refusal{400, path + ": name is missing"};
    Document d = open_document(in_folder(s, body.at("name").get<std::string>(), path), s.limits);
    const std::scoped_lock evaluating(s.evaluating);  // the cache belongs to the geometry requests
    const std::scoped_lock lock(s.document_mutex);
    s.document = std::move(d);
    s.cache = {};
    return json_response(document_json(s));
  }
  throw Refusal{404, r.method + " " + path + ": no such request"};
}

}  // namespace

std::string random_token() {
  std::random_device device;
  std::string token;
  for (int k = 0; k < 4; ++k) {
    std::array<char, 9> part{};
    std::snprintf(part.data(), part.size(), "%08x", static_cast<unsigned>(device()));
    token += part.data();
  }
  return token;
}

void open_session(Session& session, const std::filesystem::path& path, const std::string& host, int port) {
  session.document = open_document(path, session.limits);
  session.folder = std::filesystem::absolute(path).parent_path();
  session.token = random_token();
  const std::string p = ":" + std::to_string(port);
  session.hosts = {host + p};
  if (host == "127.0.0.1") session.hosts.push_back("localhost" + p);
}

Response handle(Session& session, const Request& request) {
  try {
    if (std::find(session.hosts.begin(), session.hosts.end(), request.host) == session.hosts.end())
      throw Refusal{403, "Host '" + request.host.substr(0, 80) + "' is not the address cifs view serves"};
    return route(session, request);
  } catch (const Refusal& e) {
    return text(e.status, "cifs view: " + e.message);
  } catch (const ifs::NotContractive& e) {  // the page shows it as the edit's contractivity, not a failure
    return text(422, std::string("cifs view: ") + e.what());
  } catch (const InvalidInput& e) {
    return text(400, std::string("cifs view: ") + e.what());
  } catch (const IoError& e) {
    return text(400, std::string("cifs view: ") + e.what());
  } catch (const std::bad_alloc&) {
    return text(507, "cifs view: out of memory; ask for less");
  } catch (const std::exception& e) {
    return text(500, std::string("cifs view: ") + e.what());
  }
}

}  // namespace cifs::view
