#include "apps/editor/timing_report.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "msdeform/core/build_info.h"
#include "msdeform/core/timing.h"

namespace msdeform {
namespace editor {

TimingSummary SummarizeTimings(const std::vector<LayoutTiming>& layouts,
                               const std::vector<MoveTiming>& moves,
                               const std::vector<double>& draw_ms,
                               const std::vector<double>& busy_draw_ms) {
  TimingSummary summary;
  std::vector<double> solve, skin, both;
  for (const MoveTiming& move : moves) {
    solve.push_back(move.solve_ms);
    skin.push_back(move.skin_ms);
    both.push_back(move.solve_ms + move.skin_ms);
  }
  summary.moves = static_cast<int>(moves.size());
  summary.solve_median_ms = Median(solve);
  summary.skin_median_ms = Median(skin);
  summary.solve_skin_median_ms = Median(both);
  summary.solve_skin_max_ms = both.empty() ? 0.0 : *std::max_element(both.begin(), both.end());
  summary.draw_median_ms = Median(draw_ms);
  summary.busy_frames = static_cast<int>(busy_draw_ms.size());
  summary.busy_draw_max_ms =
      busy_draw_ms.empty() ? 0.0 : *std::max_element(busy_draw_ms.begin(), busy_draw_ms.end());
  std::vector<double> wall, rigidity, setup;
  for (const LayoutTiming& layout : layouts) {
    if (layout.init) continue;
    wall.push_back(layout.wall_ms);
    rigidity.push_back(layout.rigidity_ms);
    setup.push_back(layout.setup_ms);
  }
  summary.layout_changes = static_cast<int>(wall.size());
  summary.layout_wall_median_ms = Median(wall);
  summary.rigidity_median_ms = Median(rigidity);
  summary.setup_median_ms = Median(setup);
  return summary;
}

std::string TimingsJson(const std::string& name, int vertices,
                        const std::vector<LayoutTiming>& layouts,
                        const std::vector<MoveTiming>& moves, const std::vector<double>& draw_ms,
                        const std::vector<double>& busy_draw_ms) {
  using Json = nlohmann::ordered_json;
  const TimingSummary s = SummarizeTimings(layouts, moves, draw_ms, busy_draw_ms);
  Json report;
  report["name"] = name;
  report["vertices"] = vertices;
  report["machine"] = {{"cores", NumCores()}, {"cpu", CpuModel()}};
  report["summary"] = {{"moves", s.moves},
                       {"solve_median_ms", s.solve_median_ms},
                       {"skin_median_ms", s.skin_median_ms},
                       {"solve_skin_median_ms", s.solve_skin_median_ms},
                       {"solve_skin_max_ms", s.solve_skin_max_ms},
                       {"draw_median_ms", s.draw_median_ms},
                       {"busy_frames", s.busy_frames},
                       {"busy_draw_max_ms", s.busy_draw_max_ms},
                       {"layout_changes", s.layout_changes},
                       {"layout_wall_median_ms", s.layout_wall_median_ms},
                       {"rigidity_median_ms", s.rigidity_median_ms},
                       {"setup_median_ms", s.setup_median_ms}};
  Json move_list = Json::array();
  for (const MoveTiming& m : moves) {
    move_list.push_back({{"solve_ms", m.solve_ms},
                         {"skin_ms", m.skin_ms},
                         {"frame_ms", m.frame_ms},
                         {"iterations", m.iterations}});
  }
  report["moves"] = move_list;
  Json changes = Json::array(), opens = Json::array();
  for (const LayoutTiming& l : layouts) {
    Json entry = {{"init_ms", l.init_ms},
                  {"rigidity_ms", l.rigidity_ms},
                  {"setup_ms", l.setup_ms},
                  {"path_ms", l.path_ms},
                  {"wall_ms", l.wall_ms}};
    (l.init ? opens : changes).push_back(entry);
  }
  report["layout_changes"] = changes;
  report["opens"] = opens;
  report["draw_ms"] = draw_ms;
  report["busy_draw_ms"] = busy_draw_ms;
  return report.dump(1) + "\n";
}

std::string TimingsLine(const TimingSummary& s) {
  char line[640];
  std::snprintf(line, sizeof(line),
                "%d moves: solve+skin median %.2f ms (solve %.2f, skin %.2f; max %.2f), draw "
                "median %.2f ms; %d layout changes: median %.1f ms (rigidity %.1f, setup %.1f), "
                "%d frames drawn meanwhile (longest %.1f ms)",
                s.moves, s.solve_skin_median_ms, s.solve_median_ms, s.skin_median_ms,
                s.solve_skin_max_ms, s.draw_median_ms, s.layout_changes, s.layout_wall_median_ms,
                s.rigidity_median_ms, s.setup_median_ms, s.busy_frames, s.busy_draw_max_ms);
  return line;
}

}  // namespace editor
}  // namespace msdeform
