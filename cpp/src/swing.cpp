#include "swing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pydrill::detail {
namespace {

// Times the bit velocity crosses `level` upwards (linear interpolation between samples).
std::vector<double> upward_crossings(const Trace& tr, double level) {
  std::vector<double> ups;
  for (std::size_t i = 1; i < tr.t.size(); ++i) {
    const double a = tr.bit[i - 1] - level, b = tr.bit[i] - level;
    if (a < 0 && b >= 0) ups.push_back(tr.t[i - 1] + (tr.t[i] - tr.t[i - 1]) * (-a) / (b - a));
  }
  return ups;
}

double span(const Trace& tr, double t0, double t1) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.t[i] < t0 || tr.t[i] > t1) continue;
    lo = std::min(lo, tr.bit[i]);
    hi = std::max(hi, tr.bit[i]);
  }
  return hi >= lo ? hi - lo : 0.0;
}

}  // namespace

double crossing_period(const Trace& tr, double level) {
  const std::vector<double> ups = upward_crossings(tr, level);
  if (ups.size() < 2) return -1.0;
  return (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
}

double longest_cycle(const Trace& tr, double level, double t0, double t1, double slowest) {
  std::vector<double> ups = upward_crossings(tr, level);
  ups.erase(std::remove_if(ups.begin(), ups.end(), [&](double t) { return t < t0 || t > t1; }),
            ups.end());
  if (ups.size() < 5) return slowest;
  double longest = 0.0;
  for (std::size_t i = 1; i < ups.size(); ++i) longest = std::max(longest, ups[i] - ups[i - 1]);
  return longest;
}

double swing_trend(const Trace& tr, double t0, double t1, double floor, double& last) {
  constexpr int kParts = 4;
  const double h = (t1 - t0) / kParts;
  double x[kParts], y[kParts];
  for (int q = 0; q < kParts; ++q) {
    x[q] = (q + 0.5) / kParts;
    last = span(tr, t0 + q * h, t0 + (q + 1) * h);
    y[q] = std::log(std::max(last, floor));
  }
  double xm = 0.0, ym = 0.0;
  for (int q = 0; q < kParts; ++q) xm += x[q] / kParts, ym += y[q] / kParts;
  double sxy = 0.0, sxx = 0.0;
  for (int q = 0; q < kParts; ++q) sxy += (x[q] - xm) * (y[q] - ym), sxx += (x[q] - xm) * (x[q] - xm);
  return sxy / sxx;
}

double sampled_mean(const Trace& tr, double a, double b) {
  double area = 0.0, length = 0.0;
  for (std::size_t i = 1; i < tr.t.size(); ++i) {
    const double t0 = std::max(tr.t[i - 1], a), t1 = std::min(tr.t[i], b);
    if (!(t1 > t0)) continue;
    const double h = tr.t[i] - tr.t[i - 1];
    const auto at = [&](double t) {
      return tr.bit[i - 1] + (tr.bit[i] - tr.bit[i - 1]) * (t - tr.t[i - 1]) / h;
    };
    area += 0.5 * (at(t0) + at(t1)) * (t1 - t0);
    length += t1 - t0;
  }
  return length > 0.0 ? area / length : 0.0;
}

}  // namespace pydrill::detail
