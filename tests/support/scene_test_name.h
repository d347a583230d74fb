#pragma once
// The name of a test instantiated per bundled scene path ("office-desk/desk-145.json" ->
// "desk_145"): the file name without its folder and extension, other characters as '_'.

#include <gtest/gtest.h>

#include <cctype>
#include <string>

namespace penumbra::test {

inline std::string sceneTestName(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param.substr(info.param.find('/') + 1);
  name = name.substr(0, name.rfind('.'));
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

}  // namespace penumbra::test
