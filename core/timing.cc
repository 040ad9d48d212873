#include "msdeform/core/timing.h"

#include <algorithm>

namespace msdeform {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void StageTimes::Add(const std::string& name, double ms) {
  for (auto& [stage, total] : entries_) {
    if (stage == name) {
      total += ms;
      return;
    }
  }
  entries_.emplace_back(name, ms);
}

double StageTimes::Get(const std::string& name) const {
  for (const auto& [stage, ms] : entries_)
    if (stage == name) return ms;
  return 0.0;
}

void StageTimes::Append(const StageTimes& other, const std::string& prefix) {
  for (const auto& [stage, ms] : other.entries_) Add(prefix + stage, ms);
}

}  // namespace msdeform
