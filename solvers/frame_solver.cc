#include "msdeform/solvers/frame_solver.h"

#include <cmath>
#include <utility>

namespace msdeform {

bool StoppingRule::Check(std::string* error) const {
  return StoppingRuleTable().CheckRanges(*this, error);  // the rows' ranges (frame_solver.h)
}

const OptionTable<StoppingRule>& StoppingRuleTable() {
  static const OptionTable<StoppingRule>& table =
      MakeOptionTable<StoppingRule>([](auto& t) { DeclareStoppingRuleRows(t); });
  return table;
}

}  // namespace msdeform
