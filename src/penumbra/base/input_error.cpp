#include "penumbra/base/input_error.h"

namespace penumbra {

namespace {
std::string formatMessage(const std::string& location, const std::string& problem) {
  return location.empty() ? problem : location + ": " + problem;
}
}  // namespace

InputError::InputError(const std::string& location, const std::string& problem)
    : std::runtime_error(formatMessage(location, problem)), location_(location), problem_(problem) {}

}  // namespace penumbra
