#include "fuzz_outcome.h"

#include <cxxabi.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <typeinfo>

namespace penumbra::fuzz {

void reportFinding(const std::string& what) {
  std::fprintf(stderr, "\n==penumbra-fuzz== FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

void noteOutcome(const std::string& outcome) {
  static const bool verbose = [] {
    const char* value = std::getenv("PENUMBRA_FUZZ_VERBOSE");
    return value && std::string(value) == "1";
  }();
  if (verbose) std::fprintf(stderr, "penumbra-fuzz: %s\n", outcome.c_str());
}

std::string describe(const std::exception& e) {
  const char* mangled = typeid(e).name();
  int status = 0;
  const std::unique_ptr<char, void (*)(void*)> demangled(
      abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
  return std::string(status == 0 && demangled ? demangled.get() : mangled) + ": " + e.what();
}

void checkInputError(const InputError& e, const std::string& mustMention) {
  if (e.problem().empty()) reportFinding("InputError without a problem: " + std::string(e.what()));
  if (e.location().empty())
    reportFinding("InputError without a location: " + std::string(e.what()));
  if (std::string(e.what()).find(mustMention) == std::string::npos)
    reportFinding("InputError that does not name the input (" + mustMention +
                  "): " + std::string(e.what()));
}

}  // namespace penumbra::fuzz
