#pragma once
// A benchmark's entry point: what its body throws (a scene file's InputError, an option's value
// that is not a number) is printed as one line naming the program, with exit status 2, instead
// of ending in std::terminate.

#include <cstdio>
#include <exception>

namespace penumbra::bench {

template <class Body>
int runReportingErrors(const char* program, int argc, char** argv, Body body) {
  try {
    return body(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return 2;
  }
}

}  // namespace penumbra::bench
