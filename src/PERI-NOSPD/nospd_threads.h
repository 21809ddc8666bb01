/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Splitting a loop over atoms among OpenMP threads, for the /omp styles.
   Knows nothing of LAMMPS.
------------------------------------------------------------------------- */

#ifndef NOSPD_THREADS_H
#define NOSPD_THREADS_H

#include <exception>
#include <functional>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace NOSPD {

/* fn(from, to, tid) over [0, n) in nthreads contiguous ranges, the same
   split every time for the same n and nthreads, so that per-thread sums
   added in thread order give the same bits run after run.  An exception
   thrown in a thread (a LAMMPS error) is rethrown here after the region:
   the first one caught.  nthreads < 2 or no OpenMP: one call, [0, n). */
inline void run_ranges(int nthreads, int n, const std::function<void(int, int, int)> &fn)
{
#if defined(_OPENMP)
  if (nthreads < 2 || n < 2 * nthreads) {
    fn(0, n, 0);
    return;
  }
  std::exception_ptr failure;
#pragma omp parallel num_threads(nthreads)
  {
    const int tid = omp_get_thread_num();
    const int from = static_cast<int>((static_cast<long>(n) * tid) / nthreads);
    const int to = static_cast<int>((static_cast<long>(n) * (tid + 1)) / nthreads);
    try {
      fn(from, to, tid);
    } catch (...) {
#pragma omp critical(nospd_run_ranges)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
#else
  (void) nthreads;
  fn(0, n, 0);
#endif
}

// the number of ranges run_ranges will use
inline int range_count(int nthreads, int n)
{
#if defined(_OPENMP)
  return (nthreads < 2 || n < 2 * nthreads) ? 1 : nthreads;
#else
  (void) nthreads;
  (void) n;
  return 1;
#endif
}

}    // namespace NOSPD

#endif
