#pragma once
// Fingerprints of grid arrays: 64-bit hashes that let a solver tell that its input did not
// change since the last step (a smoke scene's pressure operator and fluid regions, step
// after step, when no shell moves), so that it can keep what it built from it. Equal
// arrays hash equal, bit for bit; different ones collide with probability about 2^-64.
// One parallel pass, the same value on any number of threads.

#include <cstdint>
#include <span>

namespace shellflow::grid {

/// Folds the bytes of `data` into `seed`: FNV-1a over 64-bit words in 64 fixed chunks,
/// each chunk finished with splitmix64's mixer, the chunks and the length combined in order.
std::uint64_t fingerprint(std::span<const std::byte> data, std::uint64_t seed = 0);

/// The same for an array of trivially copyable values.
template <class T>
std::uint64_t fingerprint_of(std::span<const T> values, std::uint64_t seed = 0) {
  return fingerprint(std::as_bytes(values), seed);
}

}  // namespace shellflow::grid
