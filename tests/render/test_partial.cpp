// SPDX-License-Identifier: MIT
// Distributed renders without MPI: parts drawn one after another, their shares combined here.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>

#include "cifs/errors.hpp"
#include "cifs/mesh.hpp"
#include "cifs/render/chaos_density.hpp"
#include "cifs/render/partial.hpp"
#include "cifs/render/raster.hpp"
#include "ifs/helpers.hpp"

using namespace cifs;
using namespace cifs::render;

namespace {

bool same_bytes(const PixelShare& a, const PixelShare& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// The shares of `parts` combined over every pixel, unpacked into `root` (part 0's share).
void reduce(std::vector<Share>& parts) {
  const std::size_t pixels = parts[0].image.width * parts[0].image.height;
  std::vector<PixelShare> all(pixels), mine(pixels);
  pack(parts[0], 0, all);
  for (std::size_t p = 1; p < parts.size(); ++p) {
    pack(parts[p], 0, mine);
    combine_shares(mine, all);
  }
  unpack(parts[0], 0, all);
}

void require_same_image(const Image& a, const Image& b) {
  REQUIRE(a.channels.size() == b.channels.size());
  for (const auto& [name, values] : a.channels) {
    INFO(name);
    const auto& other = b.channels.at(name);
    REQUIRE(values.size() == other.size());
    CHECK(std::memcmp(values.data(), other.data(), values.size() * sizeof(float)) == 0);
  }
  CHECK(*a.state == *b.state);
}

/// A wavy 12 × 12 quad grid.
Mesh wavy_grid() {
  const int n = 12;
  Points V(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) V.row(i * n + j) << i, j, 1.5 * std::sin(0.7 * i) * std::cos(0.5 * j);
  std::vector<int> corners;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j)
      corners.insert(corners.end(), {i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1});
  Mesh mesh = uniform_mesh(V, corners, 4);
  for (std::size_t f = 0; f < face_count(mesh); ++f) mesh.states.push_back(static_cast<std::uint32_t>(f % 5));
  return mesh;
}

}  // namespace

TEST_CASE("combine_shares: densities add, the nearest (then smallest key) brings its payload",
          "[render][partial]") {
  PixelShare a{2, 5, 1.0f, 0.1f, 0.2f, 0.3f, 1, 0, 0, 1, 7, 0};
  PixelShare b{3, 1, 1.0f, 0.4f, 0.5f, 0.6f, 1, 0, 1, 0, 9, 0};
  PixelShare c{4, 9, 0.5f, 0.7f, 0.8f, 0.9f, 1, 1, 0, 0, 11, 0};
  std::vector<PixelShare> ab{b};
  combine_shares(std::vector<PixelShare>{a}, ab);
  // Equal depths: key 1 < 5, so b's colour and state, with 2 + 3 hits.
  CHECK(ab[0].density == 5);
  CHECK(ab[0].state == 9);
  CHECK(ab[0].r == 0.4f);
  std::vector<PixelShare> ba{a};
  combine_shares(std::vector<PixelShare>{b}, ba);
  CHECK(same_bytes(ab[0], ba[0]));  // commutative
  // c is nearer: it wins whatever its key; (a ⊕ b) ⊕ c = a ⊕ (b ⊕ c).
  std::vector<PixelShare> left = ab, bc{c};
  combine_shares(std::vector<PixelShare>{c}, left);
  combine_shares(std::vector<PixelShare>{b}, bc);
  std::vector<PixelShare> right = bc;
  combine_shares(std::vector<PixelShare>{a}, right);
  CHECK(left[0].density == 9);
  CHECK(left[0].state == 11);
  CHECK(same_bytes(left[0], right[0]));
  // An empty share changes nothing.
  std::vector<PixelShare> with_empty = left;
  combine_shares(std::vector<PixelShare>{PixelShare{}}, with_empty);
  CHECK(same_bytes(with_empty[0], left[0]));
}

TEST_CASE("check_part refuses a part outside its count", "[render][partial]") {
  CHECK_NOTHROW(check_part({2, 3}));
  CHECK_THROWS_AS(check_part({3, 3}), InvalidInput);
  CHECK_THROWS_AS(check_part({0, 0}), InvalidInput);
}

TEST_CASE("Chaos density in three parts combines into the single-process image", "[render][partial][chaos]") {
  const auto a = ifs_test::quadratic_automaton(1, 2.5, 0.7);
  Points net(3, 2);
  net << 0, 0, 1.3, 2.1, 3, -0.4;
  const std::vector<Points> nets = {net};
  FramingOptions framing;
  framing.width = 70;
  framing.height = 50;
  const Camera camera = frame(net, framing);
  ChaosDensityOptions options;
  options.samples = 5 * kDensityChunk + 123;  // 6 chunks: parts of 2, 2 and 2 chunks, the last short
  options.seed = 11;
  options.threads = 2;
  options.depth = 12;
  Image whole;
  chaos_density(whole, camera, a, nets, options);

  std::vector<Share> parts(3);
  double total = 0;
  for (unsigned p = 0; p < 3; ++p) {
    Share& share = parts[p];
    share.kind = Share::Kind::points;
    share.part = {p, 3};
    share.color = options.color;
    ChaosDensityOptions po = options;
    po.part = share.part;
    po.threads = 1 + p % 2;
    chaos_density_layer(share.points, share.image, camera, a, nets, po);
    double sum = 0;
    for (const double d : share.points.density) sum += d;
    // Two chunks of 2^16 samples (part 2: one full and the short one), minus those off screen.
    CHECK(sum > 0);
    CHECK(sum <= (p < 2 ? 2.0 * kDensityChunk : double(kDensityChunk + 123)));
    total += sum;
  }
  double whole_sum = 0;
  for (const float d : whole.channels.at("density")) whole_sum += d;
  CHECK(total == whole_sum);
  reduce(parts);
  require_same_image(parts[0].image, whole);
}

TEST_CASE("render_mesh and render_segments in row bands combine into the single-process image",
          "[render][partial]") {
  const Mesh mesh = wavy_grid();
  FramingOptions framing;
  framing.width = 150;
  framing.height = 110;  // 4 bands, the last one short
  const Camera camera = frame(mesh.vertices, framing);
  Segments edges;
  edges.vertices = mesh.vertices;
  for (int i = 0; i + 1 < 12; ++i) edges.segments.push_back({i * 12, (i + 1) * 12 + 5});
  const auto draw = [&](Image& image, Part part) {
    CurveStyle under;
    under.width = 2;
    render_segments(image, camera, edges, under);  // every part draws the layer below whole
    SurfaceStyle style;
    style.threads = 2;
    style.part = part;
    render_mesh(image, camera, mesh, style);
    CurveStyle over;
    over.part = part;
    over.color = {1, 0, 0};
    Segments diagonal;
    diagonal.vertices = mesh.vertices;
    diagonal.segments = {{0, 143}, {11, 132}};
    render_segments(image, camera, diagonal, over);
  };
  Image whole;
  draw(whole, {});
  for (const unsigned count : {2u, 3u, 5u}) {
    INFO(count << " parts");
    std::vector<Share> parts(count);
    for (unsigned p = 0; p < count; ++p) {
      parts[p].part = {p, count};
      draw(parts[p].image, parts[p].part);
    }
    // A part alone leaves the other bands' coverage as the layer below drew it.
    const auto& A0 = parts[0].image.channels.at("A");
    const auto& A = whole.channels.at("A");
    bool differs_outside = false;
    for (std::size_t i = 0; i < A.size(); ++i)
      if (!owns_row(parts[0].part, i / 150) && A0[i] != A[i]) differs_outside = true;
    CHECK(differs_outside);
    reduce(parts);
    require_same_image(parts[0].image, whole);
  }
}
