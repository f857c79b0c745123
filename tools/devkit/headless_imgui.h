// HeadlessImGui: a Dear ImGui context with no platform or renderer backend, for drawing widgets
// into draw lists in tests and tools (no GL, no window). The display size is set, the font atlas
// is built (its RGBA pixels are kept for software rasterizers), the ini file is off, and the
// renderer flag of the OpenGL3 backend is declared (draw lists may exceed 64k vertices).
// Owns its context: created in the constructor, destroyed in the destructor.
#pragma once

#include <imgui.h>

#include <cstddef>

namespace penumbra::devkit {

class HeadlessImGui {
  public:
    explicit HeadlessImGui(float width = 1280, float height = 800);
    ~HeadlessImGui();
    HeadlessImGui(const HeadlessImGui&) = delete;
    HeadlessImGui& operator=(const HeadlessImGui&) = delete;

    // One frame: NewFrame, the next window placed at (0, 0) filling the display, `draw()` (which
    // opens that window), Render. Returns the frame's draw data (valid until the next frame).
    template <class Draw>
    ImDrawData* frame(Draw&& draw) {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImGui::GetIO().DisplaySize);
        draw();
        ImGui::Render();
        ImGui::GetIO().MouseWheel = 0;
        return ImGui::GetDrawData();
    }

    // Vertices over every draw list of `d`.
    static size_t vertices(const ImDrawData* d);

    const unsigned char* atlasPixels() const { return atlas_; }
    int atlasWidth() const { return atlasWidth_; }
    int atlasHeight() const { return atlasHeight_; }

  private:
    ImGuiContext* context_;
    unsigned char* atlas_ = nullptr;
    int atlasWidth_ = 0, atlasHeight_ = 0;
};

}  // namespace penumbra::devkit
