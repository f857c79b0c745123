#include "app/viewer/panels/panel_text.h"

#include <imgui.h>
#include <imgui_internal.h>  // ImGui::LogBegin and the log's stream (GImGui->LogFile)

#include <cstdlib>

namespace penumbra::viewer {

PanelText::~PanelText() { (void)finish(); }

void PanelText::begin() {
    texts_.clear();
    start();
}

void PanelText::take(const std::string& panel) {
    texts_[panel] = finish();
    start();
}

void PanelText::end() { (void)finish(); }

void PanelText::start() {
    ImGuiContext& g = *GImGui;
    if (g.LogEnabled) return;  // someone else's log: record nothing
    stream_ = open_memstream(&data_, &size_);
    if (stream_ == nullptr) return;
    // ImGui's log to the terminal writes to its stream and only flushes it when the log ends
    // (a log to a file would close it): the memory stream takes the terminal's place.
    ImGui::LogBegin(ImGuiLogType_TTY, 0);
    g.LogFile = stream_;
}

std::string PanelText::finish() {
    if (stream_ == nullptr) return {};
    // The panel's End() ended the log, unless it drew no window.
    ImGuiContext* g = GImGui;
    if (g != nullptr && g->LogEnabled && g->LogFile == stream_) ImGui::LogFinish();
    std::fclose(stream_);  // sets data_ and size_
    stream_ = nullptr;
    std::string text = data_ != nullptr ? std::string(data_, size_) : std::string();
    std::free(data_);
    data_ = nullptr;
    size_ = 0;
    return text;
}

}  // namespace penumbra::viewer
