#pragma once
// Errors caused by what a user gave us (a scene file, a points file, an option).
// They carry a location so that messages read `file:line: problem` (pbrt style) and the CLI maps
// them to exit code 2. Untrusted input never asserts: it throws InputError.

#include <stdexcept>
#include <string>

namespace penumbra {

class InputError : public std::runtime_error {
 public:
  // `location` is "file", "file:line" or "file: /json/path"; empty when unknown.
  InputError(const std::string& location, const std::string& problem);

  const std::string& location() const { return location_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string location_;
  std::string problem_;
};

}  // namespace penumbra
