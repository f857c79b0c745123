// PanelText: the text each panel drew in a frame, as Dear ImGui's log records it (the window's
// title, text, labels, buttons and values, a line per row, also what the window's scrolling or
// size hides from view), for the state JSON and the tests that check what the panels say.
//
// Dear ImGui logs one window at a time: its End() ends the log. So each panel's text is the first
// top-level window drawn since the previous take() (a second window, such as the accuracy plot
// beside its controls, is not recorded). The log opens no tree node (depth 0), and while it runs
// ImGui submits the items outside a window's clip rectangle too (clipped away when drawn): the
// pixels are the same as without it.
#pragma once

#include <cstddef>
#include <cstdio>
#include <map>
#include <string>

namespace penumbra::viewer {

class PanelText {
  public:
    PanelText() = default;
    ~PanelText();
    PanelText(const PanelText&) = delete;
    PanelText& operator=(const PanelText&) = delete;

    // Starts recording: inside a frame (after ImGui::NewFrame), before the first panel is drawn.
    // Forgets the previous frame's text.
    void begin();
    // Keeps what the panel drawn since begin() or the previous take() said as `panel`'s text.
    void take(const std::string& panel);
    // Stops recording (before ImGui::Render); what was drawn since the last take() is dropped.
    void end();
    // Panel name -> its text, from the frame recorded last.
    const std::map<std::string, std::string>& texts() const { return texts_; }

  private:
    void start();          // a new log, into a memory stream
    std::string finish();  // ends the log if the panel's End() did not, and returns its text

    std::map<std::string, std::string> texts_;
    // The log's stream (open_memstream), between start() and finish().
    std::FILE* stream_ = nullptr;
    char* data_ = nullptr;  // the stream's text (malloc'd by the stream, freed by finish())
    std::size_t size_ = 0;
};

}  // namespace penumbra::viewer
