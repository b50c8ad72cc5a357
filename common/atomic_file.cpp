#include "common/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fs {

void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write) {
  namespace stdfs = std::filesystem;
  const stdfs::path target(path);
  const std::string tmp = (target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(getpid()))).string();
  try {
    write(tmp);
  } catch (...) {
    std::error_code ec;
    stdfs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  stdfs::rename(tmp, target, ec);
  if (ec) {
    stdfs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write file (" + ec.message() + ")");
  }
}

}  // namespace fs
