#!/usr/bin/env bash
# Extracts the Stanford bunny, data/meshes/bunny00.off of CGAL's demo data (Debian package
# libcgal-demo: 37,706 vertices, 75,408 triangles, closed, facing outward), into
# data/meshes/ (git-ignored; docs/meshes.md). The data come from an installed
# libcgal-demo, else from the .deb given as the first argument, else from one that
# `apt-get download` fetches (no root needed); dpkg-deb unpacks it in a temporary folder.
#
#   bash scripts/fetch_bunny.sh [libcgal-demo_VERSION_all.deb]
set -euo pipefail

out=data/meshes
member=data/meshes/bunny00.off
archive=/usr/share/doc/libcgal-dev/data.tar.gz
# The bunny of libcgal-demo 5.5.1-2 (Debian 12); another version's file is used with a
# warning, as the counts measured on it may differ.
sha256=ab651cb04955c161efaeb079035a1e5e1f0e0d1f816a2df67beaea68f393ff2b

if [ -s "$out/bunny00.off" ]; then
    echo "$out/bunny00.off: already there"
    exit 0
fi
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [ ! -f "$archive" ]; then
    deb=${1:-}
    if [ -z "$deb" ]; then
        (cd "$tmp" && apt-get download libcgal-demo >/dev/null) || {
            echo "fetch_bunny.sh: cannot download libcgal-demo (apt-get download); give its .deb as the argument" >&2
            exit 2
        }
        deb=$(ls "$tmp"/libcgal-demo_*.deb)
    fi
    dpkg-deb -x "$deb" "$tmp/unpacked"
    archive=$tmp/unpacked/usr/share/doc/libcgal-dev/data.tar.gz
fi
tar -xzf "$archive" -O "$member" >"$tmp/bunny00.off"
if [ "$(sha256sum "$tmp/bunny00.off" | cut -d' ' -f1)" != "$sha256" ]; then
    echo "fetch_bunny.sh: warning: bunny00.off differs from libcgal-demo 5.5.1-2's" >&2
fi
mv "$tmp/bunny00.off" "$out/bunny00.off"
echo "$out/bunny00.off: $(sed -n 2p "$out/bunny00.off" | cut -d' ' -f2) faces"
