// Seeds for local random generators derived from one base seed (CONVENTIONS.md: randomness
// only from locally seeded generators), so that each stream (a test of a synthetic campaign, a
// repeated run) has its own seed, stable across platforms and independent of the order the
// streams are made in.
#pragma once

#include <cstdint>
#include <string_view>

namespace chatterlab {

// SplitMix64's output function of x + 0x9e3779b97f4a7c15 (Steele, Lea, Flood 2014; the
// seeding generator of xoshiro): a bijection of 64-bit words that scatters neighbouring inputs.
std::uint64_t splitmix64(std::uint64_t x);

// 64-bit FNV-1a of the bytes of `text` (offset basis 0xcbf29ce484222325, prime
// 0x100000001b3).
std::uint64_t fnv1a64(std::string_view text);

// splitmix64(splitmix64(splitmix64(base) ^ fnv1a64(tag)) ^ index): the seed of stream `index`
// of kind `tag` (e.g. "synth.cut.offset_angle") under `base`. Changing any argument gives an
// unrelated seed; the same arguments give the same seed on every platform.
std::uint64_t derive_seed(std::uint64_t base, std::string_view tag, std::uint64_t index);

}  // namespace chatterlab
