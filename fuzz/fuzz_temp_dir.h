#pragma once
// The loaders take paths, so a fuzzer writes each input into files. Every fuzzer process gets a
// directory of its own (libFuzzer's -fork and -jobs run several at once), created on first use
// and removed when the process exits normally; a crashing input leaves it behind in the
// temporary directory, which is what one wants when looking at the crash.

#include <string>
#include <string_view>

namespace penumbra::fuzz {

class FuzzTempDir {
 public:
  // The process's directory, created on first call.
  static FuzzTempDir& instance();

  // Writes `bytes` to the file `name` in the directory (replacing it) and returns its path.
  std::string write(const std::string& name, std::string_view bytes) const;
  // Removes the file `name` when it exists: an input that gives no such file must not see the
  // previous input's (every input runs alone, so that a crash replays from its bytes).
  void remove(const std::string& name) const;
  // An input carrying a second file after `separator` (an OBJ's MTL, a glTF's buffer): writes
  // what follows it to `sideFile`, or removes `sideFile` when the input has no separator, and
  // returns what precedes it.
  std::string_view splitOff(std::string_view input, std::string_view separator,
                            const std::string& sideFile) const;
  std::string path(const std::string& name) const;
  const std::string& directory() const { return directory_; }

  ~FuzzTempDir();
  FuzzTempDir(const FuzzTempDir&) = delete;
  FuzzTempDir& operator=(const FuzzTempDir&) = delete;

 private:
  FuzzTempDir();
  std::string directory_;
};

}  // namespace penumbra::fuzz
