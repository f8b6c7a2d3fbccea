#include "libvdbappear/procedural/weave_pattern.h"

#include <fmt/format.h>

#include <numeric>
#include <stdexcept>

namespace vdbappear {

namespace {

template <typename OverFn>
std::vector<char> table(int repeat, OverFn over) {
  std::vector<char> t(std::size_t(repeat) * repeat);
  for (int i = 0; i < repeat; ++i)
    for (int j = 0; j < repeat; ++j) t[std::size_t(i) * repeat + j] = over(i, j);
  return t;
}

}  // namespace

WeavePattern WeavePattern::plain() {
  return {2, table(2, [](int i, int j) { return (i + j) % 2 == 0; })};
}

WeavePattern WeavePattern::twill(int n) {
  if (n < 3) throw std::invalid_argument(fmt::format("a twill needs at least 3 harnesses, got {}", n));
  const int floats = (n + 1) / 2;
  return {n, table(n, [=](int i, int j) { return (j - i + n) % n < floats; })};
}

WeavePattern WeavePattern::satin(int n) {
  if (n < 5) throw std::invalid_argument(fmt::format("a satin needs at least 5 harnesses, got {}", n));
  int step = 2;
  while (step <= n - 2 && std::gcd(step, n) != 1) ++step;
  if (step > n - 2) throw std::invalid_argument(fmt::format("there is no regular satin with {} harnesses", n));
  return {n, table(n, [=](int i, int j) { return (j - step * i % n + n) % n != 0; })};
}

const std::vector<std::string>& WeavePattern::names() {
  static const std::vector<std::string> all{"plain", "twill", "satin"};
  return all;
}

WeavePattern WeavePattern::byName(const std::string& name, int harness) {
  if (name == "plain") return plain();
  if (name == "twill") return twill(harness > 0 ? harness : 4);
  if (name == "satin") return satin(harness > 0 ? harness : 5);
  throw std::invalid_argument(fmt::format("unknown weave pattern '{}' (plain, twill or satin)", name));
}

WeavePattern WeavePattern::mirrored() const {
  return {repeat_, table(repeat_, [this](int i, int j) { return warpOver(i, repeat_ - 1 - j); })};
}

WeavePattern WeavePattern::transposed() const {
  return {repeat_, table(repeat_, [this](int i, int j) { return !warpOver(j, i); })};
}

double WeavePattern::warpOverFraction() const {
  return double(std::accumulate(over_.begin(), over_.end(), 0)) / double(over_.size());
}

}  // namespace vdbappear
