#!/usr/bin/env bash
# Regenerates docs/screenshots/: the viewer's complete UI, rendered headless (penumbra screenshot,
# OSMesa), on assets/stairs.obj and assets/grids.obj with a penumbra point inspected and the
# side-by-side preview, plus one PNG per panel cropped with the panel rectangles the state JSON
# reports; the Cornell box's "Accuracy vs time" panel (--accuracy) and its lamp moved
# (--move-light). Needs a build
# (build/app/penumbra) and ImageMagick.
set -euo pipefail
cd "$(dirname "$0")/.."
exe=./build/app/penumbra
dir=docs/screenshots
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$dir"
crop_panels() {  # name [panel]: NAME_ui.png and NAME_PANEL.png (every panel, or that one)
  convert "$tmp/$1.png" -strip -define png:compression-level=9 "$dir/$1_ui.png"
  # One file per panel: "name x y w h" lines from the state's panelRects.
  /usr/bin/python3 -c '
import json, sys
for name, (x, y, w, h) in json.load(open(sys.argv[1]))["panelRects"].items():
    if len(sys.argv) < 3 or name == sys.argv[2]:
        print(name.lower().replace(" ", "_"), int(x), int(y), int(w), int(h))' "$tmp/$1.json" ${2:+"$2"} |
  while read -r panel x y w h; do
    convert "$tmp/$1.png" -crop "${w}x${h}+${x}+${y}" +repage -strip \
      -define png:compression-level=9 "$dir/$1_${panel}.png"
  done
}
shoot() {  # name scene point
  "$exe" screenshot "$2" --point "$3" --preview-mode side --light-samples 8 --passes 8 \
    --size 1280x800 --out "$tmp/$1.png" --state-out "$tmp/$1.json"
  crop_panels "$1"
}
shoot stairs assets/stairs.obj 2.8,1.0,0
shoot grids assets/grids.obj 0.3,0.3,0
"$exe" screenshot assets/scenes/cornell_box.json --accuracy --preview-mode side --light-samples 8 \
  --size 1280x800 --out "$tmp/cornell.png" --state-out "$tmp/cornell.json"
crop_panels cornell "Accuracy vs time"
# The Cornell box's lamp moved down, to the left and stretched, its shadows following; the Move
# light window open (the whole UI).
"$exe" screenshot assets/scenes/cornell_box.json --camera 278,273,-700,278,273,0,45 \
  --move-light 0 --translate -60,-150,40 --scale 1.5,1,0.5 --rotate 0,0,15 --point 420,0,120 \
  --light-samples 8 --passes 8 --size 1600x900 --out "$tmp/moved_light.png" --state-out "$tmp/moved_light.json"
convert "$tmp/moved_light.png" -strip -define png:compression-level=9 "$dir/moved_light.png"
ls -la "$dir"
