// The Scene panel: the open scene (file, faces, lights, trees) and the list of scene files to open
// (the files of the assets folder).
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "app/viewer/layout.h"
#include "app/viewer/loaded_scene.h"

namespace penumbra::viewer {

// The scene list: every file loadScene reads (engine/io/scene_loader.h, any case of the
// extension) directly in `assets`, then in `assets`/scenes (the JSON scenes), each directory's
// files sorted. Missing directories list nothing.
std::vector<std::filesystem::path> listSceneFiles(const std::filesystem::path& assets);

class ScenePanel {
  public:
    explicit ScenePanel(std::filesystem::path assets);

    struct Actions {
        std::optional<std::filesystem::path> open;  // a file picked in the list
        bool fit = false;                           // "Fit (F)"
        bool moveLight = false;                     // "Move light (M)": its window, shown
    };
    Actions draw(const LoadedScene* scene);

  private:
    std::filesystem::path assets_;
    std::vector<std::filesystem::path> files_;
};

}  // namespace penumbra::viewer
