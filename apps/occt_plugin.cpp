// SPDX-License-Identifier: MIT
// cifs — the CLI's STEP and IGES: OpenCASCADE's libraries are opened only when a command first meets
// such a file (io::set_cad_loader): the plugin next to the installed libraries, else the build tree's.
#include "occt_plugin.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cifs/errors.hpp"

namespace cifs::cli {
namespace {

/// Where the plugin may be: beside an installed cifs (relative to the executable), then the build tree.
std::vector<std::filesystem::path> plugin_candidates() {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe", ec);
  if (!ec) out.push_back((self.parent_path() / CIFS_OCCT_PLUGIN_INSTALLED).lexically_normal());
  out.emplace_back(CIFS_OCCT_PLUGIN_BUILD);
  return out;
}

io::CadCodec load_plugin() {
  std::string tried;
  for (const std::filesystem::path& path : plugin_candidates()) {
    if (!std::filesystem::exists(path)) {
      tried += (tried.empty() ? "" : ", ") + path.string();
      continue;
    }
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept open for the process
    if (module == nullptr)
      throw InvalidInput("the OpenCASCADE plugin " + path.string() + " does not load: " + dlerror());
    auto* codec = reinterpret_cast<void (*)(io::CadCodec*)>(dlsym(module, "cifs_occt_codec"));
    if (codec == nullptr) throw InvalidInput("the OpenCASCADE plugin " + path.string() + " is not cifs's");
    io::CadCodec out;
    codec(&out);
    return out;
  }
  throw InvalidInput("the OpenCASCADE plugin of this cifs is missing (looked for " + tried + ")");
}

}  // namespace

void load_occt_on_demand() {
  io::set_cad_loader(load_plugin);
}

}  // namespace cifs::cli
