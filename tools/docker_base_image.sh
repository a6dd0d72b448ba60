#!/usr/bin/env bash
# Makes the base image the Dockerfile's first FROM names (debian:bookworm-slim) when the engine
# does not have it: pulled from a registry when one answers, otherwise built here from Debian
# packages (debootstrap bookworm, minbase, with python3, python3-pip, python3-venv and
# ca-certificates) and imported with `docker import` under that same tag. Does nothing when
# the image exists. Needs root (debootstrap) only when it has to build.
#   tools/docker_base_image.sh            # make it if missing
#   DEBIAN_MIRROR=http://mirror/debian tools/docker_base_image.sh
# The Dockerfile installs python3 and python3-venv with apt when its base lacks them, so a
# registry's debian:bookworm-slim and the image made here build the same motionsim image.
set -euo pipefail
cd "$(dirname "$0")/.."

image=$(awk 'toupper($1) == "FROM" { print $2; exit }' Dockerfile)
suite=bookworm
packages=python3,python3-pip,python3-venv,ca-certificates
mirror=${DEBIAN_MIRROR:-http://deb.debian.org/debian}

if docker image inspect "$image" >/dev/null 2>&1; then
  echo "base image $image: present"
  exit 0
fi
if timeout 120 docker pull -q "$image" >/dev/null 2>&1; then
  echo "base image $image: pulled"
  exit 0
fi
echo "base image $image: no registry answers; building it from Debian $suite packages ($mirror)"
command -v debootstrap >/dev/null 2>&1 || {
  echo "debootstrap is missing: apt-get install debootstrap" >&2
  exit 1
}
if [ "$(id -u)" != 0 ]; then
  echo "debootstrap needs root: sudo $0" >&2
  exit 1
fi

root=$(mktemp -d /var/tmp/motionsim-base.XXXXXX)
cleanup() {
  # a debootstrap that stopped half-way may leave /proc and /sys mounted in the tree
  findmnt -rn -o TARGET | grep "^$root/" | sort -r | xargs -r -n1 umount -l || true
  rm -rf --one-file-system "$root"
}
trap cleanup EXIT
debootstrap --variant=minbase --include="$packages" "$suite" "$root" "$mirror" \
  >"$root.log" 2>&1 || {
  tail -n 20 "$root.log" >&2
  echo "debootstrap $suite failed (full log: $root.log)" >&2
  exit 1
}
rm -f "$root.log"
# Slim as Debian's own -slim images: no package cache, no downloaded indexes, no manuals.
rm -rf "$root"/var/cache/apt/archives/*.deb "$root"/var/lib/apt/lists/* \
       "$root"/usr/share/doc/* "$root"/usr/share/man/* "$root"/usr/share/info/*
tar --numeric-owner --one-file-system -C "$root" -c . |
  docker import --change 'CMD ["bash"]' \
    --change 'LABEL org.opencontainers.image.description=debootstrap-'"$suite"'-minbase+'"$packages" \
    - "$image" >/dev/null
echo "base image $image: built with debootstrap ($(docker image inspect -f '{{.Size}}' "$image" | awk '{printf "%.0f MB", $1 / 1e6}'))"
