// Counter-based random numbers for the engine: the renderer gives every pixel, pass and light its
// own stream, seeded by hashing the indices, so an image does not depend on how tiles are
// scheduled over threads and one seed can be changed while the others stay fixed; the procedural
// scenes and the ray-traced baseline (EmbreeScene::sampledFraction) draw from one seeded stream.
// In engine/scene/, the lowest room of the engine, so that every room above can use it.
#pragma once

#include <cstdint>
#include <initializer_list>

namespace penumbra {

// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit state advanced by a Weyl constant and finalised
// by a bijective mixer. Small, fast and good enough to jitter strata; not for cryptography.
struct SplitMix64 {
    uint64_t state = 0;

    static constexpr uint64_t mix(uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint64_t next() { return mix(state += 0x9E3779B97F4A7C15ull); }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)

    // A stream seeded from several indices (e.g. seed, pass, pixel): each one is mixed in turn,
    // so streams for different index tuples are unrelated.
    static SplitMix64 forIndices(std::initializer_list<uint64_t> indices) {
        uint64_t h = 0x6A09E667F3BCC909ull;
        for (uint64_t i : indices) h = mix(h ^ mix(i + 0x9E3779B97F4A7C15ull));
        return SplitMix64{h};
    }
};

}  // namespace penumbra
