// Small helpers for the timings every executable reports.

#ifndef MSDEFORM_CORE_TIMING_H_
#define MSDEFORM_CORE_TIMING_H_

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace msdeform {

// Wall-clock milliseconds from `start` to now.
double MillisecondsSince(std::chrono::steady_clock::time_point start);

// The median of `values` (the mean of the two middle ones for an even count;
// 0 for none).
double Median(std::vector<double> values);

// Wall-clock milliseconds of named stages, in the order they ran (a
// precompute's lattice, graphs, ...; the report's timings_ms.stages). A stage
// timed twice adds up.
class StageTimes {
 public:
  void Add(const std::string& name, double ms);
  // Milliseconds of `name`, 0 where it never ran.
  double Get(const std::string& name) const;
  const std::vector<std::pair<std::string, double>>& entries() const { return entries_; }
  // Appends every stage of `other` (its names prefixed by `prefix`).
  void Append(const StageTimes& other, const std::string& prefix = "");

 private:
  std::vector<std::pair<std::string, double>> entries_;
};

// Adds the time from construction to destruction to `times` (may be null) as
// stage `name`.
class ScopedStage {
 public:
  ScopedStage(StageTimes* times, const char* name)
      : times_(times), name_(name), start_(std::chrono::steady_clock::now()) {}
  ~ScopedStage() {
    if (times_ != nullptr) times_->Add(name_, MillisecondsSince(start_));
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  StageTimes* times_;
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace msdeform

#endif  // MSDEFORM_CORE_TIMING_H_
