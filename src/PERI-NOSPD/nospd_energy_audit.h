/* -*- c++ -*- ----------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   The energy balance of a breaking material, whatever loads it.  Knows
   nothing of LAMMPS.

   The material's own forces f_i (force densities, the pair style's and
   the contact's) do the work W = -sum_i V_i f_i . dx_i on it (trapezoidal
   over each step; external loads, indenters, thermostats do not enter).
   It stores E (the elastic and stabilization energies, sum V_i W_i, and
   the contact energy) and dissipates D (the plastic work, sum V_i w_p,i);
   what is left is the energy the broken bonds took away,
       released = (W - W0) - (E - E0) - (D - D0),
   which may only grow: a break releases the energy its bond held.  A fall
   of `released` below its running maximum is energy the material created
   (the measure bench/scenes/energy_balance.py takes from a log).  The
   time integration's error makes `released` wander where nothing breaks,
   by a fraction of the energy in motion (kinetic and stored): `floor` in
   creates() sets that noise apart.
------------------------------------------------------------------------- */

#ifndef NOSPD_ENERGY_AUDIT_H
#define NOSPD_ENERGY_AUDIT_H

#include <algorithm>
#include <cmath>

namespace NOSPD {

class EnergyAudit {
 public:
  // a new run: the first observe() sets the reference state
  void restart() { *this = EnergyAudit(); }

  // at a step whose energies are known: the work done on the material
  // since the run started (W), its stored energy E, its dissipation D and
  // its kinetic energy K (the scale of the integration's wander only)
  void observe(double W, double E, double D, double K = 0.0)
  {
    if (!started) {
      W0 = W;
      E0 = E;
      D0 = D;
      started = true;
    }
    rel = (W - W0) - (E - E0) - (D - D0);
    top = std::max(top, rel);
    made = std::max(made, top - rel);
    dis = (D - D0) + rel;
    scale = std::max({scale, std::abs(W - W0), std::abs(E - E0), std::abs(E) + std::abs(K)});
  }

  bool observed() const { return started; }
  double released() const { return rel; }
  double created() const { return made; }          // the largest fall of released
  double dissipated() const { return dis; }        // D - D0 + released, now
  double work_scale() const { return scale; }      // the largest |W - W0|, |E - E0|, |E| + |K|

  // energy created beyond `fraction` of the energy dissipated (or with
  // none dissipated) and above `floor` times the largest energy moved
  bool creates(double fraction, double floor) const
  {
    if (!started || !(made > floor * scale)) return false;
    return !(dis > 0.0) || made > fraction * dis;
  }

 private:
  bool started = false;
  double W0 = 0.0, E0 = 0.0, D0 = 0.0;
  double rel = 0.0, top = 0.0, made = 0.0, dis = 0.0, scale = 0.0;
};

}    // namespace NOSPD

#endif
