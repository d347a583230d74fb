#include "report_file.h"

#include <fstream>

#include "commands.h"
#include "peak_memory.h"

namespace penumbra::cli {

void writeReport(nlohmann::json report, const std::string& path, const std::string& scene,
                 int polygons, const nlohmann::json& frames) {
  report["scene"] = scene;
  report["polygons"] = polygons;
  report["frames"] = frames;
  report["peak_memory_bytes"] = peakMemoryBytes();
  std::ofstream out(path);
  if (!out) throw UsageError("cannot write --report " + path);
  out << report.dump(2) << "\n";
  if (!out) throw UsageError("cannot write --report " + path);
}

}  // namespace penumbra::cli
