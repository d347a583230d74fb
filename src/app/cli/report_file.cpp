#include "report_file.h"

#include "commands.h"
#include "peak_memory.h"
#include "penumbra/base/output_file.h"

namespace penumbra::cli {

void writeReport(nlohmann::json report, const std::string& path, const std::string& scene,
                 int polygons, const nlohmann::json& frames) {
  report["scene"] = scene;
  report["polygons"] = polygons;
  report["frames"] = frames;
  report["peak_memory_bytes"] = peakMemoryBytes();
  // Whole or not at all (a failure, exit 2, names the file): the write is flushed and checked
  // before "done", which a small report's buffered failure escaped.
  writeOutputFile(path, [&](std::ostream& out) { out << report.dump(2) << "\n"; });
}

}  // namespace penumbra::cli
