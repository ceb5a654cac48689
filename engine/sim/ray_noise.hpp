// Per-ray noise and dropout drawn from a counter-based hash of (seed, frame,
// ray), so the result of a ray never depends on which thread cast it or in
// what order: the same seed gives bit-identical scans on any thread count.
#pragma once

#include <cstdint>

#include "engine/sim/arena.hpp"

namespace sarmap::sim {

// SplitMix64's finaliser: a bijective 64-bit mix.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// The key of one ray of one frame.
constexpr std::uint64_t ray_key(std::uint64_t seed, std::uint64_t frame, std::uint64_t ray) {
  return mix64(mix64(mix64(seed) ^ frame) ^ ray);
}

// A uniform double in [0, 1) from stream `stream` of a key.
double uniform01(std::uint64_t key, std::uint64_t stream);
// A standard normal value (Box-Muller on two streams of the key).
double standard_normal(std::uint64_t key);

// Axial sigma of a Kinect-class sensor at depth z (metres):
// 0.0012 + 0.0019 (z - 0.4)^2 (Khoshelham & Elberink; Nguyen et al.).
double kinect_sigma(double depth);

// The measured value for a true `value` (depth or range): false when the
// return is dropped, else `measured` gets value plus noise.
bool apply_noise(const NoiseSpec& noise, double value, std::uint64_t key, double& measured);

}  // namespace sarmap::sim
