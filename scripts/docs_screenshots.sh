#!/usr/bin/env bash
# Regenerates docs/screenshots/: the viewer's complete UI, rendered headless (penumbra screenshot,
# OSMesa), on assets/stairs.obj and assets/grids.obj with a penumbra point inspected and the
# side-by-side preview, plus one PNG per panel cropped with the panel rectangles the state JSON
# reports. Needs a build (build/app/penumbra) and ImageMagick.
set -euo pipefail
cd "$(dirname "$0")/.."
exe=./build/app/penumbra
dir=docs/screenshots
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$dir"
shoot() {  # name scene point
  "$exe" screenshot "$2" --point "$3" --preview-mode side --light-samples 8 --passes 8 \
    --size 1280x800 --out "$tmp/$1.png" --state-out "$tmp/$1.json"
  convert "$tmp/$1.png" -strip -define png:compression-level=9 "$dir/$1_ui.png"
  # One file per panel: "name x y w h" lines from the state's panelRects.
  /usr/bin/python3 -c '
import json, sys
for name, (x, y, w, h) in json.load(open(sys.argv[1]))["panelRects"].items():
    print(name.lower().replace(" ", "_"), int(x), int(y), int(w), int(h))' "$tmp/$1.json" |
  while read -r panel x y w h; do
    convert "$tmp/$1.png" -crop "${w}x${h}+${x}+${y}" +repage -strip \
      -define png:compression-level=9 "$dir/$1_${panel}.png"
  done
}
shoot stairs assets/stairs.obj 2.8,1.0,0
shoot grids assets/grids.obj 0.3,0.3,0
ls -la "$dir"
