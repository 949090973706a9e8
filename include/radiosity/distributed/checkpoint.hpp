#pragma once
/// @file checkpoint.hpp  The checkpoint file of a long solve: tagged sections of flat arrays
/// behind a header that names the scene and options it belongs to (a 64-bit FNV-1a hash of
/// them, Fowler, Noll & Vo) and a trailer hashing the payload, so that a checkpoint of another
/// run, a truncated one and a corrupted one are each refused with their own message. Written
/// atomically: to FILE.tmp, flushed to the disk (fsync), then renamed over FILE, so a crash at
/// any moment leaves the last good checkpoint (POSIX rename replaces atomically).
///
/// Layout (little-endian, as the machine writes it): "RADCKPT" and a version byte; the scene
/// hash (8 bytes); the payload's length (8 bytes); the payload, sections of [tag: 4 bytes]
/// [length: 8 bytes][bytes]; the payload's hash (8 bytes).

#include <radiosity/error.hpp>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <unistd.h>  // fsync

namespace radiosity {

/// FNV-1a, 64 bits (Fowler, Noll & Vo): a hash of bytes fed in pieces.
class Fnv1a {
  public:
    /// Feeds bytes.
    void add(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ull;
    }
    /// Feeds a trivially copyable value's bytes.
    template <class T>
    void add_value(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        add(&v, sizeof(T));
    }
    std::uint64_t value() const { return h_; }  ///< the hash so far

  private:
    std::uint64_t h_ = 0xcbf29ce484222325ull;
};

/// Builds a checkpoint's payload section by section, then writes it atomically.
class CheckpointWriter {
  public:
    /// A section of trivially copyable values.
    template <class T>
    void add(std::uint32_t tag, std::span<const T> values) {
        static_assert(std::is_trivially_copyable_v<T>);
        put(&tag, sizeof tag);
        const std::uint64_t n = values.size_bytes();
        put(&n, sizeof n);
        put(values.data(), values.size_bytes());
    }
    /// A section of one value.
    template <class T>
    void add_value(std::uint32_t tag, const T& v) {
        add(tag, std::span<const T>(&v, 1));
    }

    /// Writes header, payload and trailer to path + ".tmp", flushes it to the disk and renames
    /// it over `path`. Throws Error naming the file if any step fails (the old file then stays).
    void write(const std::string& path, std::uint64_t scene_hash) const {
        const std::string tmp = path + ".tmp";
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw Error("checkpoint " + path + ": cannot write " + tmp);
        Fnv1a h;
        h.add(payload_.data(), payload_.size());
        const std::uint64_t n = payload_.size(), sum = h.value();
        bool ok = std::fwrite(magic.data(), 1, magic.size(), f) == magic.size();
        ok = ok && std::fwrite(&scene_hash, sizeof scene_hash, 1, f) == 1;
        ok = ok && std::fwrite(&n, sizeof n, 1, f) == 1;
        ok = ok && (n == 0 || std::fwrite(payload_.data(), 1, n, f) == n);
        ok = ok && std::fwrite(&sum, sizeof sum, 1, f) == 1;
        ok = ok && std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
        ok = (std::fclose(f) == 0) && ok;
        if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
            std::remove(tmp.c_str());
            throw Error("checkpoint " + path + ": writing failed (disk full?); the last " +
                        "checkpoint, if any, is kept");
        }
    }

    /// "RADCKPT" and the format's version: 6 since the solve's state says whether the pass's
    /// row sums are held (SolveState::held; 5: a cluster link's visible transfer held to 1, 4:
    /// the oracle's oriented clusters), as a solve resumed under another rule would not give
    /// the bits of one never stopped (a link's class shares are sampled again from its pair).
    static constexpr std::array<char, 8> magic{'R', 'A', 'D', 'C', 'K', 'P', 'T', 6};

  private:
    void put(const void* p, std::size_t n) {
        const auto* b = static_cast<const std::byte*>(p);
        payload_.insert(payload_.end(), b, b + n);
    }
    std::vector<std::byte> payload_;
};

/// Reads a checkpoint back, refusing one that is not ours, of another scene or options,
/// truncated or corrupted, each with a message naming the file.
class CheckpointReader {
  public:
    /// Reads and checks `path` against the hash of this run's scene and options.
    CheckpointReader(const std::string& path, std::uint64_t scene_hash) : path_(path) {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (!f) throw Error("checkpoint " + path + ": cannot open it");
        std::vector<std::byte> all;
        std::array<std::byte, 65536> buf;
        for (std::size_t got; (got = std::fread(buf.data(), 1, buf.size(), f)) > 0;)
            all.insert(all.end(), buf.begin(), buf.begin() + std::ptrdiff_t(got));
        std::fclose(f);
        const std::size_t head = CheckpointWriter::magic.size() + 16;
        if (all.size() < CheckpointWriter::magic.size() ||
            std::memcmp(all.data(), CheckpointWriter::magic.data(), 7) != 0)
            throw Error("checkpoint " + path + ": not a radiosity checkpoint");
        if (all[7] != std::byte{CheckpointWriter::magic[7]})
            throw Error("checkpoint " + path + ": written by another version of the format");
        if (all.size() < head) throw Error("checkpoint " + path + ": truncated (no header)");
        std::uint64_t hash = 0, n = 0, sum = 0;
        std::memcpy(&hash, all.data() + 8, 8);
        std::memcpy(&n, all.data() + 16, 8);
        if (hash != scene_hash)
            throw Error("checkpoint " + path + ": written for another scene or other options " +
                        "(it cannot continue this run)");
        if (all.size() != head + n + 8)
            throw Error("checkpoint " + path + ": truncated or padded (" +
                        std::to_string(all.size()) + " bytes, the header says " +
                        std::to_string(head + n + 8) + ")");
        std::memcpy(&sum, all.data() + head + n, 8);
        Fnv1a h;
        h.add(all.data() + head, n);
        if (h.value() != sum) throw Error("checkpoint " + path + ": corrupted (checksum differs)");
        for (std::size_t at = head; at < head + n;) {
            std::uint32_t tag = 0;
            std::uint64_t len = 0;
            if (at + 12 > head + n) throw Error("checkpoint " + path + ": a section is cut short");
            std::memcpy(&tag, all.data() + at, 4);
            std::memcpy(&len, all.data() + at + 4, 8);
            at += 12;
            if (len > head + n - at) throw Error("checkpoint " + path + ": a section is cut short");
            sections_[tag].assign(all.begin() + std::ptrdiff_t(at),
                                  all.begin() + std::ptrdiff_t(at + len));
            at += len;
        }
    }

    /// The values of a section, in a vector with allocator A; Error if it is missing or not a
    /// whole number of T.
    template <class T, class A = std::allocator<T>>
    std::vector<T, A> get(std::uint32_t tag) const {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto it = sections_.find(tag);
        if (it == sections_.end() || it->second.size() % sizeof(T) != 0)
            throw Error("checkpoint " + path_ + ": section " + std::to_string(tag) +
                        " is missing or malformed");
        std::vector<T, A> v(it->second.size() / sizeof(T));
        if (!v.empty()) std::memcpy(v.data(), it->second.data(), it->second.size());
        return v;
    }
    /// The one value of a section.
    template <class T>
    T value(std::uint32_t tag) const {
        const std::vector<T> v = get<T>(tag);
        if (v.size() != 1)
            throw Error("checkpoint " + path_ + ": section " + std::to_string(tag) +
                        " is malformed");
        return v[0];
    }

  private:
    std::string path_;
    std::map<std::uint32_t, std::vector<std::byte>> sections_;
};

}  // namespace radiosity
