#!/bin/bash
# Try the README's commands the way a newcomer would: on a minimal Debian
# root (debootstrap --variant=minbase: bash, apt, coreutils; no make, no
# compiler, no git), as root, from an unpacked copy of this tree.
# Needs root, debootstrap and the Debian mirror; takes a cold LAMMPS build
# (~15-25 min on 2 cores).  Not part of ctest.
# usage: tools/check_minimal_debian.sh [ROOT_DIR] [run|test]   (default /tmp/minbase test)
# Environment: MIRROR (default: the Debian mirror of this machine's apt
# sources, found as cmake/lammps.sh finds it), SUITE (default bookworm).
set -euo pipefail

# The Debian mirror this machine's apt already uses, as cmake/lammps.sh
# takes it for its deb-src entries: the first URI of a "deb" entry that is
# not a security archive, looked for in /etc/apt/sources.list.d/debian.sources
# and /etc/apt/sources.list (cmake/lammps.sh's two places, in its order),
# then in the other sources.list.d/*.sources (deb822) and *.list (one-line)
# files.  Prints nothing when there is none.  APT_ETC (default /etc/apt)
# is for testing.
mirror_of_sources_file() {    # deb822: stanzas separated by blank lines
  awk '
    function flush() {
      if (!found && uri != "" && enabled != "no" && uri !~ /security/ &&
          (" " types " ") ~ /[ \t]deb[ \t]/) { print uri; found = 1 }
      types = ""; uri = ""; enabled = ""
    }
    /^[ \t]*#/ { next }
    /^[ \t]*$/ { flush(); next }
    tolower($1) == "types:" { types = $0; sub(/^[^:]*:/, "", types) }
    tolower($1) == "uris:" { uri = $2 }
    tolower($1) == "enabled:" { enabled = tolower($2) }
    END { flush() }' "$1"
}
mirror_of_list_file() {       # one-line style: deb [options] URI suite components
  awk '$1=="deb" && $0 !~ /security/ {for(i=2;i<=NF;i++) if ($i ~ /^(https?|file|ftp):/) {print $i; exit}}' "$1"
}
host_mirror() {
  local etc=${APT_ETC:-/etc/apt} f uri=""
  for f in "$etc/sources.list.d/debian.sources" "$etc/sources.list" \
           "$etc"/sources.list.d/*.sources "$etc"/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    case "$f" in
      *.sources) uri=$(mirror_of_sources_file "$f") ;;
      *) uri=$(mirror_of_list_file "$f") ;;
    esac
    [ -n "$uri" ] && break
  done
  printf '%s\n' "$uri"
}

SRC=$(cd "$(dirname "$0")/.." && pwd)
ROOTFS=${1:-/tmp/minbase}
TARGET=${2:-test}
SUITE=${SUITE:-bookworm}
if [ ! -x "$ROOTFS/usr/bin/apt-get" ]; then
  MIRROR=${MIRROR:-$(host_mirror)}
  if [ -z "$MIRROR" ]; then
    echo "check_minimal_debian.sh: no Debian mirror in /etc/apt/sources.list{,.d}; set MIRROR=URL" >&2
    exit 1
  fi
  echo "check_minimal_debian.sh: debootstrap $SUITE from $MIRROR" >&2
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
