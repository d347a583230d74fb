#pragma once
// The scene-file targets' common check: a file is loaded the way every front end loads it
// (loadScene: dispatch, repeated corners removed, validation), then taken through what every verb
// does next (poses at the first and last frames and between keyframes, `info`'s closedness).
// Loading may reject the file with an InputError naming it; a scene it accepts must keep
// validateScene's promises at those poses. (The live scene's grid and ray caster are left to the
// structure-aware target: a flat scene's grid of 65,536 cells took seconds per input here.)

#include <string>

namespace penumbra::fuzz {

// `path`: the scene file to load; `mustMention`: what an InputError must name (see
// fuzz_outcome.h). Aborts with a finding on anything else.
void checkSceneFile(const std::string& path, const std::string& mustMention);

}  // namespace penumbra::fuzz
