// ImGuiSession: a Dear ImGui context with the OpenGL3 renderer backend initialised for the current
// GL function table; shut down in reverse order on destruction. No imgui.ini is read or written
// (the layout is fixed by the Viewer).
#pragma once

namespace penumbra::viewer {

class ImGuiSession {
  public:
    ImGuiSession();  // throws std::runtime_error when the renderer backend does not initialise
    ~ImGuiSession();
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

}  // namespace penumbra::viewer
