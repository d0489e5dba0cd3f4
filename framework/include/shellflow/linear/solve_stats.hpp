#pragma once
// SolveStats: what a linear solve reports (the grid fluid writes it to metrics.csv).

namespace shellflow::linear {

/// Outcome of one linear solve.
struct SolveStats {
  /// Iterations taken (0 for a direct solve, or when the initial guess already met the tolerance).
  int iterations = 0;
  /// |b - A x|_2 / |b|_2 of the returned x, recomputed from A (not the recursive residual);
  /// 0 when b = 0 (then x = 0).
  double relative_residual = 0.0;
  /// True when relative_residual <= the requested tolerance (direct solve: always true
  /// once the factorisation succeeded).
  bool converged = false;
};

}  // namespace shellflow::linear
