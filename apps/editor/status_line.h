// The editor's status line: one message, and the condition it describes. A
// message about the handle layout goes once that condition ends, so that
// "no moveable handle" does not stay up over a handle that is there; other
// messages ("wrote ...", errors) stay until the next one replaces them.

#ifndef MSDEFORM_APPS_EDITOR_STATUS_LINE_H_
#define MSDEFORM_APPS_EDITOR_STATUS_LINE_H_

#include <string>

#include "apps/editor/edit_session.h"

namespace msdeform {
namespace editor {

// When a message goes by itself.
enum class Until {
  kReplaced,        // only when another message replaces it
  kMoveableHandle,  // the committed layout has a moveable handle
  kSetUp,           // no layout (or mesh) is being set up
};

class StatusLine {
 public:
  void Show(std::string text, Until until = Until::kReplaced);
  void Clear() { Show(""); }
  // Drops the message when the condition it describes has ended in
  // `session`; call once a frame, after EditSession::Poll.
  void Update(const EditSession& session);
  const std::string& text() const { return text_; }

 private:
  std::string text_;
  Until until_ = Until::kReplaced;
};

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_STATUS_LINE_H_
