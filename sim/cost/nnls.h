// Non-negative least squares (Lawson & Hanson 1974), for calibration: coefficients of a pass
// must be >= 0 so every pass is non-decreasing in each counter.
#pragma once
#include <vector>

namespace fovsim {

// Minimises ||A x - b|| subject to x >= 0. A is row-major rows x cols. Small dense problems.
std::vector<double> nnls(const std::vector<double>& A, int rows, int cols,
                         const std::vector<double>& b, int max_iter = 500);

}  // namespace fovsim
