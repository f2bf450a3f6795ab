#pragma once
/// Random numbers: always a seeded engine passed in by the caller, never a global.
#include <cstdint>
#include <random>

namespace mg {

/// The project's random engine. Same seed, same sequence, on every platform we build for.
using Rng = std::mt19937_64;

/// Derives an independent stream seed from a base seed and a stream index (SplitMix64), so
/// parallel workers get reproducible, uncorrelated streams whatever the thread count.
inline std::uint64_t derive_seed(std::uint64_t base, std::uint64_t stream) {
  std::uint64_t z = base + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace mg
