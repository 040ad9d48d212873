// Small pieces the editor's panels share (editor_panels.cc, method_panel.cc):
// a help marker, label colours as ImGui's, and the Method panel's widths.

#ifndef MSDEFORM_APPS_EDITOR_PANEL_WIDGETS_H_
#define MSDEFORM_APPS_EDITOR_PANEL_WIDGETS_H_

#include <imgui.h>

#include "apps/editor/overlays.h"

namespace msdeform {
namespace editor {

// Combo boxes and text fields of the Method panel, pixels: with the longest
// row names and their "(?)" they fit the 400-pixel panel column.
constexpr float kComboWidth = 170.0f;
constexpr float kFieldWidth = 120.0f;

// "(?)" after the last item, with `text` as its tooltip.
inline void Help(const char* text) {
  ImGui::SameLine();
  ImGui::TextDisabled("(?)");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

inline ImVec4 Color(const Rgb& rgb) {
  return ImVec4(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, 1.0f);
}

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_PANEL_WIDGETS_H_
