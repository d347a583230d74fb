#pragma once
// What a fuzz target counts as a finding. Bad input is answered by an InputError that names the
// input's file (the expected outcome, CONTRIBUTING.md "Errors"); anything else thrown
// (std::out_of_range, std::bad_alloc, ...) and any result that breaks a documented postcondition is
// a finding: it is printed on stderr and the process aborts, which libFuzzer records as a crash
// (saving the input) and the replay test as a failure. Sanitizer reports and hangs are caught by
// the sanitizers and libFuzzer themselves.

#include <exception>
#include <string>

#include "penumbra/base/input_error.h"

namespace penumbra::fuzz {

[[noreturn]] void reportFinding(const std::string& what);

// The exception's dynamic type (demangled) and message.
std::string describe(const std::exception& e);

// A finding unless the error has a problem and a location, and its message mentions
// `mustMention` (the input's file, or the directory holding the input's files).
void checkInputError(const InputError& e, const std::string& mustMention);

// With PENUMBRA_FUZZ_VERBOSE=1 in the environment, prints what an input gave (accepted, or the
// InputError that rejected it): to see how deep seeds reach. Silent otherwise.
void noteOutcome(const std::string& outcome);

// Runs f(): true when it returned, false when it threw an acceptable InputError (see
// checkInputError); any other exception is a finding.
template <typename F>
bool succeedsOrRejects(const std::string& mustMention, F&& f) {
  try {
    f();
    return true;
  } catch (const InputError& e) {
    checkInputError(e, mustMention);
    noteOutcome(std::string("rejected: ") + e.what());
    return false;
  } catch (const std::exception& e) {
    reportFinding("an exception other than InputError escaped: " + describe(e));
  } catch (...) {
    reportFinding("an exception not derived from std::exception escaped");
  }
}

}  // namespace penumbra::fuzz
