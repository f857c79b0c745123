#!/usr/bin/env bash
# Regenerates docs/screenshots/: the viewer's complete UI, rendered headless (penumbra screenshot,
# OSMesa), on assets/stairs.obj and assets/grids.obj with a penumbra point inspected and the
# side-by-side preview, plus one PNG per panel cropped with the panel rectangles the state JSON
# reports; the Cornell box's "Accuracy vs time" panel (--accuracy) and its lamp moved
# (--move-light); the table scene's panels arranged and its History tree enlarged (README's top
# image); the rendered view of table, stairs, grids and the bunny in the Cornell box in its modes.
# Needs a build (build/app/penumbra), ImageMagick, and for the bunny scripts/fetch_meshes.sh.
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
# The panels as a user arranges them (app/viewer/panel_arrangement.h) on the table scene with the
# README's point: Scene and Precompute collapsed, the History tree taller, the right column
# resized; and the History tree enlarged to most of the window (as E does).
table=(assets/scenes/table.json --point 0.511269,-0.152198,0.75 --light-samples 8 --passes 8
  --size 1280x800)
echo '{"helpSeen": true}' >"$tmp/help_seen.json"  # as on a second run: Help closed
"$exe" screenshot "${table[@]}" --settings "$tmp/help_seen.json" --collapse Scene \
  --collapse Precompute --panel "Precompute=0,40,320,150" \
  --panel "History tree=0,62,320,440" --panel "Preview=0,502,320,298" \
  --panel "Point=853,19,427,190" --panel "Light plane=853,209,427,330" \
  --panel "Path=853,539,427,261" --out "$tmp/table_arranged.png"
"$exe" screenshot "${table[@]}" --enlarge "History tree" --out "$tmp/table_tree_enlarged.png"
for shot in table_arranged table_tree_enlarged; do
  convert "$tmp/$shot.png" -strip -define png:compression-level=9 "$dir/$shot.png"
done
# The rendered view (the preview in the 3D view, the viewer's first screen) in its exact, side by
# side (exact | 16 shadow rays) and difference modes on table, stairs and grids with a point
# inspected, Help closed as on a second run; the bunny in the Cornell box close up (its difference
# and answers views with their colour scales, a pixel hovered in the answers). Written as 8-bit palette PNGs
# when that is lossless enough to keep each under 300 KB.
keep() {  # name: $tmp/name.png -> $dir/name.png, small
  convert "$tmp/$1.png" -strip -define png:compression-level=9 "$dir/$1.png"
  if [ "$(stat -c %s "$dir/$1.png")" -gt 300000 ]; then
    convert "$tmp/$1.png" -strip -colors 256 -define png:compression-level=9 "$dir/$1.png"
  fi
}
view_shot() {  # name scene mode [options...]
  local name=$1 scene=$2 mode=$3
  shift 3
  echo '{"helpSeen": true}' >"$tmp/second_run.json"  # the default layout, Help closed
  "$exe" screenshot "$scene" --view "$mode" --passes 8 --size 1280x800 \
    --settings "$tmp/second_run.json" "$@" --out "$tmp/$name.png"
  keep "$name"
}
for mode in rendered side diff; do
  view_shot "table_view_$mode" assets/scenes/table.json "$mode" --point 0.511269,-0.152198,0.75
  view_shot "stairs_view_$mode" assets/stairs.obj "$mode" --point 2.8,1.0,0
  view_shot "grids_view_$mode" assets/grids.obj "$mode" --point 0.3,0.3,0
done
if [ -f assets/external/bunny.obj ]; then
  bunny=(assets/scenes/bunny_in_box.json --camera 425,230,-330,425,100,125,40)
  for mode in rendered side diff; do
    view_shot "bunny_in_box_view_$mode" "${bunny[0]}" "$mode" "${bunny[@]:1}"
  done
  # A pixel of the bunny's self-shadowed body hovered: how the exact render answered it.
  view_shot bunny_in_box_view_answers "${bunny[0]}" answers "${bunny[@]:1}" --hover 600,440
else
  echo "docs_screenshots.sh: no assets/external/bunny.obj (bash scripts/fetch_meshes.sh):" \
    "the bunny_in_box_view_* screenshots are left as they are" >&2
fi
ls -la "$dir"
