#pragma once
// Whether the frontend's AVX2 loops are compiled (GCC on x86-64: they take their target from a
// pragma or attribute, and the build itself targets plain x86-64), and whether this processor and
// its OS run them. Internal to the frontend.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define PLANEMAP_AVX2_LOOPS 1
#endif

namespace planemap {

inline bool CpuHasAvx2() {
#ifdef PLANEMAP_AVX2_LOOPS
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
#else
  return false;
#endif
}

}  // namespace planemap
