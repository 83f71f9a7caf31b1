#include "sim/experiment/search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"

namespace fovsim {

Searcher::Searcher(std::vector<SearchDim> space, bool maximize, uint64_t seed, int batch)
    : dims_(std::move(space)),
      maximize_(maximize),
      batch_(std::max(1, batch)),
      rng_(seed, 0x5ea6c4) {
  // Stop when the step is below the resolution of every dimension (the finest one decides).
  min_step_ = 0.125;
  for (auto& d : dims_) {
    double span = d.hi - d.lo, res = 1e-3;
    if (!d.log && d.step > 0 && span > 0) res = std::max(res, 0.5 * d.step / span);
    if (!d.log && d.integer && span > 0) res = std::max(res, 0.5 / span);
    min_step_ = std::min(min_step_, res);
  }
  min_step_ = std::min(min_step_, 0.125);
}

std::vector<double> Searcher::to_real(const std::vector<double>& u) const {
  std::vector<double> x(dims_.size());
  for (size_t i = 0; i < dims_.size(); ++i) {
    const auto& d = dims_[i];
    double t = std::clamp(u[i], 0.0, 1.0);
    double v = d.log ? std::exp(std::log(d.lo) + t * (std::log(d.hi) - std::log(d.lo)))
                     : d.lo + t * (d.hi - d.lo);
    if (d.step > 0) v = std::min(d.hi, d.lo + std::round((v - d.lo) / d.step) * d.step);
    if (d.integer) v = std::min(std::floor(d.hi), std::max(std::ceil(d.lo), std::round(v)));
    x[i] = tidy(std::clamp(v, d.lo, d.hi));
  }
  return x;
}

std::vector<double> Searcher::to_unit(const std::vector<double>& x) const {
  std::vector<double> u(dims_.size());
  for (size_t i = 0; i < dims_.size(); ++i) {
    const auto& d = dims_[i];
    u[i] = d.log ? (std::log(x[i]) - std::log(d.lo)) / (std::log(d.hi) - std::log(d.lo))
                 : (x[i] - d.lo) / (d.hi - d.lo);
  }
  return u;
}

std::string Searcher::key(const std::vector<double>& x) const {
  std::string k;
  char buf[32];
  for (double v : x) {
    std::snprintf(buf, sizeof buf, "%.9g;", v);
    k += buf;
  }
  return k;
}

bool Searcher::better(const SearchEval& a, const SearchEval& b) const {
  bool fa = a.violation <= 0, fb = b.violation <= 0;
  if (fa != fb) return fa;
  if (!fa) return a.violation < b.violation;
  if (std::isnan(b.score)) return !std::isnan(a.score);
  if (std::isnan(a.score)) return false;
  return maximize_ ? a.score > b.score : a.score < b.score;
}

std::vector<std::vector<double>> Searcher::ask() {
  std::vector<std::vector<double>> out;
  auto push = [&](const std::vector<double>& u) {
    auto x = to_real(u);
    std::string k = key(x);
    if (seen_.count(k)) return;
    seen_[k] = true;
    out.push_back(std::move(x));
  };
  const size_t d = dims_.size();
  if (!started_) {
    started_ = true;
    // Initial design: a Latin hypercube of max(batch, 2) points.
    size_t n = size_t(std::max(batch_, 2));
    std::vector<std::vector<double>> u(n, std::vector<double>(d));
    for (size_t j = 0; j < d; ++j) {
      std::vector<size_t> perm(n);
      for (size_t i = 0; i < n; ++i) perm[i] = i;
      for (size_t i = n; i > 1; --i) std::swap(perm[i - 1], perm[rng_.below(uint32_t(i))]);
      for (size_t i = 0; i < n; ++i) u[i][j] = (double(perm[i]) + rng_.uniform()) / double(n);
    }
    for (auto& p : u) push(p);
    improved_ = true;
    return out;
  }
  if (!has_best_) return out;
  for (int attempt = 0; attempt < 64 && out.empty(); ++attempt) {
    if (!improved_) step_ *= 0.5;
    improved_ = false;
    if (step_ < min_step_) return out;
    auto c = to_unit(best_.x);
    // Compass directions first, then seeded perturbations inside the step box.
    for (size_t j = 0; j < d && int(out.size()) < batch_; ++j)
      for (double s : {+1.0, -1.0}) {
        if (int(out.size()) >= batch_) break;
        auto u = c;
        u[j] = std::clamp(u[j] + s * step_, 0.0, 1.0);
        push(u);
      }
    for (int tries = 0; int(out.size()) < batch_ && tries < 4 * batch_; ++tries) {
      auto u = c;
      for (size_t j = 0; j < d; ++j)
        u[j] = std::clamp(u[j] + step_ * (2 * rng_.uniform() - 1), 0.0, 1.0);
      push(u);
    }
  }
  return out;
}

void check_told(const std::vector<SearchDim>& space, const SearchEval& e, const std::string& where,
                bool values) {
  if (e.x.size() != space.size())
    throw Error(where, "the point has " + std::to_string(e.x.size()) + " values, the space " +
                           std::to_string(space.size()) + " dimensions");
  for (size_t d = 0; d < space.size(); ++d) {
    const SearchDim& s = space[d];
    // A relative slack of 1e-12: points ask() returned went through the same arithmetic.
    const double slack = 1e-12 * std::max(std::fabs(s.lo), std::fabs(s.hi));
    if (!(e.x[d] >= s.lo - slack && e.x[d] <= s.hi + slack))
      throw Error(where, s.path + " = " + format_number(e.x[d]) + " is outside the search space [" +
                             format_number(s.lo) + ", " + format_number(s.hi) + "]");
  }
  if (!values) return;
  if (!std::isfinite(e.score))
    throw Error(where, "score " + format_number(e.score) +
                           " is not a finite number (a point that could not be scored: a finite "
                           "score with violation=inf)");
  if (!(e.violation >= 0))
    throw Error(where, "violation " + format_number(e.violation) +
                           " is not a number >= 0 (0 = feasible, inf = infinitely violated)");
}

void Searcher::tell(const std::vector<SearchEval>& evals) {
  for (auto& e : evals) {
    seen_[key(e.x)] = true;
    history_.push_back(e);
    if (!has_best_ || better(e, best_)) {
      best_ = e;
      has_best_ = true;
      improved_ = true;
    }
  }
}

}  // namespace fovsim
