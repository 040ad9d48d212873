#include "apps/editor/status_line.h"

#include <utility>

namespace msdeform {
namespace editor {

void StatusLine::Show(std::string text, Until until) {
  text_ = std::move(text);
  until_ = until;
}

void StatusLine::Update(const EditSession& session) {
  bool ended = false;
  switch (until_) {
    case Until::kReplaced:
      break;
    case Until::kMoveableHandle:
      ended = !session.committed_layout().moveable.empty();
      break;
    case Until::kSetUp:
      ended = !session.busy();
      break;
  }
  if (ended) Clear();
}

}  // namespace editor
}  // namespace msdeform
