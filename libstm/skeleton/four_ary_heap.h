#pragma once
/// A four-ary min-heap with a sweep for lazily deleted entries: the priority queue of connectivity
/// surgery (surgery.cpp). A collapse there invalidates the queued entries of the vertices it touches
/// and queues them anew, so most entries go stale before they reach the top. Four-ary: a pop sifts
/// through half the levels of a binary heap, and pops (mostly of stale entries) dominate.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>

namespace sdm {

/// Pops the smallest entry under `Less` first (std::greater gives a max-heap). Entries with equal
/// keys pop in an unspecified order: give them distinct keys for a deterministic order.
template <class T, class Less = std::less<T>>
class FourAryHeap {
 public:
  bool empty() const { return heap_.empty(); }
  size_t size() const { return heap_.size(); }

  void push(const T& e) {
    size_t at = heap_.size();
    heap_.push_back(e);
    while (at > 0) {
      const size_t up = (at - 1) / 4;
      if (!later(heap_[up], e)) break;
      heap_[at] = heap_[up];
      at = up;
    }
    heap_[at] = e;
  }

  /// Removes and returns the smallest entry. The heap must not be empty.
  T pop() {
    const T top = heap_.front();
    heap_.front() = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0);
    return top;
  }

  /// Removes every entry for which stale(e) holds, then restores the heap order bottom-up (a few
  /// comparisons per entry, against a sift through the heap for each stale entry popped).
  template <class Stale>
  void sweep(Stale stale) {
    heap_.erase(std::remove_if(heap_.begin(), heap_.end(), stale), heap_.end());
    for (size_t at = heap_.size() / 4 + 1; at-- > 0;)
      if (at < heap_.size()) sift_down(at);
  }

 private:
  /// x comes out after y.
  bool later(const T& x, const T& y) const { return less_(y, x); }

  void sift_down(size_t at) {
    const size_t size = heap_.size();
    const T e = heap_[at];
    for (;;) {
      const size_t first = 4 * at + 1;
      if (first >= size) break;
      size_t best = first;
      for (size_t c = first + 1; c < std::min(first + 4, size); ++c)
        if (later(heap_[best], heap_[c])) best = c;
      if (!later(e, heap_[best])) break;
      heap_[at] = heap_[best];
      at = best;
    }
    heap_[at] = e;
  }

  std::vector<T> heap_;
  Less less_;
};

}  // namespace sdm
