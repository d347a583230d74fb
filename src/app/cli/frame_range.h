#pragma once
// The `--frames A:B` option shared by the commands that run over a range of frames.

#include <string>

namespace penumbra::cli {

struct FrameRange {
  int first = 0;
  int last = 0;  // inclusive
};

// Parses "A:B" (decimal, A <= B < frameCount); an empty text means all frames.
// Throws UsageError naming the option and the accepted range otherwise.
FrameRange parseFrameRange(const std::string& text, int frameCount);

// Checks a single `--frame` value: 0 <= frame < frameCount, else UsageError naming the range.
void checkFrame(int frame, int frameCount);

}  // namespace penumbra::cli
