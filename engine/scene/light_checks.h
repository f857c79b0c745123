// Lights that can light nothing, and how to name a light in a message.
//
// A light emits to the front of its plane only. One whose plane has no vertex of any other face
// strictly in front of it (the exact orient3d signs of visibility/face_plane.h: a face with every
// vertex on or behind the plane lies in the closed half-space behind it) lights nothing in the
// scene: most often its vertices are in the wrong order (flipped winding). loadScene reports such
// lights as a warning of the scene. A light that faces receivers but is hidden from all of them
// shows only once every pair is classified: the precompute reports it (hiddenLightWarning).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/scene/scene.h"

namespace penumbra {

// "light 2 (face 14, material 'Lamp', line 40)": light index, face, material and the face's
// line in the scene file where the format has lines.
std::string lightName(const Scene& scene, size_t light);

// The lights (indices into scene.lights) with no vertex of another face strictly in front of
// their plane. Exact. A scene whose only faces are lights has no receiver: none is reported.
std::vector<size_t> lightsFacingAway(const Scene& scene);

// One warning line for all of lightsFacingAway, naming the file, the first light and the likely
// cause; nullopt when there is none.
std::optional<std::string> lightsFacingAwayWarning(const Scene& scene);

// The warning for a light every one of whose (receiver patch, light) pairs is back-facing or
// hidden (fully hidden, or a tree with no visible leaf), with those counts: no receiver gets any
// of its light. `receivers` says which pairs were counted: "every receiver" (the precompute's,
// all of them) or "every receiver the image sees" (a render's). For the default light, the
// likely cause: geometry over the whole scene (a closed room).
std::string hiddenLightWarning(const Scene& scene, size_t light, size_t backFacing, size_t hidden,
                               std::string_view receivers = "every receiver");

}  // namespace penumbra
