#pragma once
// Writing an output file so that nothing is lost or half-written: the bytes go to a temporary file
// beside the destination, are flushed and checked, and then renamed over it, so a failure (a full
// disk, a crash) leaves the old file, not a truncated one, and a write error is reported instead
// of "wrote". A destination that exists and is not a regular file (/dev/null, /dev/full, a pipe)
// is written directly, with the same checks.

#include <filesystem>
#include <functional>
#include <ostream>

namespace penumbra {

// Calls write(stream) and commits the result to `path`. Throws std::runtime_error naming the path
// when the file cannot be written.
void writeOutputFile(const std::filesystem::path& path,
                     const std::function<void(std::ostream&)>& write);

// The temporary path beside `path` that writeOutputFile uses (for writers that need a file name,
// such as OpenEXR's; `path` itself for a special file), and the commit that renames it over
// `path`.
std::filesystem::path temporaryPathFor(const std::filesystem::path& path);
void commitTemporary(const std::filesystem::path& temporary, const std::filesystem::path& path);

}  // namespace penumbra
