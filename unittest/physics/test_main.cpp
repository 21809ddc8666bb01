// GoogleTest main for tests that run LAMMPS: MPI must be up first.
#include "gtest/gtest.h"
#include <cstdlib>
#include <mpi.h>

int main(int argc, char **argv)
{
  // where the plugin and the material files are, unless the caller says
  setenv("LAMMPS_PLUGIN_PATH", NOSPD_PLUGIN_DIR, 0);
  setenv("LAMMPS_POTENTIALS", NOSPD_POTENTIALS_DIR, 0);
  setenv("OMP_NUM_THREADS", "1", 0);
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  MPI_Finalize();
  return rc;
}
