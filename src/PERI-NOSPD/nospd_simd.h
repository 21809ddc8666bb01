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

#endif
