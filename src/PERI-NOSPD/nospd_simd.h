/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   NOSPD_KERNEL_CLONES: build a hot kernel for the generic target and, on
   x86-64 Linux with GCC >= 11, also for AVX2 and AVX-512; the best one the
   CPU has is chosen when the plugin loads.  The kernels' bond sums and 3x3
   products are plain or `omp simd` loops that widen with the target, so a
   default (generic x86-64) build still runs wide on CPUs that have the
   units.  Put it on a free function that calls the loops (flatten inlines
   them into each copy).  Define NOSPD_NO_KERNEL_CLONES to build the generic
   kernels only.
------------------------------------------------------------------------- */

#ifndef NOSPD_SIMD_H
#define NOSPD_SIMD_H

#if !defined(NOSPD_NO_KERNEL_CLONES) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__clang__) && !defined(__INTEL_LLVM_COMPILER) && defined(__GNUC__) && __GNUC__ >= 11
#define NOSPD_KERNEL_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#else
#define NOSPD_KERNEL_CLONES
#endif


#include <cstring>

namespace NOSPD {

/* 3-vectors and 3x3 rows as one 4-lane vector (GCC vector extension): one
   register with AVX2 or AVX-512, split by the compiler elsewhere.  A load
   reads four doubles: the fourth must be readable memory. */
namespace simd {
  typedef double v4 __attribute__((vector_size(32)));

  // four doubles from p (alignment not required)
  inline __attribute__((always_inline)) v4 load4(const double *p)
  {
    v4 r;
    std::memcpy(&r, p, sizeof(r));
    return r;
  }
  inline __attribute__((always_inline)) v4 splat(double a)
  {
    return v4{a, a, a, a};
  }
  // the sum of the first three lanes
  inline __attribute__((always_inline)) double sum3(v4 p)
  {
    return p[0] + p[1] + p[2];
  }
  // the 3-vector dot product of the first three lanes
  inline __attribute__((always_inline)) double dot3(v4 a, v4 b)
  {
    return sum3(a * b);
  }
  // the sums of the first three lanes of four vectors, one per lane, each
  // added as dot3 adds (so sum3x4(a0 * b0, ...)[k] == dot3(a_k, b_k))
  inline __attribute__((always_inline)) v4 sum3x4(v4 p0, v4 p1, v4 p2, v4 p3)
  {
    typedef long long m4 __attribute__((vector_size(32)));
    const v4 t0 = __builtin_shuffle(p0, p1, m4{0, 4, 2, 6});    // x0 x1 z0 z1
    const v4 t1 = __builtin_shuffle(p0, p1, m4{1, 5, 3, 7});    // y0 y1 . .
    const v4 t2 = __builtin_shuffle(p2, p3, m4{0, 4, 2, 6});    // x2 x3 z2 z3
    const v4 t3 = __builtin_shuffle(p2, p3, m4{1, 5, 3, 7});    // y2 y3 . .
    const v4 xy = __builtin_shuffle(t0 + t1, t2 + t3, m4{0, 1, 4, 5});
    const v4 z = __builtin_shuffle(t0, t2, m4{2, 3, 6, 7});
    return xy + z;
  }
  // M v for M given by its columns c0 c1 c2
  inline __attribute__((always_inline)) v4 matvec(const double *cols, v4 v)
  {
    return load4(cols) * v[0] + load4(cols + 3) * v[1] + load4(cols + 6) * v[2];
  }
}    // namespace simd

}    // namespace NOSPD

#endif
