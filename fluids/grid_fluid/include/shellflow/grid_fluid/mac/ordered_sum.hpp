#pragma once
// ordered_sum: Σ term(i) for i in [0, n), in parallel but with the same bits on any number
// of threads: fixed chunks, each summed in order, then the chunks in order. An OpenMP
// reduction combines its partial sums in an unspecified order, and the metrics of a run
// resumed from a checkpoint must match an uninterrupted run's bit for bit.

#include <array>
#include <cstdint>

namespace shellflow::grid_fluid {

template <class Term>
double ordered_sum(std::int64_t n, Term term) {
  constexpr int kChunks = 64;
  std::array<double, kChunks> partial{};
#pragma omp parallel for schedule(static)
  for (int c = 0; c < kChunks; ++c) {
    double s = 0.0;
    for (std::int64_t i = n * c / kChunks; i < n * (c + 1) / kChunks; ++i) s += term(i);
    partial[c] = s;
  }
  double sum = 0.0;
  for (const double p : partial) sum += p;
  return sum;
}

}  // namespace shellflow::grid_fluid
