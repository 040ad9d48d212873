// The editor's Method panel: every registered method, the chosen method's own
// options, and DeformerOptionTable()'s command-line rows, each set through its
// flag as `msdeform --name=value` would; rows the method does not read are
// greyed out. Part of EditorApp (apps/editor/editor_app.h).

#include <imgui.h>
#include <imgui_stdlib.h>

#include <string>
#include <vector>

#include "apps/editor/editor_app.h"
#include "apps/editor/option_flags.h"
#include "apps/editor/panel_widgets.h"
#include "apps/flags/deformer_flags.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace editor {

void EditorApp::SetFlagFromPanel(const std::string& name, const std::string& value) {
  DeformerOptions options = session_->options();
  std::string error;
  if (!SetDeformerFlag(name, value, &options, &error)) {
    status_.Show(error);
    return;
  }
  status_.Clear();
  ApplyOptions(options);
}

// Every registered method (methods/registry.h), then the selected method's
// own rows of MethodOptionTable() (cgal.*, fastlsm.*), each set through its
// flag as `msdeform --fastlsm_steps=40` would.
void EditorApp::DrawMethodChooser() {
  const std::string current = session_->method_name();
  ImGui::SetNextItemWidth(kComboWidth);
  if (ImGui::BeginCombo("method", current.c_str())) {
    for (const std::string& name : MethodNames()) {
      if (ImGui::Selectable(name.c_str(), current == name) && current != name) {
        DeformerOptions options = session_->options();
        std::string error;
        if (!SetDeformerFlag("method", name, &options, &error) ||
            !session_->SetMethod(name, &error)) {
          status_.Show(error);
        } else {
          status_.Clear();
        }
      }
    }
    ImGui::EndCombo();
  }
  Help(DeformerOptionTable().Find("method")->help.c_str());
  for (const auto& row : MethodOptionTable().rows()) {
    if (!RowOfMethod(row.name, current)) continue;
    const std::string flag = FlagSpellings(row).front();
    std::string text = DeformerFlagValue(flag);
    ImGui::SetNextItemWidth(kFieldWidth);
    if (ImGui::InputText(row.name.c_str(), &text, ImGuiInputTextFlags_EnterReturnsTrue)) {
      MethodOptions options = session_->method_options();
      std::string error;
      if (!SetMethodFlag(flag, text, &options, &error)) {
        status_.Show(error);
      } else {
        status_.Clear();
        session_->SetMethodOptions(options);
      }
    }
    Help(row.help.c_str());
  }
}

void EditorApp::DrawMethodPanel() {
  if (!ImGui::CollapsingHeader("Method", ImGuiTreeNodeFlags_DefaultOpen)) return;
  // The method chooser, then DeformerOptionTable()'s command-line rows: a combo per
  // enum, a checkbox per switch; the ablations, and the solver's details and the
  // numbers, under their own nodes. Each change goes through the flag, as
  // `msdeform --name=value`. Rows the chosen method does not read (a graph
  // method's, for cgal_arap) are greyed out.
  const std::string method = session_->method_name();
  const bool graph = IsGraphMethod(method);
  const auto draw_row = [this, &method](const OptionRow<DeformerOptions>& row) {
    const std::string flag = FlagSpellings(row).front();
    const std::string current = DeformerFlagValue(flag);
    const char* label = row.name.c_str();
    ImGui::BeginDisabled(!MethodReadsDeformerRow(method, row.name));
    if (row.type == OptionType::kEnum) {
      ImGui::SetNextItemWidth(kComboWidth);
      if (ImGui::BeginCombo(label, current.c_str())) {
        for (const std::string& value : row.choices) {
          if (ImGui::Selectable(value.c_str(), current == value) && current != value) {
            SetFlagFromPanel(flag, value);
          }
        }
        ImGui::EndCombo();
      }
    } else if (row.type == OptionType::kBool) {
      bool on = current == "true";
      if (ImGui::Checkbox(label, &on)) SetFlagFromPanel(flag, on ? "true" : "false");
    } else {
      std::string text = current;
      ImGui::SetNextItemWidth(kFieldWidth);
      if (ImGui::InputText(label, &text, ImGuiInputTextFlags_EnterReturnsTrue)) {
        SetFlagFromPanel(flag, text);
      }
    }
    ImGui::EndDisabled();
    Help(row.help.c_str());
  };
  // The switches on the panel; the subspace ARAP energy's (arap.*) are under
  // More with the numbers, as they matter only with energy=arap.
  const auto switch_row = [](const OptionRow<DeformerOptions>& row) {
    return !row.topic.empty() && row.name != "method" && row.name.rfind("arap.", 0) != 0 &&
           (row.type == OptionType::kEnum || row.type == OptionType::kBool) &&
           (row.topic != "solver" || row.name == "backend");
  };
  DrawMethodChooser();
  for (const auto& row : DeformerOptionTable().rows()) {
    if (switch_row(row) && row.topic != "ablations") draw_row(row);
  }
  if (ImGui::TreeNode("Ablations")) {
    for (const auto& row : DeformerOptionTable().rows()) {
      if (switch_row(row) && row.topic == "ablations") draw_row(row);
    }
    ImGui::TreePop();
  }
  if (ImGui::TreeNode("More")) {
    for (const auto& row : DeformerOptionTable().rows()) {
      if (!row.topic.empty() && row.name != "method" && !switch_row(row)) draw_row(row);
    }
    ImGui::TreePop();
  }
  // The paper's procedure: every option PaperProcedure() changes (the graph
  // methods' options), as flags; built once.
  static const std::string paper_flags = [] {
    const DeformerOptions paper = PaperProcedure(DeformerOptions());
    std::string flags;
    for (const auto& row : DeformerOptionTable().rows()) {
      if (row.get(paper) == row.get(DeformerOptions())) continue;
      const std::vector<std::string> spellings = FlagSpellings(row);
      flags += (flags.empty() ? "--" : " --") +
               (spellings.empty() ? row.name : spellings.front()) + "=" + row.get(paper);
    }
    return flags;
  }();
  ImGui::BeginDisabled(!graph);
  if (ImGui::Button("Paper procedure")) {
    DeformerOptions options = session_->options();
    const DeformerOptions target = PaperProcedure(options);
    std::string error;
    for (const auto& row : DeformerOptionTable().rows()) {
      if (row.get(target) == row.get(options)) continue;
      const std::vector<std::string> spellings = FlagSpellings(row);
      const std::string name = spellings.empty() ? row.name : spellings.front();
      if (!SetDeformerFlag(name, row.get(target), &options, &error)) status_.Show(error);
    }
    ApplyOptions(options);
  }
  ImGui::EndDisabled();
  Help(paper_flags.c_str());
}

}  // namespace editor
}  // namespace msdeform
