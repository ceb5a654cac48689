// The statistic the metric benchmarks report as "_min" besides the mean: on
// a shared machine a burst of other work slows one run, and OctoMap's single
// long iterations suffer most; the ratio of the minima is the sturdier
// comparison.
#pragma once

#include <algorithm>
#include <vector>

namespace sarmap::bench {

inline double fastest(const std::vector<double>& runs) { return *std::min_element(runs.begin(), runs.end()); }

}  // namespace sarmap::bench
