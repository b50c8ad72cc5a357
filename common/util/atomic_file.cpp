#include "common/util/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "common/util/interrupt.h"

namespace firstshot {

void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write,
                     OnInterrupt onInterrupt) {
  namespace stdfs = std::filesystem;
  const stdfs::path target(path);
  // ".NAME.tmpPID" beside the target (built by appending: GCC 12 warns -Wrestrict on "." + name).
  std::string tmpName = ".";
  tmpName += target.filename().string();
  tmpName += ".tmp";
  tmpName += std::to_string(getpid());
  const std::string tmp = (target.parent_path() / tmpName).string();
  try {
    write(tmp);
    if (onInterrupt == OnInterrupt::Discard) {
      std::string point = "write-";
      point += target.filename().string();
      testInterruptPoint(point);
      throwIfInterrupted(path + " was not written");
    }
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

}  // namespace firstshot
