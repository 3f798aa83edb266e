// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <numeric>
#include <set>

#include "cifs/errors.hpp"
#include "cifs/ifs/analysis.hpp"
#include "cifs/ifs/attractor.hpp"
#include "cifs/nurbs/curve.hpp"
#include "cifs/nurbs/knot_automaton.hpp"
#include "cifs/render/chaos_density.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::render;

namespace {

Points planar_net() {
  Points P(3, 2);
  P << 0, 0, 1.3, 2.1, 3, -0.4;
  return P;
}

}  // namespace

TEST_CASE("CIFS chaos density matches the deterministic leaves binned through the same camera",
          "[render][chaos]") {
  // A non-uniform quadratic segment: 4 states, so the state channel has something to say.
  const auto a = ifs_test::quadratic_automaton(1, 2.5, 0.7);
  const std::vector<Points> nets = {planar_net()};
  FramingOptions framing;
  framing.width = framing.height = 64;
  const Camera camera = frame(nets[0], framing);
  const ViewTransform view = view_transform(camera);
  const int K = 9;

  // Deterministic: every depth-K node carries 2^−K; its start point is binned like the chaos game's.
  const ifs::EndFunctionals f = ifs::end_functionals(a);
  std::vector<double> mass(64 * 64, 0.0);
  std::vector<std::set<std::uint32_t>> states(64 * 64);
  ifs::for_each_leaf(a, nets, K, [&](const ifs::Leaf& leaf) {
    const Eigen::RowVectorXd p = f.start[leaf.state] * leaf.net;
    const Projected q = view.project({p(0), p(1), 0});
    REQUIRE((q.x >= 0 && q.x < 64 && q.y >= 0 && q.y < 64));
    const std::size_t i = static_cast<std::size_t>(q.y) * 64 + static_cast<std::size_t>(q.x);
    mass[i] += std::ldexp(1.0, -K);
    states[i].insert(static_cast<std::uint32_t>(leaf.state));
  });

  ChaosDensityOptions options;
  options.samples = std::uint64_t{1} << 21;
  options.seed = 77;
  options.threads = 2;
  options.depth = K;
  Image image;
  const ChaosDensityResult r = chaos_density(image, camera, a, nets, options);
  CHECK(r.depth == K);
  CHECK(r.outside == 0);
  const std::vector<float>& density = image.channels.at("density");
  CHECK(std::accumulate(density.begin(), density.end(), 0.0) == static_cast<double>(options.samples));
  const double N = static_cast<double>(options.samples);
  double worst = 0;
  for (std::size_t i = 0; i < mass.size(); ++i) {
    // Independent samples: the count of a pixel is binomial(N, mass).
    const double expected = N * mass[i];
    const double sigma = std::sqrt(N * mass[i] * (1 - mass[i]));
    if (mass[i] == 0) {
      CHECK(density[i] == 0.0f);
      CHECK((*image.state)[i] == kNoState);
      continue;
    }
    worst = std::max(worst, std::abs(density[i] - expected) / sigma);
    // The pixel's state is one of the states of the leaves that land there.
    CHECK(states[i].count((*image.state)[i]) == 1);
    CHECK(image.channels.at("A")[i] == 1.0f);
  }
  INFO("worst deviation " << worst << " sigma");
  CHECK(worst < 5.5);

  // Depth 1: two nodes, each drawn with probability ½: the G half (state 1), which starts at the
  // segment's start, and the D half (state 2), which starts at its middle (Cox–de Boor in long
  // double, the ifs tests' reference).
  options.depth = 1;
  options.samples = 1000;
  Image halves;
  chaos_density(halves, camera, a, nets, options);
  const Eigen::RowVectorXd mid = ifs_test::quadratic_reference(nets[0], 1, 2.5, 0.7, 0.5);
  const Eigen::RowVectorXd start = ifs_test::quadratic_reference(nets[0], 1, 2.5, 0.7, 0);
  const auto pixel = [&](const Eigen::RowVectorXd& p) {
    const Projected q = view.project({p(0), p(1), 0});
    return static_cast<std::size_t>(q.y) * 64 + static_cast<std::size_t>(q.x);
  };
  const std::vector<float>& h = halves.channels.at("density");
  CHECK(h[pixel(start)] + h[pixel(mid)] == 1000.0f);
  CHECK(std::abs(h[pixel(start)] - 500.0f) < 5 * std::sqrt(250.0f));
  CHECK((*halves.state)[pixel(start)] == 1);
  CHECK((*halves.state)[pixel(mid)] == 2);
}

TEST_CASE("CIFS chaos density: the same image for 1, 2 and 3 threads", "[render][chaos]") {
  const auto a = ifs_test::uniform_automaton(3, 2);  // two segments share the uniform state
  Points P0(4, 3), P1(4, 3);
  P0 << 0, 0, 0, 1, 2, 0.5, 2, -1, 1, 3, 1, 0.2;
  P1 << 1, 2, 0.5, 2, -1, 1, 3, 1, 0.2, 4, 0, -1;
  const std::vector<Points> nets = {P0, P1};
  Points all(8, 3);
  all << P0, P1;
  FramingOptions framing;
  framing.width = 96;
  framing.height = 80;
  const Camera camera = frame(all, framing);  // perspective
  std::vector<Image> images;
  for (const unsigned threads : {1u, 2u, 3u}) {
    ChaosDensityOptions options;
    options.samples = 3 * kDensityChunk + 123;  // a ragged last chunk
    options.seed = 5;
    options.threads = threads;
    Image image;
    const ChaosDensityResult r = chaos_density(image, camera, a, nets, options);
    CHECK(r.depth > 0);
    const std::vector<float>& d = image.channels.at("density");
    CHECK(std::accumulate(d.begin(), d.end(), 0.0) + static_cast<double>(r.outside) ==
          static_cast<double>(options.samples));
    images.push_back(std::move(image));
  }
  for (std::size_t k = 1; k < images.size(); ++k) {
    for (const char* name : {"density", "Z", "A"}) {
      const auto& x = images[0].channels.at(name);
      const auto& y = images[k].channels.at(name);
      CHECK(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0);
    }
    CHECK(*images[0].state == *images[k].state);
  }
}

TEST_CASE("CIFS chaos density: the automatic depth keeps every piece within the pixel tolerance",
          "[render][chaos]") {
  const auto a = ifs_test::quadratic_automaton(0.5, 1, 3);
  const std::vector<Points> nets = {planar_net()};
  FramingOptions framing;
  framing.width = framing.height = 256;
  const Camera camera = frame(nets[0], framing);
  ChaosDensityOptions options;
  options.samples = 1000;
  Image image;
  const int D = chaos_density(image, camera, a, nets, options).depth;
  CHECK(D > 3);
  // Node j at depth D holds the attractor points j·2^6 … (j+1)·2^6 of depth D + 6 (binary
  // automaton, one segment); its emitted point is the first of them.
  const Points p = ifs::attractor_points(a, nets, D + 6);
  const double pixels_per_unit = view_transform(camera).scale;
  double worst = 0;
  for (Eigen::Index j = 0; j + 1 < p.rows(); j += 64)
    for (Eigen::Index k = 0; k <= 64 && j + k < p.rows(); ++k)
      worst = std::max(worst, (p.row(j + k) - p.row(j)).norm() * pixels_per_unit);
  CHECK(worst <= options.pixel_tolerance);
  CHECK(worst > options.pixel_tolerance / 64);  // and the depth is not absurdly deep
}

TEST_CASE("CIFS chaos density of a rational quarter circle stays on the circle", "[render][chaos]") {
  Points P(3, 2);
  P << 1, 0, 1, 1, 0, 1;
  Eigen::VectorXd w(3);
  w << 1, std::sqrt(0.5), 1;
  const nurbs::Curve curve = nurbs::make_curve(2, {0, 0, 0, 1, 1, 1}, P, w);
  const nurbs::KnotAutomaton ka = nurbs::knot_automaton(curve);
  const automata::Automaton& a = ka.automaton;
  const std::vector<Points> nets = nurbs::initial_nets(ka, curve);
  Camera camera;
  camera.eye = {0.5, 0.5, 1};
  camera.target = {0.5, 0.5, 0};
  camera.ortho_height = 1.2;
  camera.width = camera.height = 120;  // 100 pixels per unit
  ChaosDensityOptions options;
  options.samples = 200000;
  options.rational = true;
  options.depth = 14;
  Image image;
  CHECK(chaos_density(image, camera, a, nets, options).outside == 0);
  const std::vector<float>& d = image.channels.at("density");
  std::size_t hit = 0;
  for (std::size_t y = 0; y < 120; ++y)
    for (std::size_t x = 0; x < 120; ++x)
      if (d[y * 120 + x] > 0) {
        ++hit;
        // The pixel's centre in the world, within a pixel diagonal of the unit circle.
        const double wx = 0.5 + (static_cast<double>(x) + 0.5 - 60) / 100;
        const double wy = 0.5 - (static_cast<double>(y) + 0.5 - 60) / 100;
        CHECK(std::abs(std::hypot(wx, wy) - 1) < 0.0072);
      }
  CHECK(hit > 150);  // the arc is about 157 pixels long
  options.depth = 0;
  CHECK_THROWS_WITH(chaos_density(image, camera, a, nets, options), Catch::Contains("explicit depth"));
}

TEST_CASE("CIFS chaos density refuses bad input", "[render][chaos]") {
  const auto a = ifs_test::uniform_automaton(2);
  Points net = planar_net();
  Camera camera;
  camera.ortho_height = 5;
  camera.width = camera.height = 16;
  Image image;
  CHECK_THROWS_WITH(chaos_density(image, camera, a, std::vector<Points>{}),
                    "0 control nets given for the automaton's 1 initial entries (one net per entry)");
  CHECK_THROWS_WITH(chaos_density(image, camera, a, std::vector<Points>{Points::Zero(2, 2)}),
                    "control net 0 has 2 points but its initial state 0 (uniform) holds 3");
  net(1, 1) = std::nan("");
  CHECK_THROWS_WITH(chaos_density(image, camera, a, std::vector<Points>{net}),
                    "control net 0 has a coordinate that is not finite");
  net = planar_net();
  ChaosDensityOptions options;
  options.depth = 65;
  CHECK_THROWS_AS(chaos_density(image, camera, a, std::vector<Points>{net}, options), InvalidInput);
  options.depth = 0;
  options.samples = std::uint64_t{1} << 32;
  CHECK_THROWS_WITH(chaos_density(image, camera, a, std::vector<Points>{net}, options),
                    Catch::Contains("2^32"));
  Camera empty = camera;
  empty.height = 0;
  Image fresh;
  CHECK_THROWS_WITH(chaos_density(fresh, empty, a, std::vector<Points>{net}), Catch::Contains("empty"));
}
