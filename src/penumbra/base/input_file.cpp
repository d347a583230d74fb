#include "penumbra/base/input_file.h"

#include <filesystem>
#include <system_error>

#include "penumbra/base/input_error.h"

namespace penumbra {

std::ifstream openInputFile(const std::string& path, const std::string& what,
                            std::ios::openmode mode) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error || !std::filesystem::exists(status)) throw InputError(path, "cannot open " + what);
  if (std::filesystem::is_directory(status))
    throw InputError(path, what + " is a folder, not a file");
  std::ifstream in(path, mode);
  if (!in) throw InputError(path, "cannot open " + what);
  return in;
}

}  // namespace penumbra
