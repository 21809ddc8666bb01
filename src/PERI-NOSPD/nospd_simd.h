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
  // the 3-vector dot product of the first three lanes
  inline __attribute__((always_inline)) double dot3(v4 a, v4 b)
  {
    const v4 p = a * b;
    return p[0] + p[1] + p[2];
  }
  // M v for M given by its columns c0 c1 c2
  inline __attribute__((always_inline)) v4 matvec(const double *cols, v4 v)
  {
    return load4(cols) * v[0] + load4(cols + 3) * v[1] + load4(cols + 6) * v[2];
  }
}    // namespace simd

}    // namespace NOSPD

#endif
