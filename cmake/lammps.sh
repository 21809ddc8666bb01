#!/bin/bash
# Provision everything PERI-NOSPD needs on a Debian machine:
#   1. Debian packages (compiler, cmake, Open MPI, FFTW, Eigen, libyaml,
#      GoogleTest/GMock, libpng/libjpeg, matplotlib), installed when missing;
#   2. the LAMMPS source from Debian's `lammps` source package (pinned
#      upstream version), fetched with apt through a private configuration
#      derived from this machine's own apt sources;
#   3. a CMake build of LAMMPS with the packages we need, cached outside the
#      clone and keyed by version and options.
#
# Usage: cmake/lammps.sh [deps|source|build|all|print-dir|print-src]
# Prints nothing but the build directory on `print-dir`, the LAMMPS source
# tree on `print-src`.
# Environment:
#   PERI_NOSPD_CACHE   cache root (default: $HOME/.cache/peri-nospd)
#   LAMMPS_VERSION_PIN Debian upstream version to pin (default 20260704+dfsg)
set -euo pipefail

PIN="${LAMMPS_VERSION_PIN:-20260704+dfsg}"
CACHE="${PERI_NOSPD_CACHE:-${HOME:-/root}/.cache/peri-nospd}"
JOBS="${JOBS:-$(nproc)}"

# Packages are named here once; `deps` installs those that are missing.
#  build-essential cmake pkg-config        toolchain
#  libopenmpi-dev openmpi-bin              MPI (LAMMPS and plugin must share it)
#  libfftw3-dev                            KSPACE with FFT=FFTW3
#  libeigen3-dev                           3x3 algebra in the physics kernels
#  libyaml-dev libgtest-dev libgmock-dev   LAMMPS's unittest harness and ours
#  libpng-dev libjpeg-dev zlib1g-dev       dump image for example pictures
#  python3-matplotlib python3-numpy        charts and measurement scripts
#  python3-sphinx                          `make doc`
#  ca-certificates                         apt over https where configured
#  gfortran                                the test UMATs of `strain umat` are
#                                          Fortran, as users' UMATs are
DEB_PACKAGES=(build-essential gfortran cmake pkg-config libopenmpi-dev openmpi-bin
  libfftw3-dev libeigen3-dev libyaml-dev libgtest-dev libgmock-dev
  libpng-dev libjpeg-dev zlib1g-dev python3-matplotlib python3-numpy
  python3-sphinx ca-certificates)

# LAMMPS packages. PERI (atom_style peri, FixPeriNeigh, the styles we compare
# against), PLUGIN (to load us), OPENMP, KSPACE (requested build standard);
# RIGID (fix rigid projectiles in the coupling examples), GRANULAR
# (granular particles hitting a NOSPD body via pair hybrid/overlay),
# GRAPHICS (dump image: the PNG pictures of the fracture examples),
# LEPTON (the Lepton expression library with symbolic derivatives, linked
# into liblammps, which `strain formula` parses and differentiates W with).
LMP_PACKAGES=(PERI PLUGIN OPENMP KSPACE RIGID GRANULAR GRAPHICS LEPTON)

die() { echo "ERROR (cmake/lammps.sh): $*" >&2; exit 1; }
note() { echo "-- [peri-nospd] $*" >&2; }

options_key() {
  # Everything that changes the binary goes into the key.
  local s="$PIN ${LMP_PACKAGES[*]} mpi=openmpi fft=fftw3 shared=on png jpeg $(g++ -dumpfullversion 2>/dev/null || echo nogxx)"
  echo "$s" | md5sum | cut -c1-10
}

src_dir() { echo "$CACHE/lammps-$PIN/src-tree"; }
build_dir() { echo "$CACHE/lammps-$PIN/build-$(options_key)"; }

missing_packages() {
  local miss=()
  for p in "${DEB_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || miss+=("$p")
  done
  echo "${miss[@]:-}"
}

do_deps() {
  local miss
  miss="$(missing_packages)"
  if [ -z "$miss" ]; then note "Debian packages present"; return; fi
  note "installing Debian packages: $miss"
  local SUDO=""
  if [ "$(id -u)" != 0 ]; then
    command -v sudo >/dev/null && sudo -n true 2>/dev/null && SUDO="sudo -n" || \
      die "these Debian packages are missing and this user is not root: $miss
Run as root:  apt-get update && apt-get install -y $miss"
  fi
  $SUDO apt-get update -qq || die "apt-get update failed: no access to the Debian registry?
Missing packages: $miss"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $miss >/dev/null || \
    die "apt-get install failed for: $miss"
}

# A private apt configuration with deb-src entries for the suites that carry
# new LAMMPS, pointing at the same Debian mirror this machine already uses.
private_apt() {
  local d="$CACHE/apt"
  mkdir -p "$d/lists/partial" "$d/parts"
  local uri=""
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    uri=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources)
  fi
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    uri=$(awk '$1=="deb" && $0 !~ /security/ {for(i=2;i<=NF;i++) if ($i ~ /^(https?|file|ftp):/) {print $i; exit}}' /etc/apt/sources.list)
  fi
  [ -n "$uri" ] || die "could not find a Debian mirror URI in /etc/apt/sources.list{,.d}"
  local kr="/usr/share/keyrings/debian-archive-keyring.gpg"
  {
    for suite in sid forky trixie; do
      echo "deb-src [signed-by=$kr] $uri $suite main"
    done
  } > "$d/sources.list"
  # Check-Valid-Until off: a mirror that serves a frozen snapshot (as this
  # project's machines do) has Release files of the moving suites (sid,
  # forky) past their validity date; their signatures are still checked.
  APT_OPTS=(-o "Dir::Etc::SourceList=$d/sources.list" -o "Dir::Etc::SourceParts=$d/parts"
            -o "Dir::State::Lists=$d/lists" -o "Dir::Cache=$d/cache"
            -o "Acquire::Check-Valid-Until=false")
  mkdir -p "$d/cache/archives/partial"
  apt-get "${APT_OPTS[@]}" update -qq 2>/dev/null || \
    die "could not read Debian's source index from $uri (no network access to the registry?)"
}

do_source() {
  local s; s="$(src_dir)"
  if [ -f "$s/src/version.h" ]; then note "LAMMPS source present: $s"; return; fi
  private_apt
  local versions want
  versions=$(apt-cache "${APT_OPTS[@]}" showsrc lammps 2>/dev/null | awk '/^Version:/{print $2}' | sort -u)
  want=$(echo "$versions" | grep -F "$PIN-" | sort -V | tail -1 || true)
  if [ -z "$want" ]; then
    want=$(echo "$versions" | sort -V | tail -1)
    [ -n "$want" ] || die "apt offers no lammps source package"
    echo "WARNING: LAMMPS source $PIN is no longer offered by apt; using $want instead" >&2
  fi
  note "fetching Debian source lammps=$want"
  local dl="$CACHE/download"; mkdir -p "$dl"
  ( cd "$dl" && apt-get "${APT_OPTS[@]}" source --download-only --tar-only "lammps=$want" >/dev/null 2>&1 ) || \
    die "apt-get source lammps=$want failed"
  local tarball; tarball=$(ls "$dl"/lammps_*.orig.tar.* | head -1)
  rm -rf "$s.tmp"; mkdir -p "$s.tmp"
  tar xf "$tarball" -C "$s.tmp"
  # The orig tarball may or may not have a top-level directory.
  if [ ! -f "$s.tmp/src/version.h" ]; then
    local top; top=$(ls "$s.tmp" | head -1); mv "$s.tmp/$top" "$s.tmp.x"; rm -rf "$s.tmp"; mv "$s.tmp.x" "$s.tmp"
  fi
  mv "$s.tmp" "$s"
  rm -f "$tarball"
}

do_build() {
  local s b; s="$(src_dir)"; b="$(build_dir)"
  if [ -x "$b/lmp" ] && [ -f "$b/.complete" ]; then note "LAMMPS build present: $b"; return; fi
  local pk=()
  for p in "${LMP_PACKAGES[@]}"; do pk+=("-DPKG_$p=on"); done
  note "building LAMMPS in $b ($JOBS jobs; a few minutes on 2 cores)"
  mkdir -p "$b"
  cmake -S "$s/cmake" -B "$b" -DCMAKE_BUILD_TYPE=Release \
    -DBUILD_SHARED_LIBS=on -DBUILD_MPI=on -DBUILD_OMP=on -DLAMMPS_SIZES=smallbig \
    -DFFT=FFTW3 -DWITH_PNG=on -DWITH_JPEG=on -DWITH_GZIP=on -DWITH_FFMPEG=off \
    -DCMAKE_BUILD_RPATH_USE_ORIGIN=on -DCMAKE_INSTALL_RPATH='$ORIGIN' -DCMAKE_BUILD_WITH_INSTALL_RPATH=on \
    -DLAMMPS_EXCEPTIONS=on -DDOWNLOAD_POTENTIALS=off \
    "${pk[@]}" > "$b/configure.log" 2>&1 || { tail -30 "$b/configure.log"; die "LAMMPS cmake configure failed"; }
  cmake --build "$b" -j "$JOBS" > "$b/build.log" 2>&1 || { tail -30 "$b/build.log"; die "LAMMPS build failed"; }
  touch "$b/.complete"
}

case "${1:-all}" in
  deps) do_deps ;;
  source) do_source ;;
  build) do_build ;;
  all) do_deps; do_source; do_build ;;
  print-dir) build_dir ;;
  print-src) src_dir ;;
  *) die "unknown action '$1' (deps|source|build|all|print-dir|print-src)" ;;
esac
