#pragma once
// Internal invariants (programming errors, never user input): CHECK always, DCHECK in debug builds.
// On failure they print the operands and abort, so a broken invariant is never silent.

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace penumbra::detail {
[[noreturn]] inline void checkFailed(const char* file, int line, const char* expr,
                                     const std::string& operands) {
  std::fprintf(stderr, "%s:%d: CHECK failed: %s%s\n", file, line, expr, operands.c_str());
  std::abort();
}
template <typename A, typename B>
std::string describeOperands(const A& a, const B& b) {
  std::ostringstream out;
  out << " (" << a << " vs " << b << ")";
  return out.str();
}
}  // namespace penumbra::detail

#define PENUMBRA_CHECK(cond) \
  ((cond) ? (void)0 : ::penumbra::detail::checkFailed(__FILE__, __LINE__, #cond, ""))
#define PENUMBRA_CHECK_OP(a, op, b)                                                    \
  (((a)op(b)) ? (void)0                                                                \
              : ::penumbra::detail::checkFailed(__FILE__, __LINE__, #a " " #op " " #b, \
                                                ::penumbra::detail::describeOperands(a, b)))
#define CHECK(cond) PENUMBRA_CHECK(cond)
#define CHECK_EQ(a, b) PENUMBRA_CHECK_OP(a, ==, b)
#define CHECK_NE(a, b) PENUMBRA_CHECK_OP(a, !=, b)
#define CHECK_LT(a, b) PENUMBRA_CHECK_OP(a, <, b)
#define CHECK_LE(a, b) PENUMBRA_CHECK_OP(a, <=, b)
#define CHECK_GT(a, b) PENUMBRA_CHECK_OP(a, >, b)
#define CHECK_GE(a, b) PENUMBRA_CHECK_OP(a, >=, b)
#ifdef NDEBUG
#define DCHECK(cond) ((void)0)
#else
#define DCHECK(cond) PENUMBRA_CHECK(cond)
#endif
