/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Materials the user brings: a strain-energy formula (strain formula,
   nospd_formula.h) or an Abaqus UMAT library (strain umat, nospd_umat.h).
   Parses their pair_coeff/material-file keywords, builds the laws at
   init, keeps the libraries open, and writes the definitions to restarts.
   The pair styles ask it for a type's law; it holds no per-atom data.
------------------------------------------------------------------------- */

#ifndef LMP_NOSPD_USER_MATERIAL_H
#define LMP_NOSPD_USER_MATERIAL_H

#include "pointers.h"

#include "nospd_constitutive.h"
#include "nospd_umat.h"

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace NOSPD {
class FormulaLaw;
}

namespace LAMMPS_NS {

class NospdUserMaterials : protected Pointers {
 public:
  struct Spec {
    std::string energy;                                   // W formula
    std::vector<std::pair<std::string, double>> params;   // its named constants
    std::string library, symbol;                          // UMAT shared object and entry
    std::vector<double> props;                            // UMAT PROPS
    int nstatev = 0;                                      // UMAT NSTATV
    std::vector<std::string> listed;    // param names of the keyword list being read
    bool any() const { return !energy.empty() || !library.empty(); }
  };

  explicit NospdUserMaterials(LAMMPS *);
  ~NospdUserMaterials() override;

  void resize(int ntypes);
  Spec &spec(int itype) { return specs[itype]; }

  // Consume the keyword at words[k] if it is one of ours (energy, param,
  // umat, symbol, props, statev), advancing k; false if it is not.  A
  // list's params replace those of an earlier list (a material file
  // entry's); clear s.listed before each list.
  bool parse(const std::vector<std::string> &words, size_t &k, Spec &s,
             const std::string &where) const;

  // Build each active type's law for this run and check it against the
  // pair style's strain law and the type's E and nu.
  void setup(NOSPD::Law law, NOSPD::Plane plane, const int *active, std::vector<NOSPD::Lame> &lame,
             const double *youngs, const double *poisson,
             const std::vector<std::string> &names);

  bool is_umat(int itype) const { return umat_open[itype] != 0; }
  int history_size() const;    // values per atom the UMAT types need (0: none)
  const NOSPD::UmatMaterial &umat(int itype) const { return umats[itype]; }
  const std::string &library(int itype) const { return specs[itype].library; }
  std::string symbol(int itype) const
  {
    return specs[itype].symbol.empty() ? "umat_" : specs[itype].symbol;
  }

  void write_restart(FILE *fp) const;
  void read_restart(FILE *fp);

 private:
  std::vector<Spec> specs;
  // the definitions a restart file brought, held against the first run's
  // (a UMAT's state variables are only meaningful to the UMAT that wrote them)
  std::vector<Spec> restored;
  std::vector<std::unique_ptr<NOSPD::FormulaLaw>> formulas;
  std::vector<NOSPD::UmatMaterial> umats;
  std::vector<int> umat_open;
  std::map<std::string, void *> handles;    // library path -> dlopen handle

  void setup_formula(int itype, NOSPD::Plane plane, NOSPD::Lame &lame, double E, double nu);
  void setup_umat(int itype, NOSPD::Law law, NOSPD::Plane plane, const std::string &name);
  void check_restored(int itype);
  void *open_library(int itype, std::string &path);
};

}    // namespace LAMMPS_NS

#endif
