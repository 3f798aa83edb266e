// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cifs/io/json.hpp"
#include "cifs/subdivision/analysis.hpp"
#include "cifs/subdivision/ifs.hpp"
#include "cifs/subdivision/scheme.hpp"

using namespace cifs;
namespace sd = cifs::subdivision;
using nlohmann::json;

TEST_CASE("Scheme analysis JSON holds the analysis", "[io][json]") {
  for (const sd::Scheme& s : {sd::chaikin(), sd::four_point(), sd::lane_riesenfeld(3)}) {
    INFO(s.name);
    const sd::SchemeAnalysis a = sd::analyze(s);
    const json j = json::parse(io::analysis_json(s, a));
    CHECK(j["scheme"] == s.name);
    REQUIRE(j["mask"].size() == a.mask.size());
    for (std::size_t i = 0; i < a.mask.size(); ++i) CHECK(j["mask"][i] == sd::to_string(a.mask[i]));
    CHECK(j["mask_values"] == json(s.weights));
    CHECK(j["support"] == json::array({0, a.support}));
    CHECK(j["kind"] == a.kind);
    CHECK(j["interpolating"] == a.interpolating);
    CHECK(j["class"] == (a.interpolating ? "interpolating" : "approximating"));
    CHECK(j["continuity"] == a.continuity);
    CHECK(j["continuity_proof"]["k"] == a.proof.k);
    CHECK(j["continuity_proof"]["norm"] == sd::to_string(a.proof.norm));
    CHECK(j["generation_degree"] == a.generation_degree);
    CHECK(j["symbol_factored"] == a.symbol_factored);
    const auto S = sd::ifs_matrices(s);
    for (int e = 0; e < 2; ++e) {
      const json& rows = j["matrices"][e == 0 ? "S0" : "S1"];
      REQUIRE(rows.size() == static_cast<std::size_t>(S[static_cast<std::size_t>(e)].rows()));
      for (std::size_t r = 0; r < rows.size(); ++r)
        for (std::size_t c = 0; c < rows[r].size(); ++c)
          CHECK(rows[r][c].get<double>() ==
                S[static_cast<std::size_t>(e)](static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)));
    }
  }
  // Chaikin is the quadratic B-spline scheme: mask (1, 3, 3, 1)/4, dual, approximating, C^1.
  const json c = json::parse(io::analysis_json(sd::chaikin(), sd::analyze(sd::chaikin())));
  CHECK(c["mask"] == json::array({"0.25", "0.75", "0.75", "0.25"}));  // exact decimals
  CHECK(c["kind"] == "dual");
  CHECK(c["class"] == "approximating");
  CHECK(c["continuity"] == 1);
}
