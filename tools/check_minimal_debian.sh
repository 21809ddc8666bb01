#!/bin/bash
# Try the README's commands the way a newcomer would: on a minimal Debian
# root (debootstrap --variant=minbase: bash, apt, coreutils; no make, no
# compiler, no git), as root, from an unpacked copy of this tree.
# Needs root, debootstrap and the Debian mirror; takes a cold LAMMPS build
# (~15-25 min on 2 cores).  Not part of ctest.
# usage: tools/check_minimal_debian.sh [ROOT_DIR] [run|test]   (default /tmp/minbase test)
set -euo pipefail
SRC=$(cd "$(dirname "$0")/.." && pwd)
ROOTFS=${1:-/tmp/minbase}
TARGET=${2:-test}
MIRROR=${MIRROR:-http://deb.debian.org/debian}
SUITE=${SUITE:-bookworm}
if [ ! -x "$ROOTFS/usr/bin/apt-get" ]; then
  command -v debootstrap > /dev/null || apt-get install -y -qq debootstrap
  debootstrap --variant=minbase "$SUITE" "$ROOTFS" "$MIRROR"
fi
# the tree as a user unpacks it: tracked and new files, no .git, no build
rm -rf "$ROOTFS/root/peri-nospd"; mkdir -p "$ROOTFS/root/peri-nospd"
(cd "$SRC" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) |
  tar -xf - -C "$ROOTFS/root/peri-nospd"
# a user's container has /proc, /sys and /dev with /dev/shm (Open MPI's
# shared memory): bind them recursively
for m in proc sys dev; do
  mountpoint -q "$ROOTFS/$m" || mount --rbind "/$m" "$ROOTFS/$m"
done
cp /etc/resolv.conf "$ROOTFS/etc/resolv.conf"
# debootstrap writes no /etc/hosts, a container runtime or installer does:
# without the host name in it every MPI start waits for DNS (seconds)
[ -s "$ROOTFS/etc/hosts" ] || printf '127.0.0.1 localhost\n127.0.1.1 %s\n' "$(hostname)" > "$ROOTFS/etc/hosts"
trap 'for m in dev sys proc; do umount -R "$ROOTFS/$m" 2> /dev/null || true; done' EXIT
for tool in make g++ git; do
  chroot "$ROOTFS" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin bash -c "command -v $tool" &&
    echo "note: $tool is already in $ROOTFS (not a first run)"
done
time chroot "$ROOTFS" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin \
  bash -c "cd /root/peri-nospd && bash setup.sh $TARGET"
