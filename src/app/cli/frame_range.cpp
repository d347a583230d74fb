#include "frame_range.h"

#include <charconv>

#include "commands.h"

namespace penumbra::cli {

namespace {

// Parses a whole decimal field of at most 9 digits (so it fits an int); false otherwise.
bool parseFrameNumber(const char* begin, const char* end, int& value) {
  // Digits only: no sign (a negative frame is no frame; from_chars would take one).
  if (begin == end || end - begin > 9 || *begin < '0' || *begin > '9') return false;
  const auto [stop, error] = std::from_chars(begin, end, value);
  return error == std::errc() && stop == end;
}

}  // namespace

FrameRange parseFrameRange(const std::string& text, int frameCount) {
  if (text.empty()) return {0, frameCount - 1};
  const auto colon = text.find(':');
  FrameRange range;
  const char* data = text.data();
  if (colon == std::string::npos || !parseFrameNumber(data, data + colon, range.first) ||
      !parseFrameNumber(data + colon + 1, data + text.size(), range.last))
    throw UsageError("--frames must look like A:B, got '" + text + "'");
  if (range.first > range.last || range.last >= frameCount)
    throw UsageError("--frames " + text + " is outside the scene's frames 0.." +
                     std::to_string(frameCount - 1));
  return range;
}

void checkFrame(int frame, int frameCount) {
  if (frame < 0 || frame >= frameCount)
    throw UsageError("--frame " + std::to_string(frame) + " is outside the scene's frames 0.." +
                     std::to_string(frameCount - 1));
}

}  // namespace penumbra::cli
