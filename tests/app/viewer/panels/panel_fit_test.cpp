// The overflow measure of the panels (app/viewer/panels/panel_fit.h), headless (no GL): a table
// whose column is too narrow for its header label counts as overflow by how much the label is
// wider, a column wide enough counts 0, and a plain label past a window's edge counts as before.
//
// The expectations are computed by hand from ImGui's default font, ProggyClean at 13 px, in which
// every glyph is 7 px wide: "form factor" is 11 glyphs, 77 px. With the cell padding, the window
// padding and the window border set to 0 and no table borders, a fixed column of width W spans W
// pixels from its left edge, and its header label starts at that edge: the label reaches 77 - W
// past it.
#include "app/viewer/panels/panel_fit.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <map>
#include <string>

#include "tools/devkit/headless_imgui.h"

namespace penumbra::viewer {
namespace panel_fit_test {

constexpr float kGlyph = 7;               // ProggyClean's advance at 13 px
constexpr float kLabel = 11 * kGlyph;     // "form factor"
constexpr float kTableWindowWidth = 400;  // room for both columns at their given widths

// A window "Panel" of width kTableWindowWidth holding a table of two fixed columns, "form factor"
// of `width` px and "x" of 30 px, with a header row and one row of short values; the overflow of
// the frame.
std::map<std::string, float> tableOverflow(float width) {
    devkit::HeadlessImGui imgui(800, 600);
    ImGuiStyle& style = ImGui::GetStyle();
    style.CellPadding = ImVec2(0, 0);
    style.WindowPadding = ImVec2(0, 0);
    style.WindowBorderSize = 0;
    std::map<std::string, float> overflow;
    // Two frames: a table lays out its columns from the frame before.
    for (int frame = 0; frame < 2; ++frame)
        imgui.frame([&] {
            ImGui::SetNextWindowSize(ImVec2(kTableWindowWidth, 200));
            ImGui::Begin("Panel", nullptr, ImGuiWindowFlags_NoTitleBar);
            if (ImGui::BeginTable("t", 2, ImGuiTableFlags_SizingFixedFit)) {
                ImGui::TableSetupColumn("form factor", ImGuiTableColumnFlags_WidthFixed, width);
                ImGui::TableSetupColumn("x", ImGuiTableColumnFlags_WidthFixed, 30);
                ImGui::TableHeadersRow();
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted("1");
                ImGui::TableNextColumn();
                ImGui::TextUnformatted("2");
                ImGui::EndTable();
            }
            ImGui::End();
            overflow = measureHorizontalOverflow();
        });
    return overflow;
}

TEST(PanelFit, TheFontIsTheOneTheExpectationsAssume) {
    devkit::HeadlessImGui imgui;
    imgui.frame([] {
        ImGui::Begin("w");
        EXPECT_FLOAT_EQ(ImGui::GetFontSize(), 13);
        EXPECT_FLOAT_EQ(ImGui::CalcTextSize("form factor").x, kLabel);
        ImGui::End();
    });
}

// The header "form factor" (77 px) in a 40 px column: ImGui draws "form f..." inside the cell, and
// the measure says the label is 37 px too wide.
TEST(PanelFit, ACutTableHeaderCountsAsOverflow) {
    const std::map<std::string, float> narrow = tableOverflow(40);
    ASSERT_TRUE(narrow.contains("Panel"));
    EXPECT_NEAR(narrow.at("Panel"), kLabel - 40, 1.0);
    const std::map<std::string, float> narrower = tableOverflow(20);
    EXPECT_NEAR(narrower.at("Panel"), kLabel - 20, 1.0);
}

TEST(PanelFit, AHeaderThatFitsCountsNothing) {
    const std::map<std::string, float> wide = tableOverflow(kLabel + 10);
    ASSERT_TRUE(wide.contains("Panel"));
    EXPECT_LE(wide.at("Panel"), 0.0f);
    const std::map<std::string, float> exact = tableOverflow(kLabel);
    EXPECT_LE(exact.at("Panel"), 0.0f);
}

// A label past a window's right edge (no table): 20 glyphs, 140 px, in a 100 px window without
// padding reach 40 px past it.
TEST(PanelFit, ALabelPastTheWindowEdgeCountsAsOverflow) {
    devkit::HeadlessImGui imgui(800, 600);
    ImGui::GetStyle().WindowPadding = ImVec2(0, 0);
    ImGui::GetStyle().WindowBorderSize = 0;  // the clip edge is the window's
    std::map<std::string, float> overflow;
    for (int frame = 0; frame < 2; ++frame)
        imgui.frame([&] {
            ImGui::SetNextWindowSize(ImVec2(100, 100));
            ImGui::Begin("Narrow", nullptr, ImGuiWindowFlags_NoTitleBar);
            ImGui::TextUnformatted("abcdefghijklmnopqrst");
            ImGui::End();
            overflow = measureHorizontalOverflow();
        });
    ASSERT_TRUE(overflow.contains("Narrow"));
    EXPECT_NEAR(overflow.at("Narrow"), 20 * kGlyph - 100, 1.0);
}

}  // namespace panel_fit_test
}  // namespace penumbra::viewer
