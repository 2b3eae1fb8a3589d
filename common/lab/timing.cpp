#include "timing.hpp"

#include <algorithm>
#include <fstream>
#include <string>

namespace ispars::lab {

double peak_rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

double now_seconds() {
  using clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double median_ns_per_call(std::size_t count, std::size_t batch, const std::function<void(std::size_t)>& call) {
  std::vector<double> per_call;
  for (std::size_t start = 0; start < count; start += batch) {
    const std::size_t end = std::min(count, start + batch);
    const double t0 = now_seconds();
    for (std::size_t i = start; i < end; ++i) call(i);
    const double t1 = now_seconds();
    per_call.push_back((t1 - t0) * 1e9 / static_cast<double>(end - start));
  }
  return median(std::move(per_call));
}

}  // namespace ispars::lab
