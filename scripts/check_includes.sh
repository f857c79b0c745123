#!/usr/bin/env bash
# Lists every `#include "..."` from a lower room of the source to a higher one, and fails (exit 1)
# when there is any. Usage: scripts/check_includes.sh (from anywhere; it reads the repository it
# lives in).
#
# The layers, lowest first: visibility/ < engine/ < app/ < tools/ < tests/. Inside a layer, the
# rooms below, lowest first; a file belongs to the room of the longest prefix that matches its
# path, and may include from its own room and from any lower one. Rooms on one line share a rank
# (the viewer's panels sit beside the state they show, and include it).
#   visibility/                    the exact core
#   visibility/fp_query/           the from-point query's strategies, over the core
#   engine/scene/ < engine/raytrace/ < engine/precompute/ < engine/render/ < engine/io/ <
#   engine/studies/ < engine/cluster/  (engine/CMakeLists.txt says what each holds)
#   app/viewer/viewport.h          a rectangle of the framebuffer: no GL, no ImGui, so that the
#                                  GL renderer, the layout and the panels all name it
#   app/viewer/gl/                 GL only: contexts, shaders, buffers, the scene renderer
#   app/viewer/, app/viewer/panels/  the viewer's state and its panels
#   app/viewer/host/               where the viewer runs: the window and the headless hosts
#   app/cli/                       the commands (and the bench)
#   tools/, tests/
set -euo pipefail
cd "$(dirname "$0")/.."

# prefix rank; the longest matching prefix decides.
rooms='
visibility/ 0
visibility/fp_query/ 1
engine/scene/ 10
engine/raytrace/ 11
engine/precompute/ 12
engine/render/ 13
engine/io/ 14
engine/studies/ 15
engine/cluster/ 16
app/viewer/viewport.h 20
app/viewer/gl/ 21
app/viewer/ 22
app/viewer/panels/ 22
app/viewer/host/ 23
app/cli/ 24
tools/ 30
tests/ 40
'

git ls-files -z --cached --others --exclude-standard -- '*.h' '*.cpp' |
  grep -zE '^(visibility|engine|app|tools|tests)/' |
  { xargs -0 grep -snE '^[[:space:]]*#[[:space:]]*include[[:space:]]+"' || true; } |
  sed -E 's|^([^:]+):([0-9]+):.*#[[:space:]]*include[[:space:]]+"([^"]+)".*|\1 \2 \3|' |
  awk -v rooms="${rooms}" '
    BEGIN {
      n = split(rooms, lines, "\n")
      for (i = 1; i <= n; ++i) {
        if (split(lines[i], f, " ") == 2) { prefix[++count] = f[1]; rank[count] = f[2] }
      }
    }
    function roomOf(path,    i, best, bestLength) {
      best = 0; bestLength = 0
      for (i = 1; i <= count; ++i)
        if (index(path, prefix[i]) == 1 && length(prefix[i]) > bestLength) {
          best = i; bestLength = length(prefix[i])
        }
      return best
    }
    {
      from = roomOf($1); to = roomOf($3)
      # Includes outside the rooms (third-party headers with quotes, generated files) are not
      # checked.
      if (from == 0 || to == 0) next
      if (rank[to] > rank[from]) {
        printf "%s:%s: includes %s (%s above %s)\n", $1, $2, $3, prefix[to], prefix[from]
        ++upward
      }
    }
    END {
      if (upward > 0) {
        printf "check_includes: %d include(s) from a lower room to a higher one\n", upward
        exit 1
      }
      print "check_includes: no include from a lower room to a higher one"
    }'
