// The editor's timing panel as a file (--timings=PATH): every Drag of the
// session (a mouse move or a script step) and every background job (open,
// new options, handle-layout change), with their medians, so the interactive
// targets can be measured from a scripted session (README.md, "Editor").

#ifndef MSDEFORM_APPS_EDITOR_TIMING_REPORT_H_
#define MSDEFORM_APPS_EDITOR_TIMING_REPORT_H_

#include <string>
#include <vector>

#include "apps/editor/edit_session.h"

namespace msdeform {
namespace editor {

struct TimingSummary {
  int moves = 0;
  double solve_median_ms = 0.0;
  double skin_median_ms = 0.0;
  double solve_skin_median_ms = 0.0;  // per move, solve + skin
  double solve_skin_max_ms = 0.0;
  double draw_median_ms = 0.0;  // per drawn frame
  int busy_frames = 0;          // frames drawn while a layout change ran
  double busy_draw_max_ms = 0.0;
  int layout_changes = 0;  // jobs without Init
  double layout_wall_median_ms = 0.0;
  double rigidity_median_ms = 0.0;
  double setup_median_ms = 0.0;
};

TimingSummary SummarizeTimings(const std::vector<LayoutTiming>& layouts,
                               const std::vector<MoveTiming>& moves,
                               const std::vector<double>& draw_ms,
                               const std::vector<double>& busy_draw_ms = {});

// JSON: "name", "vertices", "machine" (cores, cpu), "summary" (the medians
// above), "moves" (solve_ms, skin_ms, frame_ms, iterations each),
// "layout_changes" and "opens" (init_ms, rigidity_ms, setup_ms, path_ms,
// wall_ms each), "draw_ms", "busy_draw_ms".
std::string TimingsJson(const std::string& name, int vertices,
                        const std::vector<LayoutTiming>& layouts,
                        const std::vector<MoveTiming>& moves, const std::vector<double>& draw_ms,
                        const std::vector<double>& busy_draw_ms);

// One line: "N moves: solve+skin median X ms (...), draw median Z ms; K layout changes:
// median W ms (rigidity R, setup S), F frames drawn meanwhile (longest L ms)".
std::string TimingsLine(const TimingSummary& summary);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_TIMING_REPORT_H_
