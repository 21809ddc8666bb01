/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The history store of the bonds fix: the inelastic laws' rows per atom,
   accepted and trial, each n_atom values of the atom and n_bond per
   partner slot; their layout, migration records, commit and sums.
------------------------------------------------------------------------- */

#ifndef LMP_NOSPD_HISTORY_STORE_H
#define LMP_NOSPD_HISTORY_STORE_H

#include "lmptype.h"

namespace LAMMPS_NS {

class Memory;

/* Owned by FixNospdBonds (its `hist`), which grows, copies and migrates
   the rows with its other per-atom arrays; the pair styles write the trial
   rows and read the accepted ones.  `accepted` holds the state of the last
   accepted step, `trial` what the latest force evaluation made of it; the
   trial rows become the accepted ones by commit() (the end of an MD step,
   the end of a minimization), so run 0, the setup of a run and line
   searches never accumulate plastic strain. */
class NospdHistoryStore {
 public:
  explicit NospdHistoryStore(Memory *memory) : memory(memory) {}
  ~NospdHistoryStore();
  NospdHistoryStore(const NospdHistoryStore &) = delete;
  NospdHistoryStore &operator=(const NospdHistoryStore &) = delete;

  int n = 0;         // values per atom, 0 if no type has history
  int n_atom = 0;    // of which the atom's own
  int n_bond = 0;    // and per partner slot
  int slots = 0;     // partner slots the rows hold
  double **accepted = nullptr;    // [nmax][n]
  double **trial = nullptr;       // [nmax][n]
  bool trial_ready = false;       // the trial rows hold a force evaluation

  // (re)lay the rows out for nmax atoms: values kept, new columns zero (the
  // virgin state); 0 and 0 frees them
  void layout(int na, int nb, int nslots, int nmax);
  void grow(int nmax);
  void copy(int i, int j);
  void clear(int i);
  // the n_bond values of partner slot `slot` in a row
  double *bond(double *row, int slot) const { return row + n_atom + n_bond * slot; }
  // atom i's record in transit: its values, then the entries of its intact
  // partner slots in slot order (partner[s] == 0: broken, dropped)
  int pack(int i, double *buf, int npartner, const tagint *partner) const;
  // the inverse, the partners arrived compacted; the record in its
  // writer's layout (na, nb)
  int unpack(int i, const double *buf, int na, int nb, int npartner);
  void commit();
  // the rows to report: the accepted ones, except during a minimization,
  // which accepts its trial rows only at its end
  double **current(bool minimizing) const { return (minimizing && trial_ready) ? trial : accepted; }
  double local_sum(int k, int nlocal, bool minimizing) const;
  double bytes(int nmax) const { return nmax * 2.0 * n * sizeof(double); }

 private:
  Memory *memory;
};

}    // namespace LAMMPS_NS

#endif
