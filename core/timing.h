// Small helpers for the timings every executable reports.

#ifndef MSDEFORM_CORE_TIMING_H_
#define MSDEFORM_CORE_TIMING_H_

#include <chrono>
#include <vector>

namespace msdeform {

// Wall-clock milliseconds from `start` to now.
double MillisecondsSince(std::chrono::steady_clock::time_point start);

// The median of `values` (the mean of the two middle ones for an even count;
// 0 for none).
double Median(std::vector<double> values);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_TIMING_H_
