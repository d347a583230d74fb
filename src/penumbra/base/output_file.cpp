#include "penumbra/base/output_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace penumbra {

namespace {

bool isSpecialFile(const std::filesystem::path& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  return !error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw std::runtime_error("cannot write '" + path.string() + "': " + why);
}

}  // namespace

std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
  if (isSpecialFile(path)) return path;  // written directly: no file is created beside a device
  std::filesystem::path temporary = path;
  temporary += ".partial-" + std::to_string(::getpid());
  return temporary;
}

void commitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  if (temporary == path) return;
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    fail(path, "cannot replace it");
  }
}

void writeOutputFile(const std::filesystem::path& path,
                     const std::function<void(std::ostream&)>& write) {
  if (isSpecialFile(path)) {
    std::ofstream out(path, std::ios::binary);
    if (!out) fail(path, "cannot open it");
    write(out);
    out.flush();
    if (!out) fail(path, "write error");
    return;
  }
  const std::filesystem::path temporary = temporaryPathFor(path);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail(path, "cannot create a file there");
    write(out);
    out.flush();
    out.close();
    if (!out) {
      std::error_code error;
      std::filesystem::remove(temporary, error);
      fail(path, "write error");
    }
  }
  commitTemporary(temporary, path);
}

}  // namespace penumbra
