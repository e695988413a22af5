#!/usr/bin/env bash
# Times one of README.md's two commands (./scripts/test.sh or ./scripts/demo.sh) from a clean clone
# on a fresh Debian 12 root: debootstrap's minbase plus what a new 2-core build machine ships (GCC,
# CMake, GoogleTest, Google Benchmark, git, Python, Node.js with npm, the clang tools), with none of
# vscan's packages and no ccache. Every output line is stamped with the seconds since the start.
#
#   sudo bench/fresh_machine.sh test|demo [WORK]
#
# Needs root, debootstrap and the Debian mirror. The root is made once into WORK (default
# /var/tmp/vscan-fresh, about 2 GB) and unpacked afresh for each run; it commits what HEAD holds.
# CA certificates added to the host (/usr/local/share/ca-certificates) are copied in, for networks
# that re-sign TLS.
set -euo pipefail
KIND="${1:-}"
case "$KIND" in test|demo) ;; *) echo "usage: fresh_machine.sh test|demo [WORK]" >&2; exit 2 ;; esac
WORK="${2:-/var/tmp/vscan-fresh}"
MIRROR="${VSCAN_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROOT="$WORK/root"
BASE_PACKAGES=(g++ make cmake git ca-certificates python3 npm libgtest-dev libgmock-dev libbenchmark-dev
               clang-format clang-tidy cppcheck gdb valgrind time)

unmount() {
  for d in dev/pts dev sys proc; do
    if mountpoint -q "$ROOT/$d"; then umount -R "$ROOT/$d" 2>/dev/null || umount -R -l "$ROOT/$d"; fi
  done
}
trap unmount EXIT

mount_kernel_filesystems() {
  mkdir -p "$ROOT/proc" "$ROOT/sys" "$ROOT/dev"
  mount -t proc proc "$ROOT/proc"
  mount --rbind /sys "$ROOT/sys"
  mount --rbind /dev "$ROOT/dev"
  cp /etc/resolv.conf "$ROOT/etc/resolv.conf"
}

if [ ! -f "$WORK/base.tar" ]; then
  mkdir -p "$WORK"
  unmount
  rm -rf --one-file-system "$ROOT"
  debootstrap --variant=minbase bookworm "$ROOT" "$MIRROR"
  printf '127.0.0.1\tlocalhost\n::1\tlocalhost ip6-localhost ip6-loopback\n' >"$ROOT/etc/hosts"
  # ca-certificates' own install adds these to the bundle.
  mkdir -p "$ROOT/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$ROOT/usr/local/share/ca-certificates/" 2>/dev/null || true
  mount_kernel_filesystems
  chroot "$ROOT" apt-get update -qq
  chroot "$ROOT" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${BASE_PACKAGES[@]}" >/dev/null
  unmount
  tar -C "$WORK" -cf "$WORK/base.tar" root
fi

# A run killed before its trap left the host's /dev and /sys bound in the root: never delete through them.
unmount
rm -rf --one-file-system "$ROOT"
tar -C "$WORK" -xf "$WORK/base.tar"
mount_kernel_filesystems
git clone -q "$REPO" "$ROOT/root/vscan"
echo "vscan $(git -C "$ROOT/root/vscan" log --oneline -1), ./scripts/$KIND.sh on a fresh root, $(nproc) cores"
bundle=/etc/ssl/certs/ca-certificates.crt
start=$(date +%s)
status=0
chroot "$ROOT" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  LANG=C.UTF-8 NODE_EXTRA_CA_CERTS=$bundle npm_config_cafile=$bundle SSL_CERT_FILE=$bundle \
  bash -c "cd /root/vscan && /usr/bin/time -v ./scripts/$KIND.sh" 2>&1 |
  while IFS= read -r line; do printf '%5d %s\n' $(($(date +%s) - start)) "$line"; done || status=$?
echo "fresh_machine.sh: ./scripts/$KIND.sh exited $status after $(($(date +%s) - start)) s"
exit "$status"
