#include "sim/cost/nnls.h"

#include <algorithm>
#include <cmath>

namespace fovsim {

namespace {
// Unconstrained least squares on the columns in `set` via normal equations (Gaussian
// elimination with partial pivoting); columns not in `set` are 0.
std::vector<double> ls_subset(const std::vector<double>& A, int m, int n,
                              const std::vector<double>& b, const std::vector<char>& set) {
  std::vector<int> idx;
  for (int j = 0; j < n; ++j)
    if (set[j]) idx.push_back(j);
  const int k = int(idx.size());
  std::vector<double> M(size_t(k) * (k + 1), 0.0);
  for (int a = 0; a < k; ++a) {
    for (int c = 0; c < k; ++c) {
      double s = 0;
      for (int i = 0; i < m; ++i) s += A[size_t(i) * n + idx[a]] * A[size_t(i) * n + idx[c]];
      M[size_t(a) * (k + 1) + c] = s;
    }
    double s = 0;
    for (int i = 0; i < m; ++i) s += A[size_t(i) * n + idx[a]] * b[i];
    M[size_t(a) * (k + 1) + k] = s;
  }
  for (int c = 0; c < k; ++c) {
    int piv = c;
    for (int r = c + 1; r < k; ++r)
      if (std::fabs(M[size_t(r) * (k + 1) + c]) > std::fabs(M[size_t(piv) * (k + 1) + c])) piv = r;
    if (piv != c)
      for (int q = 0; q <= k; ++q)
        std::swap(M[size_t(c) * (k + 1) + q], M[size_t(piv) * (k + 1) + q]);
    double d = M[size_t(c) * (k + 1) + c];
    if (std::fabs(d) < 1e-300) continue;
    for (int r = 0; r < k; ++r) {
      if (r == c) continue;
      double f = M[size_t(r) * (k + 1) + c] / d;
      if (f == 0) continue;
      for (int q = c; q <= k; ++q) M[size_t(r) * (k + 1) + q] -= f * M[size_t(c) * (k + 1) + q];
    }
  }
  std::vector<double> x(n, 0.0);
  for (int a = 0; a < k; ++a) {
    double d = M[size_t(a) * (k + 1) + a];
    x[idx[a]] = std::fabs(d) < 1e-300 ? 0.0 : M[size_t(a) * (k + 1) + k] / d;
  }
  return x;
}
}  // namespace

std::vector<double> nnls(const std::vector<double>& A, int m, int n, const std::vector<double>& b,
                         int max_iter) {
  std::vector<double> x(n, 0.0);
  std::vector<char> P(n, 0);
  auto gradient = [&](std::vector<double>& w) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) {
      double s = b[i];
      for (int j = 0; j < n; ++j) s -= A[size_t(i) * n + j] * x[j];
      r[i] = s;
    }
    for (int j = 0; j < n; ++j) {
      double s = 0;
      for (int i = 0; i < m; ++i) s += A[size_t(i) * n + j] * r[i];
      w[j] = s;
    }
  };
  std::vector<double> w(n);
  const double tol = 1e-12;
  for (int it = 0; it < max_iter; ++it) {
    gradient(w);
    int jmax = -1;
    double wmax = tol;
    for (int j = 0; j < n; ++j)
      if (!P[j] && w[j] > wmax) wmax = w[j], jmax = j;
    if (jmax < 0) break;
    P[jmax] = 1;
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      std::vector<double> z = ls_subset(A, m, n, b, P);
      bool feasible = true;
      for (int j = 0; j < n; ++j)
        if (P[j] && z[j] <= 0) feasible = false;
      if (feasible) {
        x = z;
        break;
      }
      double alpha = 1.0;
      for (int j = 0; j < n; ++j)
        if (P[j] && z[j] <= 0) alpha = std::min(alpha, x[j] / (x[j] - z[j]));
      for (int j = 0; j < n; ++j) {
        x[j] += alpha * (z[j] - x[j]);
        if (P[j] && x[j] <= 1e-15) P[j] = 0, x[j] = 0;
      }
    }
  }
  return x;
}

}  // namespace fovsim
