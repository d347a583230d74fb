#pragma once
// Writing a `--report` JSON file: the common fields every report carries (DESIGN.md §6), then the
// command's own.

#include <nlohmann/json.hpp>
#include <string>

namespace penumbra::cli {

// Adds "scene", "polygons", "frames" and "peak_memory_bytes" to `report` and writes it to `path`,
// indented; throws UsageError naming the path when it cannot be written.
void writeReport(nlohmann::json report, const std::string& path, const std::string& scene,
                 int polygons, const nlohmann::json& frames);

}  // namespace penumbra::cli
