// SPDX-License-Identifier: MIT
// cifs — the analysis of a subdivision scheme as JSON (`cifs scheme NAME --analyze`, docs/cli.md).
#include <cmath>
#include <nlohmann/json.hpp>

#include "cifs/io/json.hpp"
#include "cifs/subdivision/ifs.hpp"

namespace cifs::io {

using nlohmann::json;
using subdivision::Parameter;
using subdivision::Rational;
using subdivision::Scheme;
using subdivision::SchemeAnalysis;

std::string analysis_json(const Scheme& scheme, const SchemeAnalysis& r) {
  json j;
  j["scheme"] = scheme.name;
  json params = json::object();
  for (const Parameter& p : scheme.parameters) params[p.name] = subdivision::to_string(p.value);
  j["parameters"] = params;
  json mask = json::array(), mask_values = json::array();
  for (const Rational& x : r.mask) mask.push_back(subdivision::to_string(x));
  for (double w : scheme.weights) mask_values.push_back(w);
  j["mask"] = mask;
  j["mask_values"] = mask_values;
  j["symbol"] = r.symbol;
  j["symbol_factored"] = r.symbol_factored;
  j["support"] = json::array({0, r.support});
  j["kind"] = r.kind;
  j["symmetric"] = r.symmetric;
  j["interpolating"] = r.interpolating;
  j["class"] = r.interpolating ? "interpolating" : "approximating";
  j["one_plus_z_power"] = r.multiplicity;
  j["generation_degree"] = r.generation_degree;
  j["reproduction_degree"] = r.reproduction_degree;
  j["continuity"] = r.continuity;
  if (r.continuity >= 0)
    j["continuity_proof"] = {{"k", r.proof.k},
                             {"difference_mask",
                              [&] {
                                json d = json::array();
                                for (const Rational& x : subdivision::difference_mask(r.mask, r.proof.k))
                                  d.push_back(subdivision::to_string(x));
                                return d;
                              }()},
                             {"power", r.proof.power},
                             {"norm", subdivision::to_string(r.proof.norm)},
                             {"norm_value", subdivision::to_double(r.proof.norm)}};
  else
    j["continuity_proof"] = nullptr;
  j["holder"] = json::array({r.holder_low ? json(*r.holder_low) : json(nullptr),
                             r.holder_high ? json(*r.holder_high) : json(nullptr)});
  j["holder_low_power"] = r.holder_low_power;
  j["holder_high_word"] = r.holder_high_word;
  json eig = json::object();
  for (int e = 0; e < 2; ++e) {
    json list = json::array();
    for (const auto& z : r.eigenvalues[static_cast<std::size_t>(e)]) {
      const double re = std::abs(z.real()) < 1e-15 ? 0.0 : z.real();
      const double im = std::abs(z.imag()) < 1e-12 ? 0.0 : z.imag();
      list.push_back(json::array({re, im}));
    }
    eig[e == 0 ? "S0" : "S1"] = list;
  }
  j["eigenvalues"] = eig;
  const auto S = subdivision::ifs_matrices(scheme);
  json matrices = json::object();
  for (int e = 0; e < 2; ++e) {
    json rows = json::array();
    for (Eigen::Index i = 0; i < S[static_cast<std::size_t>(e)].rows(); ++i) {
      json row = json::array();
      for (Eigen::Index k = 0; k < S[static_cast<std::size_t>(e)].cols(); ++k)
        row.push_back(S[static_cast<std::size_t>(e)](i, k));
      rows.push_back(row);
    }
    matrices[e == 0 ? "S0" : "S1"] = rows;
  }
  j["matrices"] = matrices;
  return j.dump(2) + "\n";
}

}  // namespace cifs::io
