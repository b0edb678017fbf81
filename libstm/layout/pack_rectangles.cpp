#include "libstm/layout/pack_rectangles.h"

#include "libstm/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <limits>
#include <random>

namespace sdm {

namespace {

struct Box {
  int x, y, w, h;
};

enum class Orient { Free, Landscape, Portrait };
enum class Split { ShorterLeftover, LongerLeftover, MinArea, MaxArea };
enum class Score { BestShortSide, BestArea, BestLongSide };

struct Strategy {
  int order;
  Orient orient;
  Split split;
  Score score;
};

// One guillotine packing attempt of outer sizes (ow, oh) into an S x S square.
bool guillotine(const std::vector<std::array<int, 2>>& outer, const std::vector<int>& order, int S, const Strategy& st,
                std::vector<Box>& placed, std::vector<char>& rotated) {
  std::vector<Box> free{{0, 0, S, S}};
  placed.assign(outer.size(), Box{0, 0, 0, 0});
  rotated.assign(outer.size(), 0);
  for (int i : order) {
    long best_a = -1, best_b = -1;
    int best_f = -1;
    bool best_rot = false;
    // Orientation policies are preferences: the second pass allows either orientation.
    for (int pass = 0; pass < 2 && best_f < 0; ++pass) {
      if (pass == 1 && st.orient == Orient::Free) break;
      for (int r = 0; r < 2; ++r) {
        const int rw = r ? outer[i][1] : outer[i][0];
        const int rh = r ? outer[i][0] : outer[i][1];
        if (r && rw == rh) continue;
        if (pass == 0 && st.orient == Orient::Landscape && rw < rh) continue;
        if (pass == 0 && st.orient == Orient::Portrait && rw > rh) continue;
        for (size_t f = 0; f < free.size(); ++f) {
          const Box& F = free[f];
          if (rw > F.w || rh > F.h) continue;
          const long dw = F.w - rw, dh = F.h - rh;
          long a = 0, b = 0;
          switch (st.score) {
            case Score::BestShortSide: a = std::min(dw, dh), b = std::max(dw, dh); break;
            case Score::BestLongSide: a = std::max(dw, dh), b = std::min(dw, dh); break;
            case Score::BestArea: a = long(F.w) * F.h - long(rw) * rh, b = std::min(dw, dh); break;
          }
          if (best_f < 0 || a < best_a || (a == best_a && b < best_b)) best_a = a, best_b = b, best_f = int(f), best_rot = r;
        }
      }
    }
    if (best_f < 0) return false;
    const Box F = free[best_f];
    const int rw = best_rot ? outer[i][1] : outer[i][0];
    const int rh = best_rot ? outer[i][0] : outer[i][1];
    placed[i] = {F.x, F.y, rw, rh};
    rotated[i] = best_rot;
    free.erase(free.begin() + best_f);
    const int dw = F.w - rw, dh = F.h - rh;
    bool horizontal = false;  // true: the cut runs along x at y = F.y + rh (right piece is rh tall)
    switch (st.split) {
      case Split::ShorterLeftover: horizontal = dw <= dh; break;
      case Split::LongerLeftover: horizontal = dw > dh; break;
      case Split::MinArea: horizontal = long(rw) * dh > long(dw) * rh; break;
      case Split::MaxArea: horizontal = long(rw) * dh <= long(dw) * rh; break;
    }
    Box right, top;
    if (horizontal) {
      right = {F.x + rw, F.y, dw, rh};
      top = {F.x, F.y + rh, F.w, dh};
    } else {
      right = {F.x + rw, F.y, dw, F.h};
      top = {F.x, F.y + rh, rw, dh};
    }
    if (right.w > 0 && right.h > 0) free.push_back(right);
    if (top.w > 0 && top.h > 0) free.push_back(top);
  }
  return true;
}

struct Attempt {
  std::vector<Box> placed;
  std::vector<char> rotated;
  std::vector<std::array<int, 2>> inner;
};

// Calls `take(attempt)` for every strategy that packs the rectangles at scale s, in a fixed order,
// until it returns false; returns whether any packed.
template <class Take>
bool each_packing(const std::vector<Eigen::Vector2d>& sizes, double s, int S, int m, Take&& take) {
  const size_t n = sizes.size();
  Attempt out;
  bool any = false;
  std::vector<std::array<int, 2>> inner(n), outer(n);
  for (size_t i = 0; i < n; ++i) {
    inner[i] = {int(std::floor(s * sizes[i].x())), int(std::floor(s * sizes[i].y()))};
    if (inner[i][0] < 1 || inner[i][1] < 1) return false;
    outer[i] = {inner[i][0] + 2 * m, inner[i][1] + 2 * m};
    if (std::min(outer[i][0], outer[i][1]) > S) return false;
  }
  // Sort orders, all descending with the input index as the last key (determinism).
  auto key = [&](int o, int i) -> std::array<long, 3> {
    const long a = outer[i][0], b = outer[i][1];
    const long lo = std::min(a, b), hi = std::max(a, b);
    switch (o) {
      case 0: return {a * b, hi, lo};
      case 1: return {hi, lo, 0};
      case 2: return {a + b, hi, 0};
      case 3: return {lo, hi, 0};
      case 4: return {b, a, 0};
      default: return {a, b, 0};
    }
  };
  static const Orient orients[] = {Orient::Free, Orient::Landscape, Orient::Portrait};
  static const Split splits[] = {Split::ShorterLeftover, Split::LongerLeftover, Split::MinArea, Split::MaxArea};
  static const Score scores[] = {Score::BestShortSide, Score::BestArea, Score::BestLongSide};
  std::vector<int> order(n);
  for (int o = 0; o < 6; ++o) {
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return key(o, i) > key(o, j); });
    for (Orient orient : orients)
      for (Split split : splits)
        for (Score score : scores)
          if (guillotine(outer, order, S, {o, orient, split, score}, out.placed, out.rotated)) {
            out.inner = inner;
            any = true;
            if (!take(out)) return true;
          }
  }
  // Few rectangles leave the sorted orders few chances: also try fixed pseudo-random orders
  // (a fixed seed keeps the result deterministic).
  std::mt19937 rng(20240601u);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return key(0, i) > key(0, j); });
  for (int k = 0; k < 64 && n > 2; ++k) {
    std::shuffle(order.begin(), order.end(), rng);
    for (Split split : splits)
      for (Score score : scores)
        if (guillotine(outer, order, S, {0, Orient::Free, split, score}, out.placed, out.rotated)) {
          out.inner = inner;
          any = true;
          if (!take(out)) return true;
        }
  }
  return any;
}

// The first packing at scale s, into `out`.
bool try_scale(const std::vector<Eigen::Vector2d>& sizes, double s, int S, int m, Attempt& out) {
  return each_packing(sizes, s, S, m, [&](const Attempt& a) {
    out = a;
    return false;
  });
}

// The most a rectangle's side grows: a layout's reader refuses rectangles over twice their
// capsule's size at the layout's scale (a tampered radius), so growth stays under that.
constexpr double kMaxGrowth = 1.95;

// Grows the placed outer boxes into free space (see the header); inner = outer - 2 margin.
void grow(std::vector<Box>& box, int S, int m, double max_aniso) {
  const size_t n = box.size();
  const std::vector<Box> start = box;
  auto overlaps = [&](const Box& a, const Box& b) {
    return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
  };
  for (int round = 0; round < 64; ++round) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i)
      for (int dir = 0; dir < 4; ++dir) {
        Box& B = box[i];
        // Growth bound from the anisotropy: this side's factor may reach max_aniso times the other's.
        const bool along_x = dir % 2 == 0;
        // (on inner sizes: the margins do not grow)
        const double other = along_x ? double(B.h - 2 * m) / (start[i].h - 2 * m) : double(B.w - 2 * m) / (start[i].w - 2 * m);
        const int cur = (along_x ? B.w : B.h) - 2 * m, base = (along_x ? start[i].w : start[i].h) - 2 * m;
        int room = int(std::floor(std::min(max_aniso * other, kMaxGrowth) * base + 1e-9)) - cur;
        // Free space: the atlas border and every other box in the way.
        if (dir == 0) room = std::min(room, S - (B.x + B.w));
        if (dir == 1) room = std::min(room, S - (B.y + B.h));
        if (dir == 2) room = std::min(room, B.x);
        if (dir == 3) room = std::min(room, B.y);
        if (room <= 0) continue;
        Box sweep = B;  // the strip the side would sweep over
        if (dir == 0) sweep = {B.x + B.w, B.y, room, B.h};
        if (dir == 1) sweep = {B.x, B.y + B.h, B.w, room};
        if (dir == 2) sweep = {B.x - room, B.y, room, B.h};
        if (dir == 3) sweep = {B.x, B.y - room, B.w, room};
        for (size_t j = 0; j < n && room > 0; ++j) {
          if (j == i || !overlaps(sweep, box[j])) continue;
          const Box& o = box[j];
          if (dir == 0) room = std::min(room, o.x - (B.x + B.w));
          if (dir == 1) room = std::min(room, o.y - (B.y + B.h));
          if (dir == 2) room = std::min(room, B.x - (o.x + o.w));
          if (dir == 3) room = std::min(room, B.y - (o.y + o.h));
          if (dir == 0) sweep.w = room;
          if (dir == 1) sweep.h = room;
          if (dir == 2) sweep = {B.x - room, B.y, room, B.h};
          if (dir == 3) sweep = {B.x, B.y - room, B.w, room};
        }
        if (room <= 0) continue;
        if (dir == 0) B.w += room;
        if (dir == 1) B.h += room;
        if (dir == 2) B.x -= room, B.w += room;
        if (dir == 3) B.y -= room, B.h += room;
        changed = true;
      }
    if (!changed) break;
  }
}

// How many of the packings that fit at the final scale are grown to find the fullest: the first
// packing alone left a strip of 18 % of the atlas on the scanned Stanford bunny (14 rectangles,
// coverage 0.83) that other packings at the same scale let their neighbours fill (0.98; DECISIONS
// 3, "Packing: the fullest of several packings").
constexpr int kGrownPackings = 8;  // at least
// More for few rectangles, whose growth is cheap (it compares every pair of rectangles each round):
// as many as keep (packings x rectangles^2) within this.
constexpr double kGrowthBudget = 2e5;

// Of the first packings at scale s (as many as the two constants above allow), the one that
// covers most of the atlas once grown (the first of equals), with its inner sizes updated.
Attempt best_grown(const std::vector<Eigen::Vector2d>& sizes, double s, int S, int m, double max_aniso) {
  Attempt best;
  long best_area = -1;
  int tried = 0;
  const double n = double(sizes.size());
  const int packings = std::max(kGrownPackings, int(kGrowthBudget / (n * n)));
  each_packing(sizes, s, S, m, [&](const Attempt& a) {
    Attempt g = a;
    grow(g.placed, S, m, max_aniso);
    long area = 0;
    for (const Box& b : g.placed) area += long(b.w) * b.h;
    if (area > best_area) best_area = area, best = std::move(g);
    return ++tried < packings;
  });
  for (size_t i = 0; i < sizes.size(); ++i) {
    const Box& b = best.placed[i];
    best.inner[i] = best.rotated[i] ? std::array<int, 2>{b.h - 2 * m, b.w - 2 * m} : std::array<int, 2>{b.w - 2 * m, b.h - 2 * m};
  }
  return best;
}

}  // namespace

Packing pack_rectangles(const std::vector<Eigen::Vector2d>& sizes_in, int atlas_size, int margin, double max_anisotropy) {
  if (atlas_size < 1) throw InputError("atlas size must be positive, got " + std::to_string(atlas_size));
  if (margin < 0) throw InputError("margin must not be negative, got " + std::to_string(margin));
  if (sizes_in.empty()) throw InputError("no rectangle to pack");
  double area = 0, max_side = 0;
  for (const auto& s : sizes_in) {
    if (!(s.x() > 0) || !(s.y() > 0) || !std::isfinite(s.x()) || !std::isfinite(s.y()))
      throw InputError("rectangle sizes must be positive and finite");
    area += s.x() * s.y();
    max_side = std::max(max_side, std::max(s.x(), s.y()));
  }
  // The best scale puts some rectangle exactly on a texel step; rounding the sizes to 2^-30 of the
  // largest keeps float noise in the input (a rotated copy of the mesh) from flipping that step.
  const double quantum = std::ldexp(max_side, -30);
  std::vector<Eigen::Vector2d> sizes(sizes_in.size());
  for (size_t i = 0; i < sizes.size(); ++i)
    sizes[i] = {std::max(quantum, std::round(sizes_in[i].x() / quantum) * quantum),
                std::max(quantum, std::round(sizes_in[i].y() / quantum) * quantum)};
  const double S = atlas_size;
  // Upper bound: inner areas alone fill the atlas, and the longest side fits.
  double hi = std::min(S / std::sqrt(area), (S - 2 * margin) / max_side) * (1 + 1e-9);
  Attempt best;
  double lo = 0;
  bool found = false;
  auto bisect = [&](double top) {
    for (int it = 0; it < 60 && top - lo > 1e-7 * top; ++it) {
      const double mid = 0.5 * (lo + top);
      Attempt a;
      if (try_scale(sizes, mid, atlas_size, margin, a)) {
        lo = mid, best = std::move(a), found = true;
      } else {
        top = mid;
      }
    }
  };
  bisect(hi);
  if (!found) {
    Attempt a;
    if (lo > 0 && try_scale(sizes, lo, atlas_size, margin, a)) best = std::move(a), found = true;
  }
  // Feasibility is not monotone where one rectangle is far smaller than the others (a speck beside
  // the model): below the scale that gives it a whole texel nothing fits, so a bisection from 0
  // never sees the feasible range above it. Search again from that scale.
  if (!found) {
    double least = 0;
    for (const auto& z : sizes) least = std::max(least, 1 / z.minCoeff());
    least *= 1 + 1e-12;
    Attempt a;
    if (least < hi && try_scale(sizes, least, atlas_size, margin, a)) {
      lo = least, best = std::move(a), found = true;
      bisect(hi);
    }
  }
  // Inner sizes are whole texels, so feasibility only changes where some floor(s * size) steps:
  // climb those steps from the binary search's answer while the rectangles still fit.
  for (int step = 0; found && step < 64; ++step) {
    double next = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < sizes.size(); ++i)
      for (double side : {sizes[i].x(), sizes[i].y()}) next = std::min(next, (std::floor(lo * side) + 1) / side);
    next *= 1 + 1e-12;
    Attempt a;
    if (!try_scale(sizes, next, atlas_size, margin, a)) break;
    lo = next, best = std::move(a);
  }
  if (!found)
    throw InputError("the " + std::to_string(sizes.size()) + " rectangles do not fit into a " + std::to_string(atlas_size) +
                     "^2 atlas with a margin of " + std::to_string(margin) + " texels; use a larger --size or a smaller margin");
  if (max_anisotropy > 1) best = best_grown(sizes, lo, atlas_size, margin, max_anisotropy);
  Packing p;
  p.scale = lo;
  p.rects.resize(sizes.size());
  double outer_area = 0, inner_area = 0;
  for (size_t i = 0; i < sizes.size(); ++i) {
    PackedRect& r = p.rects[i];
    r.x = best.placed[i].x + margin;
    r.y = best.placed[i].y + margin;
    r.w = best.inner[i][0];
    r.h = best.inner[i][1];
    r.rotated = best.rotated[i];
    outer_area += double(r.w + 2 * margin) * (r.h + 2 * margin);
    inner_area += double(r.w) * r.h;
  }
  p.coverage = outer_area / (S * S);
  p.coverage_inner = inner_area / (S * S);
  return p;
}

}  // namespace sdm
