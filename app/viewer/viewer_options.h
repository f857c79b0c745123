// ViewerOptions: what the viewer starts with (the command line's view and screenshot options);
// the viewer keeps them and its panels and keys edit them as it runs.
#pragma once

#include <filesystem>

#include "app/viewer/layout.h"
#include "app/viewer/panels/preview_panel.h"
#include "app/viewer/preview_runner.h"
#include "engine/io/load_options.h"
#include "engine/render/exact_options.h"

namespace penumbra::viewer {

struct ViewerOptions {
    std::filesystem::path assetsDirectory = "assets";  // the scene list of the Scene panel
    bool showHelp = true;
    bool preview = true;              // run the progressive preview (when the renderer exists)
    PreviewSettings previewSettings;  // width/height are overwritten from the viewport
    double previewScale = 0.25;       // preview pixels per viewport pixel (the panel's thumbnail)
    // The rendered view (the default: the exact soft shadows from the first screen) renders at the
    // viewport's resolution; the raster view is flat colours.
    ViewMode view = ViewMode::Rendered;
    double split = 0.5;  // side by side in the rendered view: exact left of this fraction
    ExactOptions exact;  // the build budget and the renderer's exact settings
    // How scenes load (engine/io/load_options.h): --strict (what the loaders repair is an error
    // instead) and --no-default-light (a scene without any light stays unlit).
    LoadOptions load = LoadOptions::forCommands();
    // The content scale (the window host sets GLFW's; screenshot --ui-scale) and the columns'
    // widths (dragged at the 3D view's edges).
    LayoutSettings layout;
    // The viewer's settings file (viewer_settings.h: the panels' arrangement, the columns, whether
    // Help was seen): read when the viewer starts, written by saveSettings(). Empty: none.
    std::filesystem::path settingsFile;
    // The visibility file of the first scene opened (--visibility; visibility_link.h): its trees
    // are read when the scene opens and the precompute writes them back. Empty: none.
    std::filesystem::path visibilityFile;
};

}  // namespace penumbra::viewer
