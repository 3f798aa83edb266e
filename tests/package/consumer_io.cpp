// SPDX-License-Identifier: MIT
// An io consumer (find_package(cifs COMPONENTS io)) that never finds nlohmann_json itself.
#include <cifs/io/json.hpp>
#include <cstdio>

int main() {
  using namespace cifs;
  Points P(2, 2);
  P << 0, 0, 1, 2;
  const std::string text = io::to_json(nurbs::make_curve(1, {0, 0, 1, 1}, P));
  std::printf("consumer (io): %s\n", text.c_str());
  return text.find("\"curve\"") != std::string::npos ? 0 : 1;
}
