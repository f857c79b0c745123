// Hash64: a streaming 64-bit hash of 64-bit words, used for the scene hash and the checksum of the
// visibility file. Not cryptographic.
//
// Each step is h <- fmix64(h ^ (w * K)) with K odd: for fixed h it is injective in the word w,
// and for a fixed word it is a bijection of h. So two inputs of the same length that differ in
// exactly one word (e.g. one flipped byte) always hash differently; other differences collide with
// probability about 2^-64. The input length is mixed in at the end.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

namespace penumbra {

class Hash64 {
  public:
    void addU64(uint64_t w) {
        h_ = fmix(h_ ^ (w * 0x9E3779B97F4A7C15ull));
        ++words_;
    }
    void addU32(uint32_t v) { addU64(v); }
    void addDouble(double v) { addU64(std::bit_cast<uint64_t>(v)); }  // the bit pattern
    // Bytes as little-endian 64-bit words, the last one zero-padded, then the byte count.
    void addBytes(std::span<const unsigned char> bytes) {
        size_t i = 0;
        for (; i + 8 <= bytes.size(); i += 8) addU64(loadLE(bytes.data() + i, 8));
        if (i < bytes.size()) addU64(loadLE(bytes.data() + i, bytes.size() - i));
        addU64(bytes.size());
    }
    uint64_t value() const { return fmix(h_ ^ words_); }

  private:
    static uint64_t loadLE(const unsigned char* p, size_t n) {
        uint64_t w = 0;
        for (size_t k = 0; k < n; ++k) w |= static_cast<uint64_t>(p[k]) << (8 * k);
        return w;
    }
    // MurmurHash3's finaliser: a bijection of 64-bit words.
    static uint64_t fmix(uint64_t h) {
        h ^= h >> 33;
        h *= 0xFF51AFD7ED558CCDull;
        h ^= h >> 33;
        h *= 0xC4CEB9FE1A85EC53ull;
        h ^= h >> 33;
        return h;
    }

    uint64_t h_ = 0x243F6A8885A308D3ull;
    uint64_t words_ = 0;
};

// Hash64::addBytes over bytes that arrive in pieces (a file written as it streams, the merge of
// visibility files): value() equals Hash64::addBytes of the pieces' concatenation, then value().
class Hash64ByteStream {
  public:
    void add(std::span<const unsigned char> bytes) {
        for (unsigned char b : bytes) {
            pending_ |= static_cast<uint64_t>(b) << (8 * pendingBytes_);
            if (++pendingBytes_ == 8) {
                h_.addU64(pending_);
                pending_ = 0;
                pendingBytes_ = 0;
            }
        }
        count_ += bytes.size();
    }
    uint64_t value() const {
        Hash64 h = h_;
        if (pendingBytes_ > 0) h.addU64(pending_);
        h.addU64(count_);
        return h.value();
    }

  private:
    Hash64 h_;
    uint64_t pending_ = 0;
    size_t pendingBytes_ = 0;
    uint64_t count_ = 0;
};

}  // namespace penumbra
