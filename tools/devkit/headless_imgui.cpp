#include "tools/devkit/headless_imgui.h"

namespace penumbra::devkit {

HeadlessImGui::HeadlessImGui(float width, float height) : context_(ImGui::CreateContext()) {
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(width, height);
    io.DeltaTime = 1.0f / 60.0f;
    io.IniFilename = nullptr;
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    io.Fonts->GetTexDataAsRGBA32(&atlas_, &atlasWidth_, &atlasHeight_);
}

HeadlessImGui::~HeadlessImGui() { ImGui::DestroyContext(context_); }

size_t HeadlessImGui::vertices(const ImDrawData* d) {
    size_t n = 0;
    for (int i = 0; i < d->CmdListsCount; ++i) n += size_t(d->CmdLists[i]->VtxBuffer.Size);
    return n;
}

}  // namespace penumbra::devkit
