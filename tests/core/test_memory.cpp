// SPDX-License-Identifier: MIT
// Huge-page advice: where the kernel gives transparent huge pages only on request ("madvise"
// mode), an advised buffer is backed by them once written, and its contents are those written.
#include "cifs/memory.hpp"

#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

namespace {

/// Kilobytes of AnonHugePages in the mapping of /proc/self/smaps that holds `address`, or −1.
long huge_kilobytes_at(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= a && a < end;
    } else if (inside && line.rfind("AnonHugePages:", 0) == 0) {
      return std::stol(line.substr(14));
    }
  }
  return -1;
}

std::string thp_mode() {
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(file, mode);
  return mode;
}

}  // namespace

TEST_CASE("a buffer advised for huge pages gets them, contents unchanged", "[core][memory]") {
  std::vector<std::int32_t> v;
  cifs::assign_huge(v, std::size_t{6} << 20, std::int32_t{0});  // 24 MiB
  std::iota(v.begin(), v.end(), 0);
  CHECK(v[12345] == 12345);
  CHECK(v.back() == static_cast<std::int32_t>(v.size() - 1));
  if (thp_mode().find("[madvise]") == std::string::npos) {
    WARN("transparent huge pages are not in madvise mode here (" << thp_mode() << "): effect not checked");
    return;
  }
  CHECK(huge_kilobytes_at(v.data() + v.size() / 2) >= 2048);
  // Small buffers are left alone; null and odd sizes are accepted.
  cifs::advise_huge_pages(nullptr, 1 << 30);
  cifs::advise_huge_pages(v.data() + 1, 4097);
}
