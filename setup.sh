#!/bin/bash
# The README's two commands, on a machine that may have nothing but bash and
# apt (a minimal Debian root: no make, no compiler, no git):
#   bash setup.sh run    provision (Debian packages, LAMMPS from Debian's
#                        source package), build the plugin alone, then run
#                        the flagship example
#   bash setup.sh test   the same provisioning, then build the plugin and the
#                        test programs and run the whole test suite
# It installs make from Debian when missing and hands over to the Makefile,
# whose `lammps` target (cmake/lammps.sh) installs everything else.
set -euo pipefail
cd "$(dirname "$0")"
target=${1:-run}
case "$target" in
  run | test | plugin | plugin-only | lammps | bench | chart | doc) ;;
  *) echo "usage: bash setup.sh run|test   (or plugin, plugin-only, lammps, bench, chart, doc)" >&2; exit 2 ;;
esac
if ! command -v make > /dev/null; then
  if [ "$(id -u)" != 0 ]; then
    echo "setup.sh: make is missing and this user is not root; run as root:" >&2
    echo "  apt-get update && apt-get install -y make" >&2
    exit 1
  fi
  echo "-- [peri-nospd] installing make from Debian" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends make > /dev/null
fi
exec make "$target"
