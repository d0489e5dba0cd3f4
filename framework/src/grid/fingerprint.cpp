#include "shellflow/grid/fingerprint.hpp"

#include <array>
#include <cstring>

namespace shellflow::grid {

namespace {

constexpr std::uint64_t kOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kPrime = 0x100000001b3ULL;

std::uint64_t mix(std::uint64_t z) {  // splitmix64's finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t fingerprint(std::span<const std::byte> data, std::uint64_t seed) {
  constexpr int kChunks = 64;
  const std::int64_t words = static_cast<std::int64_t>(data.size() / 8);
  std::array<std::uint64_t, kChunks> chunk{};
#pragma omp parallel for schedule(static) if (words >= (1 << 16))
  for (int c = 0; c < kChunks; ++c) {
    std::uint64_t h = kOffset;
    for (std::int64_t i = words * c / kChunks; i < words * (c + 1) / kChunks; ++i) {
      std::uint64_t word;
      std::memcpy(&word, data.data() + 8 * i, sizeof word);
      h = (h ^ word) * kPrime;
    }
    chunk[c] = mix(h);
  }
  std::uint64_t h = mix(seed ^ kOffset);
  const auto add = [&](std::uint64_t word) { h = mix((h ^ word) * kPrime); };
  add(static_cast<std::uint64_t>(data.size()));
  for (const std::uint64_t c : chunk) add(c);
  const std::size_t rest = data.size() % 8;
  std::uint64_t tail = 0;  // the last size % 8 bytes (memcpy never gets an empty array's null)
  if (rest > 0) std::memcpy(&tail, data.data() + 8 * words, rest);
  add(tail);
  return h;
}

}  // namespace shellflow::grid
