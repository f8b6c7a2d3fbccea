#pragma once
// Weave patterns: which yarn lies on top at each crossing of warp yarn i and weft yarn j, on a
// periodic repeat x repeat table (the "weave draft").

#include <string>
#include <vector>

namespace vdbappear {

class WeavePattern {
 public:
  // 1/1: warp over weft where i + j is even.
  static WeavePattern plain();
  // n-harness twill: each warp floats over ceil(n/2) wefts, under the rest, and the float steps by
  // one weft per warp, which gives the diagonal wale. n >= 3.
  static WeavePattern twill(int harness);
  // n-harness warp-faced satin: each warp goes under one weft in n; the under-points step by the
  // smallest counter s in [2, n-2] coprime with n, so none touch. n >= 5, n != 6 (no such s).
  static WeavePattern satin(int harness);
  // "plain", "twill" or "satin"; harness 0 picks the default (twill 4, satin 5).
  static WeavePattern byName(const std::string& name, int harness = 0);
  static const std::vector<std::string>& names();

  WeavePattern mirrored() const;    // the wale runs the other way
  WeavePattern transposed() const;  // warp-faced <-> weft-faced

  int repeat() const { return repeat_; }
  bool warpOver(int warp, int weft) const { return over_[index(warp) * repeat_ + index(weft)]; }
  double warpOverFraction() const;  // share of crossings with the warp on top

 private:
  WeavePattern(int repeat, std::vector<char> over) : repeat_(repeat), over_(std::move(over)) {}
  int index(int k) const { return ((k % repeat_) + repeat_) % repeat_; }
  int repeat_;
  std::vector<char> over_;  // row-major [warp][weft]
};

}  // namespace vdbappear
