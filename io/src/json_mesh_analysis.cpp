// SPDX-License-Identifier: MIT
// cifs — local subdivision matrices of mesh schemes and their spectra as JSON
// (`cifs scheme MESH-SCHEME --valence N --analyze`, docs/cli.md).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numbers>

#include "cifs/io/json.hpp"

namespace cifs::io {

using nlohmann::json;
using subdivision::LocalMatrix;
using subdivision::LocalSpectrum;

namespace {

json complex_json(const std::complex<long double>& z) {
  return json::array({static_cast<double>(z.real()), static_cast<double>(z.imag())});
}

json vector_json(const subdivision::LongVector& v) {
  json out = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(static_cast<double>(v(i)));
  return out;
}

json c1_json(const subdivision::C1Verdict& v) {
  json j;
  j["verdict"] = v.c1;
  j["reason"] = v.reason;
  j["spectral"] = v.spectral;
  if (!v.spectral) return j;
  j["method"] = v.method;
  if (v.method == "sampled") j["levels"] = v.levels;
  j["pieces"] = v.pieces;
  j["splits"] = v.splits;
  j["decided"] = v.decided;
  j["regular"] = v.regular;
  j["winding"] = v.winding;
  j["margin"] = static_cast<double>(v.margin);
  if (v.through_centre) j["through_centre"] = true;
  if (v.angle != 0 && !v.through_centre)
    j["sector_angle_degrees"] = static_cast<double>(v.angle * 180 / std::numbers::pi_v<long double>);
  if (v.sectors.empty()) return j;
  json sectors = json::array();
  for (const subdivision::C1Verdict::Sector& sector : v.sectors) {
    const LocalSpectrum& s = sector.spectrum;
    json spectrum = json::array();
    for (std::size_t i = 0; i < std::min<std::size_t>(s.eigenvalues.size(), 6); ++i)
      spectrum.push_back(complex_json(s.eigenvalues[i]));
    sectors.push_back({{"faces", sector.faces},
                       {"leading_eigenvalues", spectrum},
                       {"lambda1", static_cast<double>(s.subdominant)},
                       {"lambda2", static_cast<double>(s.second)},
                       {"mu", complex_json(s.mu)},
                       {"c1", c1_json(sector.verdict)}});
  }
  j["sectors"] = sectors;
  return j;
}

json local_json(const LocalMatrix& m, const LocalSpectrum& s) {
  json j;
  j["scheme"] = std::string(subdivision::scheme_name(m.scheme));
  j["valence"] = m.valence;
  j["vertex"] = subdivision::vertex_class(m.valence, m.options);
  if (m.options.boundary && m.options.interior_corners.empty())
    j["boundary_rule"] = m.options.rule == subdivision::BoundaryRule::edge_only ? "edge" : "corner";
  if (!m.options.sharp.empty()) j["sharp_edges"] = m.options.sharp;
  if (m.options.concave) j["concave"] = true;
  if (m.options.rules != RuleSet::opensubdiv) j["rules"] = std::string(option_name(m.options.rules));
  if (!m.options.interior_corners.empty()) {  // Doo–Sabin: a face touching the boundary
    json corners = json::array();
    for (const char c : m.options.interior_corners) corners.push_back(c != 0 ? 1 : 0);
    j["interior_corners"] = corners;
    j["sector_corners"] = subdivision::sector_sizes(m.valence, m.options);
  } else if (m.options.boundary || !m.options.sharp.empty() || m.options.corner) {
    j["sector_faces"] = subdivision::sector_sizes(m.valence, m.options);
  }
  j["steps"] = m.steps;
  j["neighbourhood"] = m.labels;
  j["exact"] = m.exact.has_value();
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.values.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index k = 0; k < m.values.cols(); ++k)
      if (m.exact)
        row.push_back(subdivision::to_string((*m.exact)(static_cast<int>(i), static_cast<int>(k))));
      else
        row.push_back(static_cast<double>(m.values(i, k)));
    rows.push_back(row);
  }
  j["matrix"] = rows;
  json spectrum = json::array();
  for (const auto& z : s.eigenvalues) spectrum.push_back(complex_json(z));
  j["spectrum"] = spectrum;
  j["dominant_simple"] = s.dominant_simple;
  j["subdominant"] = {{"lambda1", static_cast<double>(s.subdominant)},
                      {"lambda2", static_cast<double>(s.second)},
                      {"equal_pair", s.subdominant_pair},
                      {"eigenvectors", json::array({vector_json(s.subdominant_basis.col(0)),
                                                    vector_json(s.subdominant_basis.col(1))})}};
  j["gap"] = s.gap;
  j["mu"] = complex_json(s.mu);
  j["curvature"] = {
      {"ratio", s.curvature_ratio ? json(static_cast<double>(*s.curvature_ratio)) : json(nullptr)},
      {"verdict", s.curvature}};
  j["limit_stencil"] = vector_json(s.limit_stencil);
  j["residual"] = static_cast<double>(s.residual);
  return j;
}

}  // namespace

std::string local_analysis_json(std::span<const LocalMatrix> matrices, std::span<const LocalSpectrum> spectra,
                                std::span<const subdivision::C1Verdict> verdicts, bool as_array) {
  json out = json::array();
  for (std::size_t i = 0; i < matrices.size(); ++i) {
    out.push_back(local_json(matrices[i], spectra[i]));
    if (i < verdicts.size()) out.back()["c1"] = c1_json(verdicts[i]);
  }
  return (as_array ? out : out.at(0)).dump(2) + "\n";
}

}  // namespace cifs::io
