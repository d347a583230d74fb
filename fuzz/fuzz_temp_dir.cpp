#include "fuzz_temp_dir.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

namespace penumbra::fuzz {

namespace fs = std::filesystem;

FuzzTempDir& FuzzTempDir::instance() {
  static FuzzTempDir dir;
  return dir;
}

FuzzTempDir::FuzzTempDir() {
  // The pid alone may repeat across containers sharing /tmp; a random suffix makes the name ours.
  std::random_device random;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path candidate =
        fs::temp_directory_path() /
        ("penumbra-fuzz-" + std::to_string(::getpid()) + "-" + std::to_string(random() % 1000000));
    std::error_code error;
    if (fs::create_directory(candidate, error)) {
      directory_ = candidate.string();
      return;
    }
  }
  // Not a finding of the code under test: the fuzzer cannot run here at all.
  std::fprintf(stderr, "fuzz: cannot create a temporary directory under %s\n",
               fs::temp_directory_path().c_str());
  std::abort();
}

FuzzTempDir::~FuzzTempDir() {
  std::error_code ignored;
  fs::remove_all(directory_, ignored);
}

std::string FuzzTempDir::path(const std::string& name) const {
  return (fs::path(directory_) / name).string();
}

std::string FuzzTempDir::write(const std::string& name, std::string_view bytes) const {
  const std::string file = path(name);
  // A new file rather than the old one truncated: ext4 flushes a file truncated and written again
  // when it is closed (auto_da_alloc), which cost milliseconds per input.
  remove(name);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", file.c_str());
    std::abort();
  }
  return file;
}

std::string_view FuzzTempDir::splitOff(std::string_view input, std::string_view separator,
                                       const std::string& sideFile) const {
  const size_t split = input.find(separator);
  if (split == std::string_view::npos)
    remove(sideFile);
  else
    write(sideFile, input.substr(split + separator.size()));
  return input.substr(0, split);
}

void FuzzTempDir::remove(const std::string& name) const {
  std::error_code ignored;
  fs::remove(path(name), ignored);
}

}  // namespace penumbra::fuzz
