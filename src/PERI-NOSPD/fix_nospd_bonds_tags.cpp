/* ----------------------------------------------------------------------
   PERI-NOSPD: the bonds fix's partners through changes of atom IDs: IDs
   renumbered (delete_atoms compress), atoms created or deleted.
------------------------------------------------------------------------- */

#include "fix_nospd_bonds.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "modify.h"
#include "output.h"
#include "thermo.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   Atom IDs renumbered since the families were stored (delete_atoms with
   its default `compress yes`), or atoms created since: partner lists hold
   the old IDs.  Every old atom's (old, new) pair goes round the ranks
   once; each rank translates the partners it holds.  A partner whose old
   ID no old atom carries any more was deleted: its bond is broken
   (resolve_missing would not see it, since its old ID may now belong to
   another atom, a new one included).
------------------------------------------------------------------------- */

namespace {
struct Renumbering {
  std::vector<std::pair<tagint, std::pair<int, int>>> slots;    // old partner ID, (i, slot)
  std::vector<tagint> newtag;                                   // per entry of slots, 0: not found
};

void translate_ids(int n, char *buf, void *ptr)
{
  auto *r = static_cast<Renumbering *>(ptr);
  const auto *pairs = reinterpret_cast<const tagint *>(buf);    // old, new; sorted by old
  size_t k = 0;
  for (int p = 0; p < n && k < r->slots.size(); p++) {
    const tagint old = pairs[2 * p];
    while (k < r->slots.size() && r->slots[k].first < old) k++;
    for (; k < r->slots.size() && r->slots[k].first == old; k++) r->newtag[k] = pairs[2 * p + 1];
  }
}
}    // namespace

void FixNospdBonds::follow_renumbered_tags()
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int flags[2] = {0, 0}, anyflags[2] = {0, 0};    // renumbered, created
  for (int i = 0; i < nlocal; i++) {
    if (own_tag[i] == 0)
      flags[1] = 1;    // created after the families: in no family
    else if (own_tag[i] != tag[i])
      flags[0] = 1;
  }
  MPI_Allreduce(flags, anyflags, 2, MPI_INT, MPI_MAX, world);
  const bool renumbered = anyflags[0], created = anyflags[1];
  if (!renumbered && !created) return;

  Renumbering r;
  for (int i = 0; i < nlocal; i++)
    for (int n = 0; n < npartner[i]; n++)
      if (partner[i][n]) r.slots.push_back({partner[i][n], {i, n}});
  std::sort(r.slots.begin(), r.slots.end());
  r.newtag.assign(r.slots.size(), 0);
  // only atoms that were there when the partner IDs were written: a new
  // atom may carry the ID of a deleted one (LAMMPS hands out the largest ID
  // left plus one, and delete_atoms compress yes frees IDs), and must not
  // inherit its bonds
  std::vector<std::pair<tagint, tagint>> ids;
  ids.reserve(nlocal + 1);
  for (int i = 0; i < nlocal; i++)
    if (own_tag[i]) ids.push_back({own_tag[i], tag[i]});
  std::sort(ids.begin(), ids.end());
  static_assert(sizeof(std::pair<tagint, tagint>) == 2 * sizeof(tagint), "packed ID pairs");
  comm->ring((int) ids.size(), 2 * sizeof(tagint), ids.data(), 0, translate_ids, nullptr, &r);

  int ngone = 0;
  for (size_t k = 0; k < r.slots.size(); k++) {
    const int i = r.slots[k].second.first, n = r.slots[k].second.second;
    partner[i][n] = r.newtag[k];    // 0 (broken) if the partner is gone
    if (!r.newtag[k]) {
      stale[i] = 1;
      ngone++;
    }
  }
  for (int i = 0; i < nlocal; i++) own_tag[i] = tag[i];
  bigint one = ngone, all = 0;
  MPI_Allreduce(&one, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  nbonds_vanished += all;
  if (comm->me == 0) {
    if (renumbered)
      error->warning(FLERR, "Fix {}: atom IDs were renumbered since the bond families were "
                     "built (delete_atoms compress yes): the families follow the new IDs", style);
  }
  if (all) warn_vanished(all);
}

void FixNospdBonds::warn_vanished(bigint nbroken)
{
  count_bonds_pending = true;
  if (comm->me == 0)
    error->warning(FLERR, "Fix {}: {} bonds broken: their partner atoms no longer exist "
                   "(delete_atoms, fix evaporate, or atoms lost under thermo_modify lost "
                   "ignore)", style, nbroken);
}

/* ----------------------------------------------------------------------
   Partners found neither as owned atoms nor as ghosts.  Either they no
   longer exist (delete_atoms, atoms lost through a non-periodic boundary
   under thermo_modify lost ignore): their bonds are broken, alike on every
   rank count, and the families' K recomputed; or they exist on a rank
   beyond the ghost cutoff: an error with the distance.  All ranks take
   part, since which is which takes a global look-up of the tags.
------------------------------------------------------------------------- */

void FixNospdBonds::resolve_missing(const std::vector<MissingPartner> &missing,
                                    std::vector<FarBond> &far)
{
  // the missing tags of all ranks, with the owner's position where one exists
  std::vector<tagint> mine;
  for (const auto &m : missing) mine.push_back(m.tag);
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  int nmine = mine.size();
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&nmine, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  const int nall = displs.back() + counts.back();
  std::vector<tagint> tags(nall);
  MPI_Allgatherv(mine.data(), nmine, MPI_LMP_TAGINT, tags.data(), counts.data(), displs.data(),
                 MPI_LMP_TAGINT, world);
  std::vector<double> found(4 * nall, 0.0), found_all(4 * nall);
  for (int k = 0; k < nall; k++) {
    const int j = partner_index(tags[k]);
    if (j < 0 || j >= atom->nlocal) continue;
    found[4 * k] = 1.0;
    for (int d = 0; d < 3; d++) found[4 * k + 1 + d] = atom->x[j][d];
  }
  MPI_Allreduce(found.data(), found_all.data(), 4 * nall, MPI_DOUBLE, MPI_SUM, world);
  // tags is the concatenation of sorted per-rank lists: look up within this rank's part
  const auto first_mine = tags.begin() + displs[comm->me];
  const auto last_mine = first_mine + nmine;

  int nvanished = 0;
  for (const auto &m : missing) {
    const int k = std::lower_bound(first_mine, last_mine, m.tag) - tags.begin();
    if (found_all[4 * k] == 0.0) {
      partner[m.i][m.slot] = 0;    // the partner is gone: so is the bond
      stale[m.i] = 1;
      nvanished++;
    } else {
      double d[3];
      for (int c = 0; c < 3; c++) d[c] = found_all[4 * k + 1 + c] - atom->x[m.i][c];
      domain->minimum_image(FLERR, d);
      far.push_back({m.i, m.slot, m.tag, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])});
    }
  }

  // atoms lost (LAMMPS still counts them) rather than deleted: unless the
  // user lets atoms go (thermo_modify lost ignore|warn), LAMMPS stops at the
  // next thermo output; stop now and say why
  bigint nlocal = atom->nlocal, natoms_now = 0;
  MPI_Allreduce(&nlocal, &natoms_now, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (natoms_now < atom->natoms && output->thermo && output->thermo->lostflag == Thermo::ERROR) {
    const std::string hint = (update->whichflag == 2)
        ? ": under minimize the line search moved them up to min_modify dmax (and a fix "
          "box/relax the box by up to its vmax); set them to a fraction of the point spacing "
          "(and of the strain)"
        : ": a blown-up run or a body leaving a non-periodic box; to let atoms go, use "
          "thermo_modify lost ignore";
    error->all(FLERR, "Fix {}: {} atoms were lost, and bond partners with them{}", style,
               atom->natoms - natoms_now, hint);
  }
  bigint one = nvanished, all = 0;
  MPI_Allreduce(&one, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  nbonds_vanished += all;
  warn_vanished(all);
}

/* ----------------------------------------------------------------------
   Bonds longer than the ghost cutoff: on one rank their partners are at
   hand, on several they may not be, so they go the same way on any rank
   count.  With a damage fix they break (a bond stretched that far has
   failed, whatever the criterion: Johnson-Cook or eqps failure do not look
   at stretch); without one they are an error.
------------------------------------------------------------------------- */

void FixNospdBonds::settle_far_bonds(const std::vector<FarBond> &far)
{
  int nfar = far.size(), anyfar = 0;
  MPI_Allreduce(&nfar, &anyfar, 1, MPI_INT, MPI_SUM, world);
  if (!anyfar) return;
  if (modify->get_fix_by_style("^nospd/damage").empty()) {
    // a line-search minimizer moves atoms by up to min_modify dmax (0.1
    // distance units by default: 10 cm in SI) in its first trial step
    const std::string hint = (update->whichflag == 2)
        ? "; under minimize, set min_modify dmax to a fraction of the point spacing"
        : "";
    if (nfar)
      error->one(FLERR,
                 "Fix {}: bond partner {} of atom {} is {:.6g} away, beyond the ghost cutoff "
                 "{:.6g} ({} such bonds on this rank): a bond stretched beyond it; increase "
                 "it with comm_modify cutoff or break such bonds with a damage fix{}",
                 style, far[0].tag, atom->tag[far[0].i], far[0].length, comm->get_comm_cutoff(),
                 nfar, hint);
    error->all(FLERR, "Fix {}: bond partners beyond the ghost cutoff on another rank", style);
  }
  for (const auto &f : far) {
    partner[f.i][f.slot] = 0;
    stale[f.i] = 1;
  }
  count_bonds_pending = true;
  far_broken += anyfar / 2;
  if (comm->me == 0 && !far_warned)
    error->warning(FLERR, "Fix {}: {} bond ends stretched beyond the ghost cutoff {:.4g} broke "
                   "(with a damage fix such bonds break on any rank count; reported once)",
                   style, anyfar, comm->get_comm_cutoff());
  far_warned = true;
}
