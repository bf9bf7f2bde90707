// Keeps a bounded, evenly spaced sample of a stream (cmc check echoes at most
// kMaxEchoedRows of a prediction's rows and of the evaluation points in check.json).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace cmc::check {

// Keeps at most `cap` items of a stream, evenly spaced: every stride-th one (the stride
// doubles whenever more would be kept) and the last.
template <class T>
class Sampler {
 public:
  explicit Sampler(std::size_t cap) : cap_(std::max<std::size_t>(cap, 2)) {}
  void add(const T& v) {
    last_in_ = count_++ % stride_ == 0;
    if (last_in_) {
      kept_.push_back(v);
      if (kept_.size() >= cap_) {  // keep every other one, leaving room for the last
        std::size_t j = 0;
        for (std::size_t i = 0; i < kept_.size(); i += 2) kept_[j++] = kept_[i];
        kept_.resize(j);
        stride_ *= 2;
        last_in_ = (count_ - 1) % stride_ == 0;
      }
    }
    last_ = v;
  }
  std::vector<T> take() const {
    std::vector<T> out = kept_;
    if (count_ && !last_in_) out.push_back(last_);
    return out;
  }
  std::size_t stride() const { return stride_; }

 private:
  std::size_t cap_, stride_ = 1, count_ = 0;
  std::vector<T> kept_;
  T last_{};
  bool last_in_ = false;
};

}  // namespace cmc::check
