// Forced into every file when the compiler is clang (CMakeLists.txt; the fuzz and sanitizer
// builds of scripts/ci-fuzz.sh and scripts/ci-sanitizers.sh): GCC's
// __builtin_shuffle (rasterizer/pipeline.cpp, a runtime-mask vector shuffle) has no clang
// spelling, so it is emulated element by element here. The GCC builds never see this file.
#pragma once
#if defined(__clang__) && !defined(__GNUC_SHUFFLE_COMPAT)
#define __GNUC_SHUFFLE_COMPAT 1
#define __builtin_shuffle(v, m)                                     \
  ([](auto a_, auto m_) {                                           \
    decltype(a_) r_;                                                \
    constexpr int n_ = sizeof(a_) / sizeof(a_[0]);                  \
    for (int i_ = 0; i_ < n_; ++i_) r_[i_] = a_[m_[i_] & (n_ - 1)]; \
    return r_;                                                      \
  }((v), (m)))
#endif
