#pragma once
// Below this many unknowns the OpenMP fork/join costs more than a vector loop (small
// enclosed regions and coarse multigrid levels), so those loops run on one thread.

namespace shellflow::linear::detail {

constexpr int kParallelThreshold = 8192;

}  // namespace shellflow::linear::detail
