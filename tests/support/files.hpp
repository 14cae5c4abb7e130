// File helpers shared by the tests that write files (header-only: the format tests are their own
// executable, without the support library).
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace rptest {

// Files in the directory of `path` whose name starts with the name of `path` (left-over
// temporary files of a write to `path`), excluding `path` itself.
inline int leftovers(const std::string& path) {
  const std::filesystem::path target(path);
  const std::string prefix = target.filename().string();
  int count = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(target.parent_path(), error)) {
    const std::string name = entry.path().filename().string();
    if (name != prefix && name.compare(0, prefix.size(), prefix) == 0) ++count;
  }
  return count;
}

}  // namespace rptest
