// Invariant checks. CHECK is always on and prints both operands; DCHECK compiles away in release
// builds so hot loops pay nothing. These are for programming errors; bad user input goes through
// relief::Status (status.h) instead.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace relief::detail {
[[noreturn]] inline void check_failed(const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", file, line, what.c_str());
  std::abort();
}
template <class A, class B>
std::string check_message(const char* expr, const A& a, const B& b) {
  std::ostringstream os;
  os << expr << " (" << a << " vs " << b << ")";
  return os.str();
}
}  // namespace relief::detail

#define RELIEF_CHECK(cond)                                                  \
  do {                                                                      \
    if (!(cond)) ::relief::detail::check_failed(__FILE__, __LINE__, #cond); \
  } while (0)
#define RELIEF_CHECK_OP(a, op, b)                                                    \
  do {                                                                               \
    const auto& relief_a_ = (a);                                                     \
    const auto& relief_b_ = (b);                                                     \
    if (!(relief_a_ op relief_b_))                                                   \
      ::relief::detail::check_failed(                                                \
          __FILE__, __LINE__,                                                        \
          ::relief::detail::check_message(#a " " #op " " #b, relief_a_, relief_b_)); \
  } while (0)

#define CHECK(cond) RELIEF_CHECK(cond)
#define CHECK_EQ(a, b) RELIEF_CHECK_OP(a, ==, b)
#define CHECK_NE(a, b) RELIEF_CHECK_OP(a, !=, b)
#define CHECK_LT(a, b) RELIEF_CHECK_OP(a, <, b)
#define CHECK_LE(a, b) RELIEF_CHECK_OP(a, <=, b)
#define CHECK_GT(a, b) RELIEF_CHECK_OP(a, >, b)
#define CHECK_GE(a, b) RELIEF_CHECK_OP(a, >=, b)

#ifdef NDEBUG
#define DCHECK(cond) \
  do {               \
  } while (0)
#define DCHECK_LT(a, b) DCHECK(true)
#define DCHECK_LE(a, b) DCHECK(true)
#define DCHECK_GE(a, b) DCHECK(true)
#else
#define DCHECK(cond) RELIEF_CHECK(cond)
#define DCHECK_LT(a, b) RELIEF_CHECK_OP(a, <, b)
#define DCHECK_LE(a, b) RELIEF_CHECK_OP(a, <=, b)
#define DCHECK_GE(a, b) RELIEF_CHECK_OP(a, >=, b)
#endif
