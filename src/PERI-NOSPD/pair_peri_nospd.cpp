/* ----------------------------------------------------------------------
   PERI-NOSPD: correspondence peridynamics for LAMMPS.
   Classical correspondence pair style with zero-energy-mode control.
------------------------------------------------------------------------- */

#include "pair_peri_nospd.h"

#include "atom.h"
#include "citeme.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_nospd_bonds.h"
#include "force.h"
#include "lattice.h"
#include "memory.h"
#include "modify.h"
#include "potential_file_reader.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using NOSPD::Law;
using NOSPD::Mat3;
using NOSPD::Plane;
using NOSPD::Stab;

static const char cite_nospd[] =
    "pair peri/nospd: doi:10.1007/s10659-007-9125-1\n\n"
    "@Article{Silling07,\n"
    " author = {S. A. Silling and M. Epton and O. Weckner and J. Xu and E. Askari},\n"
    " title = {Peridynamic States and Constitutive Modeling},\n"
    " journal = {J.~Elasticity},\n"
    " year =    2007,\n"
    " volume =  88,\n"
    " pages =   {151--184}\n"
    "}\n\n";

static constexpr const char *BONDS_FIX_ID = "NOSPD_BONDS";
static constexpr double BIG = 1.0e300;

/* ---------------------------------------------------------------------- */

PairPeriNospd::PairPeriNospd(LAMMPS *lmp) :
    Pair(lmp), fix_bonds(nullptr), strain_law(Law::SMALL), plane_mode(Plane::NONE),
    stab(Stab::SILLING), stab_param(0.5), influence(NospdBondModel::CONSTANT), thickness(1.0),
    singular_tol(1.0e-4), youngs(nullptr), poisson(nullptr), g0(nullptr),
    stab_scalar(nullptr), cut(nullptr), nmax_work(0), bmat(nullptr), tmat(nullptr),
    moments(nullptr), stab_atom(nullptr), comm_tensors(1)
{
  if (lmp->citeme) lmp->citeme->add(cite_nospd);
  single_enable = 0;
  restartinfo = 1;
  one_coeff = 0;
  manybody_flag = 1;
  no_virial_fdotr_compute = 1;
  comm_forward = 9;
}

/* ---------------------------------------------------------------------- */

PairPeriNospd::~PairPeriNospd()
{
  if (fix_bonds && modify->get_fix_by_id(BONDS_FIX_ID)) modify->delete_fix(BONDS_FIX_ID);
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(stab_atom);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(cut);
    memory->destroy(youngs);
    memory->destroy(poisson);
    memory->destroy(g0);
    memory->destroy(stab_scalar);
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  memory->create(cutsq, n, n, "pair:cutsq");
  memory->create(cut, n, n, "pair:cut");
  memory->create(youngs, n, "pair:youngs");
  memory->create(poisson, n, "pair:poisson");
  memory->create(g0, n, "pair:g0");
  memory->create(stab_scalar, n, "pair:stab_scalar");
  for (int i = 0; i < n; i++) {
    youngs[i] = poisson[i] = g0[i] = stab_scalar[i] = 0.0;
    for (int j = 0; j < n; j++) {
      setflag[i][j] = 0;
      cut[i][j] = 0.0;
    }
  }
  lame.assign(n, NOSPD::Lame{0.0, 0.0, 0.0});
  material_name.assign(n, std::string());
}

/* ----------------------------------------------------------------------
   pair_style peri/nospd keyword value ...
------------------------------------------------------------------------- */

void PairPeriNospd::settings(int narg, char **arg)
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  int iarg = 0;
  bool plane_given = false;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    auto need = [&](int n) {
      if (iarg + n >= narg) error->all(FLERR, "{}: keyword {} needs {} value(s)", cmd, key, n);
    };
    if (key == "strain") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "small") strain_law = Law::SMALL;
      else if (v == "finite" || v == "corotational") strain_law = Law::COROTATIONAL;
      else if (v == "svk") strain_law = Law::SVK;
      else if (v == "neohookean") strain_law = Law::NEOHOOKE;
      else error->all(FLERR, "{}: unknown strain '{}' (small, finite, svk, neohookean)", cmd, v);
      iarg += 2;
    } else if (key == "stabilization") {
      need(1);
      const std::string v = arg[iarg + 1];
      iarg += 2;
      if (v == "none") stab = Stab::NONE;
      else if (v == "wan") stab = Stab::WAN;
      else if (v == "silling" || v == "hourglass") {
        if (iarg >= narg) error->all(FLERR, "{}: stabilization {} needs a value", cmd, v);
        stab = (v == "silling") ? Stab::SILLING : Stab::HOURGLASS;
        stab_param = utils::numeric(FLERR, arg[iarg], false, lmp);
        if (!(stab_param > 0.0))
          error->all(FLERR, "{}: stabilization {} value must be > 0, got {}", cmd, v, arg[iarg]);
        iarg++;
      } else
        error->all(FLERR, "{}: unknown stabilization '{}' (none, silling G, hourglass C, wan)",
                   cmd, v);
    } else if (key == "influence") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "constant") influence = NospdBondModel::CONSTANT;
      else if (v == "inverse") influence = NospdBondModel::INVERSE;
      else error->all(FLERR, "{}: unknown influence '{}' (constant, inverse)", cmd, v);
      iarg += 2;
    } else if (key == "plane") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "strain") plane_mode = Plane::STRAIN;
      else if (v == "stress") plane_mode = Plane::STRESS;
      else error->all(FLERR, "{}: unknown plane '{}' (strain, stress)", cmd, v);
      plane_given = true;
      iarg += 2;
    } else if (key == "thickness") {
      need(1);
      thickness = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(thickness > 0.0)) error->all(FLERR, "{}: thickness must be > 0, got {}", cmd, arg[iarg + 1]);
      iarg += 2;
    } else if (key == "singular_tol") {
      need(1);
      singular_tol = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(singular_tol > 0.0 && singular_tol < 1.0))
        error->all(FLERR, "{}: singular_tol must be in (0,1), got {}", cmd, arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "{}: unknown keyword '{}'", cmd, key);
  }
  if (domain->dimension == 3 && plane_given)
    error->all(FLERR, "{}: keyword plane applies to 2D only (dimension 2)", cmd);
  if (domain->dimension == 2 && !plane_given) plane_mode = Plane::STRAIN;
  if (domain->dimension == 3) plane_mode = Plane::NONE;
}

/* ----------------------------------------------------------------------
   pair_coeff I J E nu delta
   pair_coeff I J file name delta      (material from a potentials/ file)
   pair_coeff I J delta                (horizon of a cross pair only)
   A material belongs to a type: it applies to the types in both ranges.
------------------------------------------------------------------------- */

void PairPeriNospd::coeff(int narg, char **arg)
{
  const std::string cmd = std::string("pair_coeff (") + force->pair_style + ")";
  if (narg != 3 && narg != 5)
    error->all(FLERR, "{}: expected 'I J E nu delta', 'I J file name delta' or 'I J delta'", cmd);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  const double delta = utils::numeric(FLERR, arg[narg - 1], false, lmp);
  if (!(delta > 0.0)) error->all(FLERR, "{}: horizon delta must be > 0, got {}", cmd, arg[narg - 1]);

  bool has_material = (narg == 5);
  double E = 0.0, nu = 0.0, G0 = 0.0;
  std::string name;
  if (has_material) {
    if (utils::is_double(arg[2])) {
      E = utils::numeric(FLERR, arg[2], false, lmp);
      nu = utils::numeric(FLERR, arg[3], false, lmp);
      name = "inline";
    } else {
      name = arg[3];
      read_material_file(arg[2], name, E, nu, G0);
    }
    if (!(E > 0.0)) error->all(FLERR, "{}: Young's modulus E must be > 0, got {}", cmd, E);
    if (!(nu > -1.0 && nu < 0.5) && plane_mode != Plane::STRESS)
      error->all(FLERR, "{}: Poisson ratio nu must be in (-1, 0.5), got {}", cmd, nu);
    if (!(nu > -1.0 && nu < 1.0))
      error->all(FLERR, "{}: Poisson ratio nu must be in (-1, 1) in plane stress, got {}", cmd, nu);
    if (plane_mode == Plane::STRESS && strain_law != Law::SMALL && !(nu < 0.5))
      error->all(FLERR, "{}: finite-strain plane stress needs nu < 0.5, got {}", cmd, nu);
  }

  int count = 0, nmat = 0;
  for (int i = ilo; i <= ihi; i++) {
    if (has_material && i >= jlo && i <= jhi) {
      youngs[i] = E;
      poisson[i] = nu;
      g0[i] = G0;
      material_name[i] = name;
      nmat++;
    }
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      cut[i][j] = delta;
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "{}: no type pairs in '{} {}'", cmd, arg[0], arg[1]);
  if (has_material && nmat == 0)
    error->all(FLERR, "{}: a material belongs to one type: use 'I I' or '* *'; for the cross "
               "pair {} {} give only the horizon", cmd, arg[0], arg[1]);
  ensure_bonds_fix();
}

/* ----------------------------------------------------------------------
   The correspondence pair style of this run, alone or inside pair hybrid,
   under its name or its alias without "peri" (which keeps LAMMPS's own
   PERI_NEIGH fix, matching "peri", unambiguous beside peri/lps).
------------------------------------------------------------------------- */

PairPeriNospd *PairPeriNospd::find(Force *force)
{
  for (const char *name : {"^peri/nospd", "^nospd"})
    if (auto *p = dynamic_cast<PairPeriNospd *>(force->pair_match(name, 0))) return p;
  return nullptr;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::read_material_file(const std::string &file, const std::string &name,
                                       double &E, double &nu, double &G0)
{
  double vals[3] = {0.0, 0.0, 0.0};
  int found = 0;
  if (comm->me == 0) {
    PotentialFileReader reader(lmp, file, "peri/nospd material");
    char *line;
    while ((line = reader.next_line(5))) {
      try {
        ValueTokenizer v(line);
        if (v.next_string() != name) continue;
        vals[0] = v.next_double();    // E
        vals[1] = v.next_double();    // nu
        v.next_double();              // density: set with the `set` command
        vals[2] = v.next_double();    // G0
        found = 1;
        break;
      } catch (TokenizerException &e) {
        error->one(FLERR, "pair_coeff: bad line in material file {}: {}", file, e.what());
      }
    }
  }
  MPI_Bcast(&found, 1, MPI_INT, 0, world);
  if (!found)
    error->all(FLERR, "pair_coeff ({}): material '{}' not found in file {}", force->pair_style,
               name, file);
  MPI_Bcast(vals, 3, MPI_DOUBLE, 0, world);
  E = vals[0];
  nu = vals[1];
  G0 = vals[2];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::check_material(int itype) const
{
  if (!(youngs[itype] > 0.0))
    error->all(FLERR, "pair_coeff ({}): no material for atom type {}: give 'pair_coeff {} {} "
               "E nu delta' or a material file", force->pair_style, itype, itype, itype);
}

/* ---------------------------------------------------------------------- */

double PairPeriNospd::init_one(int i, int j)
{
  check_material(i);
  check_material(j);
  if (setflag[i][j] == 0) cut[i][j] = MAX(cut[i][i], cut[j][j]);
  cut[j][i] = cut[i][j];
  return cut[i][j];
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::init_style()
{
  const std::string cmd = std::string("pair_style ") + force->pair_style;
  if (!atom->peri_flag) error->all(FLERR, "{} requires atom_style peri", cmd);
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "{} requires an atom map: add 'atom_modify map array' before the box",
               cmd);
  const int dim = domain->dimension;
  if (dim == 2 && domain->zperiodic == 0)
    error->all(FLERR, "{}: 2D runs need a periodic z", cmd);

  // the types this style owns: under pair hybrid, only those given to it
  active.assign(atom->ntypes + 1, 0);
  for (int i = 1; i <= atom->ntypes; i++) active[i] = (setflag[i][i] && youngs[i] > 0.0);

  // volumes and densities: a zero one would make K or the mass vanish
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  double *vfrac = atom->vfrac, *rmass = atom->rmass;
  int bad = -1;
  double badval = 0.0;
  const char *what = "";
  for (int i = 0; i < nlocal && bad < 0; i++) {
    if (!active[type[i]]) continue;
    if (!(vfrac[i] > 0.0)) { bad = i; badval = vfrac[i]; what = "volume (vfrac)"; }
    else if (!(rmass[i] > 0.0)) { bad = i; badval = rmass[i]; what = "density (rmass)"; }
  }
  int anybad = (bad >= 0), allbad;
  MPI_Allreduce(&anybad, &allbad, 1, MPI_INT, MPI_MAX, world);
  if (allbad) {
    if (bad >= 0)
      error->one(FLERR, "{}: atom {} has {} = {}, must be > 0 (set it with the set command)",
                 cmd, atom->tag[bad], what, badval);
    error->all(FLERR, "{}: atoms with zero volume or density", cmd);
  }

  // the horizon must reach beyond the nearest points; estimate their
  // spacing from the smallest volume
  double vmin = BIG, vmin_all;
  for (int i = 0; i < nlocal; i++)
    if (active[type[i]]) vmin = MIN(vmin, vfrac[i]);
  MPI_Allreduce(&vmin, &vmin_all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (vmin_all < BIG) {
    const double spacing = (dim == 3) ? cbrt(vmin_all) : sqrt(vmin_all / thickness);
    for (int i = 1; i <= atom->ntypes; i++)
      if (active[i] && cut[i][i] < 0.999 * spacing)
        error->all(FLERR, "{}: horizon {} of type {} is smaller than the point spacing {:.6g} "
                   "(from the smallest volume{}): families would be empty",
                   cmd, cut[i][i], i, spacing, dim == 2 ? " and the thickness" : "");
  }
  if (domain->lattice && domain->lattice->style != 0)
    for (int i = 1; i <= atom->ntypes; i++)
      if (active[i] && cut[i][i] < domain->lattice->xlattice)
        error->all(FLERR, "{}: horizon {} of type {} is smaller than the lattice spacing {}", cmd,
                   cut[i][i], i, domain->lattice->xlattice);

  // per-type constants of the law and of the stabilization
  for (int i = 1; i <= atom->ntypes; i++) {
    stab_scalar[i] = 0.0;
    if (!active[i]) continue;
    lame[i] = NOSPD::Lame::from_young(youngs[i], poisson[i]);
    const double c = NOSPD::micromodulus(dim, plane_mode, youngs[i], poisson[i], cut[i][i],
                                         thickness);
    if (stab == Stab::SILLING) stab_scalar[i] = stab_param * c / cut[i][i];
    else if (stab == Stab::HOURGLASS) stab_scalar[i] = stab_param * c;
  }
  comm_tensors = (stab == Stab::WAN || stab == Stab::HOURGLASS) ? 2 : 1;
  comm_forward = 9 * comm_tensors + 1;

  ensure_bonds_fix();
  NospdBondModel model;
  model.horizon = cut;
  model.influence = influence;
  model.dim = dim;
  model.singular_tol = singular_tol;
  model.active = active.data();
  fix_bonds->set_model(model);
  // no neighbor list: the families are fixed and live in the fix; the
  // ghost cutoff follows from the pair cutoff (horizon) plus the skin
}

/* ----------------------------------------------------------------------
   The fix that owns families and state: created with the first pair_coeff
   (so that thermo_style can name f_NOSPD_BONDS) or at init after a
   restart, under one ID so that it gets its restart data back.
------------------------------------------------------------------------- */

void PairPeriNospd::ensure_bonds_fix()
{
  if (fix_bonds) return;
  auto *f = modify->get_fix_by_id(BONDS_FIX_ID);
  if (!f) f = modify->add_fix(fmt::format("{} all PERI_NEIGH/NOSPD", BONDS_FIX_ID));
  fix_bonds = dynamic_cast<FixNospdBonds *>(f);
  if (!fix_bonds)
    error->all(FLERR, "pair_style {}: fix {} exists but is not a PERI_NEIGH/NOSPD fix",
               force->pair_style, BONDS_FIX_ID);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::grow_work()
{
  if (atom->nmax <= nmax_work) return;
  nmax_work = atom->nmax;
  memory->destroy(bmat);
  memory->destroy(tmat);
  memory->destroy(moments);
  memory->destroy(stab_atom);
  memory->create(stab_atom, nmax_work, "pair:stab_atom");
  memory->create(bmat, nmax_work, 9, "pair:bmat");
  memory->create(tmat, nmax_work, 9, "pair:tmat");
  memory->create(moments, nmax_work, 6, "pair:moments");
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  grow_work();

  const bool linear_stab = (stab == Stab::SILLING || stab == Stab::WAN);
  fix_bonds->compute_deformation((eflag && linear_stab) ? moments : nullptr);
  constitutive_pass(eflag);
  comm->forward_comm(this);

  const bool virial = vflag_either;
  switch (stab) {
    case Stab::NONE:
      virial ? force_pass<0, 1>(eflag) : force_pass<0, 0>(eflag);
      break;
    case Stab::SILLING:
      virial ? force_pass<1, 1>(eflag) : force_pass<1, 0>(eflag);
      break;
    case Stab::HOURGLASS:
      virial ? force_pass<2, 1>(eflag) : force_pass<2, 0>(eflag);
      break;
    case Stab::WAN:
      virial ? force_pass<3, 1>(eflag) : force_pass<3, 0>(eflag);
      break;
  }
}

/* ----------------------------------------------------------------------
   per owned atom: P(F), W(F), and what pass 2 needs of it and its partners:
   B = P K^-1 - S H, plus S (Wan) or H (hourglass)
------------------------------------------------------------------------- */

void PairPeriNospd::constitutive_pass(int eflag)
{
  const int nlocal = atom->nlocal;
  const int *type = atom->type;
  const int *singular = fix_bonds->singular;
  double **defgrad = fix_bonds->defgrad;
  double **kinv = fix_bonds->kinv;
  double **pk1 = fix_bonds->pk1;
  double *wdens = fix_bonds->energy_density;

  for (int i = 0; i < nlocal; i++) {
    if (singular[i]) {
      // no force state of its own: no stress, no stabilization
      for (int k = 0; k < 9; k++) bmat[i][k] = tmat[i][k] = pk1[i][k] = 0.0;
      stab_atom[i] = 0.0;
      wdens[i] = 0.0;
      continue;
    }
    const int itype = type[i];
    stab_atom[i] = stab_scalar[itype];
    Mat3 F = NOSPD::load(defgrad[i]);
    const Mat3 H = F - Mat3::Identity();
    const Mat3 Ki = NOSPD::load(kinv[i]);
    Mat3 P;
    double W = 0.0;
    if (!NOSPD::first_piola(strain_law, plane_mode, lame[itype], F, P, W))
      error->one(FLERR, "pair_style {}: atom {} has det F = {:.6g}: the finite-strain law is "
                 "undefined for an inverted or collapsed family", force->pair_style,
                 atom->tag[i], F.determinant());
    NOSPD::store(F, defgrad[i]);
    NOSPD::store(P, pk1[i]);
    const Mat3 A = P * Ki;

    Mat3 B = A;
    if (stab == Stab::SILLING) {
      B -= stab_scalar[itype] * H;
    } else if (stab == Stab::WAN) {
      const Mat3 S = NOSPD::wan_tensor(lame[itype], domain->dimension, plane_mode, Ki);
      B -= S * H;
      NOSPD::store(S, tmat[i]);
    } else if (stab == Stab::HOURGLASS) {
      NOSPD::store(H, tmat[i]);
    }
    NOSPD::store(B, bmat[i]);

    if (eflag) {
      double e = W;
      if (stab == Stab::SILLING || stab == Stab::WAN) {
        // 1/2 sum_j w z.S z = 1/2 S : Z
        const Mat3 Z = nonaffine_moment(i, H, Ki);
        if (stab == Stab::SILLING) e += 0.5 * stab_scalar[itype] * Z.trace();
        else e += 0.5 * NOSPD::load(tmat[i]).cwiseProduct(Z).sum();
      }
      wdens[i] = e;
      tally_energy(i, e);
    }
  }
}

/* ----------------------------------------------------------------------
   Z = sum_j w z (x) z with z = U - H xi, from the moments of pass 1:
   Z = M_UU - H K H^T, since sum_j w U (x) xi = H K
------------------------------------------------------------------------- */

NOSPD::Mat3 PairPeriNospd::nonaffine_moment(int i, const Mat3 &H, const Mat3 &Ki) const
{
  const double *m = moments[i];
  Mat3 M;
  M << m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2];
  Mat3 K = Ki.inverse();
  if (domain->dimension == 2) K(2, 2) = 0.0;
  return M - H * K * H.transpose();
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::tally_energy(int i, double e)
{
  if (eflag_global) eng_vdwl += e;
  if (eflag_atom) eatom[i] += e;
}

/* ----------------------------------------------------------------------
   pass 2: f_i = sum_j w ((B_i + B_j) xi + (S_i + S_j) U)  [+ hourglass]
   The i-terms factor out of the sum: B_i sum_j w xi + S_i sum_j w U, both
   moments kept by the bonds fix, so the inner loop touches only j's data.
   With a virial every bond's full pair force is needed, so the loop
   carries the i-terms too.
------------------------------------------------------------------------- */

template <int STAB, int VIRIAL> void PairPeriNospd::force_pass(int /*eflag*/)
{
  // flat views of the per-atom arrays: one load per value in the inner loop
  const double *_noalias const xf = atom->x[0];
  const double *_noalias const x0f = fix_bonds->x0s[0];
  const double *_noalias const bf = bmat[0];
  const double *_noalias const tf = tmat[0];
  const double *_noalias const sa = stab_atom;
  const int nlocal = atom->nlocal;
  const int *_noalias const bfirst = fix_bonds->bond_first;
  const int *_noalias const bj = fix_bonds->bond_j;
  const double *_noalias const bw = fix_bonds->bond_w;
  double **ximom = fix_bonds->xi_moment;
  double **umom = fix_bonds->u_moment;

  for (int i = 0; i < nlocal; i++) {
    const double *Bi = bf + 9 * i;
    const double *Ti = tf + 9 * i;
    const double si = sa[i];
    const double xi0 = x0f[3 * i], yi0 = x0f[3 * i + 1], zi0 = x0f[3 * i + 2];
    const double xc = xf[3 * i], yc = xf[3 * i + 1], zc = xf[3 * i + 2];
    double fx = 0.0, fy = 0.0, fz = 0.0;
    double v[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    Mat3 Hi;
    if (STAB == 2) Hi = NOSPD::load(Ti);

    const int bend = bfirst[i + 1];
    for (int b = bfirst[i]; b < bend; b++) {
      const int j = bj[b];
      const double w = bw[b];
      const double *X0j = x0f + 3 * j;
      const double *Xj = xf + 3 * j;
      const double ex = X0j[0] - xi0, ey = X0j[1] - yi0, ez = X0j[2] - zi0;
      const double yx = Xj[0] - xc, yy = Xj[1] - yc, yz = Xj[2] - zc;
      const double ux = yx - ex, uy = yy - ey, uz = yz - ez;
      const double *Bj = bf + 9 * j;
      double gx = Bj[0] * ex + Bj[1] * ey + Bj[2] * ez;
      double gy = Bj[3] * ex + Bj[4] * ey + Bj[5] * ez;
      double gz = Bj[6] * ex + Bj[7] * ey + Bj[8] * ez;
      if (VIRIAL) {
        gx += Bi[0] * ex + Bi[1] * ey + Bi[2] * ez;
        gy += Bi[3] * ex + Bi[4] * ey + Bi[5] * ez;
        gz += Bi[6] * ex + Bi[7] * ey + Bi[8] * ez;
      }
      if (STAB == 1) {
        const double s = VIRIAL ? si + sa[j] : sa[j];
        gx += s * ux;
        gy += s * uy;
        gz += s * uz;
      } else if (STAB == 3) {
        const double *Tj = tf + 9 * j;
        gx += Tj[0] * ux + Tj[1] * uy + Tj[2] * uz;
        gy += Tj[3] * ux + Tj[4] * uy + Tj[5] * uz;
        gz += Tj[6] * ux + Tj[7] * uy + Tj[8] * uz;
        if (VIRIAL) {
          gx += Ti[0] * ux + Ti[1] * uy + Ti[2] * uz;
          gy += Ti[3] * ux + Ti[4] * uy + Ti[5] * uz;
          gz += Ti[6] * ux + Ti[7] * uy + Ti[8] * uz;
        }
      } else if (STAB == 2) {
        // hourglass: (c_i z_i + c_j z_j).Y / (|Y|^2 |xi|) Y, z = U - H xi
        const double *Hj = tf + 9 * j;
        const double hix = Hi(0, 0) * ex + Hi(0, 1) * ey + Hi(0, 2) * ez;
        const double hiy = Hi(1, 0) * ex + Hi(1, 1) * ey + Hi(1, 2) * ez;
        const double hiz = Hi(2, 0) * ex + Hi(2, 1) * ey + Hi(2, 2) * ez;
        const double hjx = Hj[0] * ex + Hj[1] * ey + Hj[2] * ez;
        const double hjy = Hj[3] * ex + Hj[4] * ey + Hj[5] * ez;
        const double hjz = Hj[6] * ex + Hj[7] * ey + Hj[8] * ez;
        const double sj = sa[j];
        const double zx = si * (ux - hix) + sj * (ux - hjx);
        const double zy = si * (uy - hiy) + sj * (uy - hjy);
        const double zz = si * (uz - hiz) + sj * (uz - hjz);
        const double ry2 = yx * yx + yy * yy + yz * yz;
        if (ry2 > 0.0) {
          const double c = (zx * yx + zy * yy + zz * yz) / (ry2 * sqrt(ex * ex + ey * ey + ez * ez));
          gx += c * yx;
          gy += c * yy;
          gz += c * yz;
        }
      }
      fx += w * gx;
      fy += w * gy;
      fz += w * gz;
      if (VIRIAL) {
        // 1/2 r (x) F with r = x_i - x_j = -Y and F = w g, the force on i
        const double hx = -0.5 * w * yx, hy = -0.5 * w * yy, hz = -0.5 * w * yz;
        v[0] += hx * gx;
        v[1] += hy * gy;
        v[2] += hz * gz;
        v[3] += hx * gy;
        v[4] += hx * gz;
        v[5] += hy * gz;
      }
    }

    if (!VIRIAL) {
      const double *m = ximom[i];
      fx += Bi[0] * m[0] + Bi[1] * m[1] + Bi[2] * m[2];
      fy += Bi[3] * m[0] + Bi[4] * m[1] + Bi[5] * m[2];
      fz += Bi[6] * m[0] + Bi[7] * m[1] + Bi[8] * m[2];
      const double *u = umom[i];
      if (STAB == 1) {
        fx += si * u[0];
        fy += si * u[1];
        fz += si * u[2];
      } else if (STAB == 3) {
        fx += Ti[0] * u[0] + Ti[1] * u[1] + Ti[2] * u[2];
        fy += Ti[3] * u[0] + Ti[4] * u[1] + Ti[5] * u[2];
        fz += Ti[6] * u[0] + Ti[7] * u[1] + Ti[8] * u[2];
      }
    }
    add_force_virial(i, fx, fy, fz, v, VIRIAL);
  }
}

/* ---------------------------------------------------------------------- */

int PairPeriNospd::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                     int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int i = list[ii];
    for (int k = 0; k < 9; k++) buf[m++] = bmat[i][k];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) buf[m++] = tmat[i][k];
    buf[m++] = stab_atom[i];
  }
  return m;
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  const int last = first + n;
  for (int i = first; i < last; i++) {
    for (int k = 0; k < 9; k++) bmat[i][k] = buf[m++];
    if (comm_tensors == 2)
      for (int k = 0; k < 9; k++) tmat[i][k] = buf[m++];
    stab_atom[i] = buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    fwrite(&youngs[i], sizeof(double), 1, fp);
    fwrite(&poisson[i], sizeof(double), 1, fp);
    fwrite(&g0[i], sizeof(double), 1, fp);
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&cut[i][j], sizeof(double), 1, fp);
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    if (me == 0) {
      utils::sfread(FLERR, &youngs[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &poisson[i], sizeof(double), 1, fp, nullptr, error);
      utils::sfread(FLERR, &g0[i], sizeof(double), 1, fp, nullptr, error);
    }
    MPI_Bcast(&youngs[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&poisson[i], 1, MPI_DOUBLE, 0, world);
    MPI_Bcast(&g0[i], 1, MPI_DOUBLE, 0, world);
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) utils::sfread(FLERR, &cut[i][j], sizeof(double), 1, fp, nullptr, error);
        MPI_Bcast(&cut[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::write_restart_settings(FILE *fp)
{
  int iv[4] = {static_cast<int>(strain_law), static_cast<int>(plane_mode),
               static_cast<int>(stab), influence};
  double dv[3] = {stab_param, thickness, singular_tol};
  fwrite(iv, sizeof(int), 4, fp);
  fwrite(dv, sizeof(double), 3, fp);
}

/* ---------------------------------------------------------------------- */

void PairPeriNospd::read_restart_settings(FILE *fp)
{
  int iv[4];
  double dv[3];
  if (comm->me == 0) {
    utils::sfread(FLERR, iv, sizeof(int), 4, fp, nullptr, error);
    utils::sfread(FLERR, dv, sizeof(double), 3, fp, nullptr, error);
  }
  MPI_Bcast(iv, 4, MPI_INT, 0, world);
  MPI_Bcast(dv, 3, MPI_DOUBLE, 0, world);
  strain_law = static_cast<Law>(iv[0]);
  plane_mode = static_cast<Plane>(iv[1]);
  stab = static_cast<Stab>(iv[2]);
  influence = iv[3];
  stab_param = dv[0];
  thickness = dv[1];
  singular_tol = dv[2];
}

/* ---------------------------------------------------------------------- */

double PairPeriNospd::memory_usage()
{
  return (double) nmax_work * (9 + 9 + 6 + 1) * sizeof(double);
}

/* ---------------------------------------------------------------------- */

void *PairPeriNospd::extract(const char *name, int &dim)
{
  dim = 2;
  if (strcmp(name, "delta") == 0 || strcmp(name, "cut") == 0) return (void *) cut;
  return nullptr;
}

// the Silling and hourglass passes are also run by the bond-associated style
template void LAMMPS_NS::PairPeriNospd::force_pass<1, 0>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<1, 1>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<2, 0>(int);
template void LAMMPS_NS::PairPeriNospd::force_pass<2, 1>(int);
