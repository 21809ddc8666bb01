/* Shared helpers for the physics tests: a LAMMPS instance with the
   PERI-NOSPD plugin (auto-loaded through LAMMPS_PLUGIN_PATH), decks of
   regular blocks, and access to per-atom data by atom ID. */
#ifndef NOSPD_TEST_UTIL_H
#define NOSPD_TEST_UTIL_H

#include "atom.h"
#include "compute.h"
#include "exceptions.h"
#include "fix.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "input.h"
#include "lammps.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

#include "gtest/gtest.h"
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace nospdtest {

using LAMMPS_NS::LAMMPS;

inline LAMMPS *open_lammps()
{
  const char *args[] = {"nospdtest", "-log", "none", "-echo", "none", "-screen", "none",
                        "-nocite"};
  return new LAMMPS(8, (char **) args, MPI_COMM_WORLD);
}

inline void cmd(LAMMPS *lmp, const std::string &line) { lmp->input->one(line); }

// Run a command and return the LAMMPS error text it raised ("" if none).
inline std::string error_of(LAMMPS *lmp, const std::string &line)
{
  try {
    lmp->input->one(line);
  } catch (LAMMPS_NS::LAMMPSAbortException &e) {
    return e.what();
  } catch (LAMMPS_NS::LAMMPSException &e) {
    return e.what();
  }
  return "";
}

inline std::string num(double v)
{
  char buf[64];
  snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

struct Block {
  int dim = 3;
  int n = 13;              // points per side
  double dx = 1.0e-3;      // spacing (m)
  double mfactor = 3.01;   // horizon / dx
  bool periodic = false;
  std::string style = "peri/nospd";
  std::string settings;    // pair_style keywords
  double E = 200e9, nu = 0.3;
  double delta() const { return mfactor * dx; }
};

// A simple-cubic (3D) or square (2D) block of n^dim points, SI units.
inline void make_block(LAMMPS *lmp, const Block &b)
{
  const std::string bc = b.periodic ? "p p p" : (b.dim == 2 ? "s s p" : "s s s");
  cmd(lmp, "units si");
  cmd(lmp, "dimension " + std::to_string(b.dim));
  cmd(lmp, "boundary " + bc);
  cmd(lmp, "atom_style peri");
  cmd(lmp, "atom_modify map array");
  cmd(lmp, "lattice " + std::string(b.dim == 2 ? "sq " : "sc ") + num(b.dx));
  const std::string zr = b.dim == 2 ? " -0.5 0.5" : " 0 " + std::to_string(b.n);
  if (b.periodic)
    cmd(lmp, "region box block 0 " + std::to_string(b.n) + " 0 " + std::to_string(b.n) +
                 (b.dim == 2 ? " -0.5 0.5" : " 0 " + std::to_string(b.n)));
  else
    cmd(lmp, "region box block -0.25 " + std::to_string(b.n - 0.75) + " -0.25 " +
                 std::to_string(b.n - 0.75) + zr);
  cmd(lmp, "create_box 2 box");
  cmd(lmp, "create_atoms 1 box");
  cmd(lmp, "set group all density 7850");
  const double vol = b.dim == 2 ? b.dx * b.dx * 1.0 : b.dx * b.dx * b.dx;
  cmd(lmp, "set group all volume " + num(vol));
  cmd(lmp, "neighbor " + num(0.5 * b.dx) + " bin");
  cmd(lmp, "comm_modify cutoff " + num(b.delta() * 2.2));
  cmd(lmp, "pair_style " + b.style + " " + b.settings);
  char buf[256];
  snprintf(buf, sizeof(buf), "pair_coeff * * %.17g %.17g %.17g", b.E, b.nu, b.delta());
  cmd(lmp, buf);
  cmd(lmp, "timestep 1e-9");
  cmd(lmp, "thermo_modify norm no");
}

// What LAMMPS writes while it runs `lines`, through a log file in the build
// folder (removed after).
inline std::string log_of(LAMMPS *lmp, const std::vector<std::string> &lines)
{
  // one file per process and call: ctest -j runs several test binaries in
  // the same folder at once, and a shared name let one remove another's log
  static int calls = 0;
  const std::string log =
      "nospd_test_log_of." + std::to_string(getpid()) + "." + std::to_string(calls++) + ".log";
  cmd(lmp, "log " + log);
  for (const auto &line : lines) cmd(lmp, line);
  cmd(lmp, "log none");
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::remove(log.c_str());
  return text;
}

// Per-atom vectors by atom ID - 1 (serial tests: every atom is local).
inline std::vector<std::array<double, 3>> by_tag(LAMMPS *lmp, double **v)
{
  const int n = lmp->atom->natoms;
  std::vector<std::array<double, 3>> out(n);
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const int t = lmp->atom->tag[i] - 1;
    out[t] = {v[i][0], v[i][1], v[i][2]};
  }
  return out;
}

// Two by_tag vectors agree to rel times the largest component of a (which
// must not vanish: a test of zero forces proves nothing).
inline void expect_same_vectors(const std::vector<std::array<double, 3>> &a,
                                const std::vector<std::array<double, 3>> &b, double rel)
{
  ASSERT_EQ(a.size(), b.size());
  double amax = 0.0, diff = 0.0;
  for (size_t i = 0; i < a.size(); i++)
    for (int k = 0; k < 3; k++) {
      amax = std::max(amax, std::abs(a[i][k]));
      diff = std::max(diff, std::abs(a[i][k] - b[i][k]));
    }
  EXPECT_GT(amax, 0.0);
  EXPECT_LE(diff, rel * amax);
}

inline double potential_energy(LAMMPS *lmp)
{
  auto *pe = lmp->modify->get_compute_by_id("thermo_pe");
  return pe->compute_scalar();
}

// Energy consistency: random displacements of 0.4 % of the spacing from
// x0, then -dE/dy by central differences against the force at the probed
// atoms (atom ID - 1).  Serial decks; the pair energy is eng_vdwl.
inline void expect_force_is_energy_gradient(LAMMPS *lmp, const Block &blk,
                                            const std::vector<int> &probes)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-0.004 * blk.dx, 0.004 * blk.dx);
  double **x = lmp->atom->x, **x0 = lmp->atom->x0;
  for (int i = 0; i < lmp->atom->nlocal; i++) {
    const double d[3] = {U(rng), U(rng), blk.dim == 3 ? U(rng) : 0.0};
    for (int k = 0; k < blk.dim; k++) x[i][k] = x0[i][k] + d[k];
  }
  cmd(lmp, "run 0");
  const auto f0 = by_tag(lmp, lmp->atom->f);
  double fmax = 0.0;
  for (auto &v : f0)
    for (double c : v) fmax = std::max(fmax, std::abs(c));
  const double h = 1e-5 * blk.dx;
  for (int probe : probes) {
    const int i = lmp->atom->map(probe + 1);
    for (int k = 0; k < blk.dim; k++) {
      const double keep = x[i][k];
      x[i][k] = keep + h;
      cmd(lmp, "run 0");
      const double ep = lmp->force->pair->eng_vdwl;
      x[i][k] = keep - h;
      cmd(lmp, "run 0");
      const double em = lmp->force->pair->eng_vdwl;
      x[i][k] = keep;
      const double fd = -(ep - em) / (2.0 * h);
      EXPECT_NEAR(fd, f0[probe][k], 2e-6 * fmax) << "atom " << probe + 1 << " dir " << k;
    }
  }
}

// Break a fraction of the bonds at random, on both ends, straight in the
// bonds fix's partner lists (serial decks; the next run rebuilds K, F).
inline int break_random_bonds(LAMMPS *lmp, double fraction, unsigned seed)
{
  auto *fb = static_cast<LAMMPS_NS::FixNospdBonds *>(lmp->modify->get_fix_by_id("NOSPD_BONDS"));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int nbroken = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    for (int s = 0; s < fb->npartner[i]; s++) {
      const auto tj = fb->partner[i][s];
      if (tj == 0 || tj < lmp->atom->tag[i] || U(rng) > fraction) continue;
      fb->partner[i][s] = 0;
      const int j = lmp->atom->map(tj);
      for (int t = 0; t < fb->npartner[j]; t++)
        if (fb->partner[j][t] == lmp->atom->tag[i]) fb->partner[j][t] = 0;
      nbroken++;
    }
  return nbroken;
}

}    // namespace nospdtest

#endif
