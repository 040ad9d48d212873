#include "msdeform/core/build_info.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#if defined(__GNUC__) && defined(__x86_64__)
#include <cpuid.h>
#include <immintrin.h>
#endif

#include <Eigen/Core>
#include <OpenMesh/Core/System/config.h>

#include "msdeform_build_info.h"  // MSDEFORM_COMMIT, generated

namespace msdeform {
namespace {

// SHA-256 round constants (FIPS 180-4 §4.2.2).
alignas(16) constexpr uint32_t kRoundConstants[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
    0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
    0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
    0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
    0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
    0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
    0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
    0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
    0xc67178f2};

uint32_t Rotate(uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

// One 64-byte block into the state, in plain C++ (FIPS 180-4 §6.2.2).
void CompressPortable(const unsigned char* block, uint32_t* state) {
  uint32_t w[64];
  for (int i = 0; i < 16; ++i) {
    w[i] = (uint32_t(block[4 * i]) << 24) | (uint32_t(block[4 * i + 1]) << 16) |
           (uint32_t(block[4 * i + 2]) << 8) | uint32_t(block[4 * i + 3]);
  }
  for (int i = 16; i < 64; ++i) {
    const uint32_t s0 = Rotate(w[i - 15], 7) ^ Rotate(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const uint32_t s1 = Rotate(w[i - 2], 17) ^ Rotate(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  uint32_t a = state[0], b = state[1], c = state[2], d = state[3], e = state[4], f = state[5],
           g = state[6], h = state[7];
  for (int i = 0; i < 64; ++i) {
    const uint32_t t1 = h + (Rotate(e, 6) ^ Rotate(e, 11) ^ Rotate(e, 25)) + ((e & f) ^ (~e & g)) +
                        kRoundConstants[i] + w[i];
    const uint32_t t2 = (Rotate(a, 2) ^ Rotate(a, 13) ^ Rotate(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  state[0] += a;
  state[1] += b;
  state[2] += c;
  state[3] += d;
  state[4] += e;
  state[5] += f;
  state[6] += g;
  state[7] += h;
}

#if defined(__GNUC__) && defined(__x86_64__)
#define MSDEFORM_SHA_EXTENSIONS 1

// Whether this CPU has the x86 SHA extensions (and the SSSE3/SSE4.1 the code
// around them uses); every AMD Zen has them, Intel's since Ice Lake and Goldmont.
bool RunsShaExtensions() {
  static const bool runs = [] {
    __builtin_cpu_init();
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    if (!__get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx)) return false;
    const bool sha = (ebx >> 29) & 1;  // CPUID.(EAX=7,ECX=0):EBX.SHA[bit 29]
    return sha && __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("sse4.1");
  }();
  return runs;
}

// `count` 64-byte blocks into the state with the SHA extensions: each
// sha256rnds2 does two rounds on the state held as (a, b, e, f) and (c, d, g,
// h); sha256msg1/msg2 extend the message schedule four words at a time.
__attribute__((target("sha,ssse3,sse4.1"))) void CompressWithShaExtensions(
    const unsigned char* blocks, size_t count, uint32_t* state) {
  // state[0..3] = (a, b, c, d), state[4..7] = (e, f, g, h), lane 0 first.
  const __m128i abcd = _mm_loadu_si128(reinterpret_cast<const __m128i*>(state));
  const __m128i efgh = _mm_loadu_si128(reinterpret_cast<const __m128i*>(state + 4));
  const __m128i cdab = _mm_shuffle_epi32(abcd, 0xB1);
  const __m128i hgfe = _mm_shuffle_epi32(efgh, 0x1B);
  // The instructions want (f, e, b, a) and (h, g, d, c) from lane 0 up.
  __m128i abef = _mm_alignr_epi8(cdab, hgfe, 8);
  __m128i cdgh = _mm_blend_epi16(hgfe, cdab, 0xF0);
  // Big-endian message words to lanes.
  const __m128i byte_swap = _mm_set_epi64x(0x0c0d0e0f08090a0bULL, 0x0405060700010203ULL);
  for (size_t n = 0; n < count; ++n, blocks += 64) {
    const __m128i abef_before = abef, cdgh_before = cdgh;
    __m128i w[4];  // w[g % 4]: message words 4g .. 4g + 3
#pragma GCC unroll 16
    for (int g = 0; g < 16; ++g) {
      __m128i words;
      if (g < 4) {
        words = _mm_shuffle_epi8(
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(blocks + 16 * g)), byte_swap);
      } else {
        // W_t = sigma1(W_t-2) + W_t-7 + sigma0(W_t-15) + W_t-16 for t = 4g .. 4g + 3.
        words = _mm_sha256msg1_epu32(w[g % 4], w[(g + 1) % 4]);
        words = _mm_add_epi32(words, _mm_alignr_epi8(w[(g + 3) % 4], w[(g + 2) % 4], 4));
        words = _mm_sha256msg2_epu32(words, w[(g + 3) % 4]);
      }
      w[g % 4] = words;
      __m128i scheduled = _mm_add_epi32(
          words, _mm_load_si128(reinterpret_cast<const __m128i*>(kRoundConstants + 4 * g)));
      cdgh = _mm_sha256rnds2_epu32(cdgh, abef, scheduled);
      scheduled = _mm_shuffle_epi32(scheduled, 0x0E);
      abef = _mm_sha256rnds2_epu32(abef, cdgh, scheduled);
    }
    abef = _mm_add_epi32(abef, abef_before);
    cdgh = _mm_add_epi32(cdgh, cdgh_before);
  }
  const __m128i feba = _mm_shuffle_epi32(abef, 0x1B);
  const __m128i dchg = _mm_shuffle_epi32(cdgh, 0xB1);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(state), _mm_blend_epi16(feba, dchg, 0xF0));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(state + 4), _mm_alignr_epi8(dchg, feba, 8));
}
#endif  // defined(__GNUC__) && defined(__x86_64__)

// FIPS 180-4 SHA-256, whole blocks straight from the input.
class Sha256Hasher {
 public:
  explicit Sha256Hasher(bool use_cpu_extensions) {
    state_ = kInitial;
#ifdef MSDEFORM_SHA_EXTENSIONS
    extensions_ = use_cpu_extensions && RunsShaExtensions();
#else
    (void)use_cpu_extensions;
#endif
  }

  void Update(const unsigned char* data, size_t size) {
    length_ += size;
    if (block_size_ > 0) {  // complete the buffered block first
      const size_t take = std::min(size, 64 - block_size_);
      std::memcpy(block_ + block_size_, data, take);
      block_size_ += take;
      data += take;
      size -= take;
      if (block_size_ < 64) return;
      Compress(block_, 1);
      block_size_ = 0;
    }
    const size_t whole = size / 64;
    Compress(data, whole);
    std::memcpy(block_, data + 64 * whole, size - 64 * whole);
    block_size_ = size - 64 * whole;
  }

  std::string HexDigest() {
    const uint64_t bits = length_ * 8;
    unsigned char padding[72] = {0x80};  // 0x80, zeros to 56 mod 64, the bit length
    const size_t zeros = (block_size_ < 56 ? 56 : 120) - block_size_ - 1;
    for (int i = 0; i < 8; ++i) padding[1 + zeros + i] = static_cast<unsigned char>(bits >> (56 - 8 * i));
    Update(padding, 1 + zeros + 8);
    char hex[65];
    for (int i = 0; i < 8; ++i) std::snprintf(hex + 8 * i, 9, "%08x", state_[i]);
    return std::string(hex, 64);
  }

 private:
  static constexpr std::array<uint32_t, 8> kInitial = {0x6a09e667, 0xbb67ae85, 0x3c6ef372,
                                                       0xa54ff53a, 0x510e527f, 0x9b05688c,
                                                       0x1f83d9ab, 0x5be0cd19};

  void Compress(const unsigned char* blocks, size_t count) {
#ifdef MSDEFORM_SHA_EXTENSIONS
    if (extensions_) {
      CompressWithShaExtensions(blocks, count, state_.data());
      return;
    }
#endif
    for (size_t n = 0; n < count; ++n) CompressPortable(blocks + 64 * n, state_.data());
  }

  std::array<uint32_t, 8> state_;
  bool extensions_ = false;
  unsigned char block_[64];
  size_t block_size_ = 0;
  uint64_t length_ = 0;
};

}  // namespace

const char* MsdeformVersion() { return MSDEFORM_VERSION; }
const char* MsdeformCommit() { return MSDEFORM_COMMIT; }

std::string EigenVersion() {
  return std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
         std::to_string(EIGEN_MINOR_VERSION);
}

std::string OpenMeshVersion() {
  return std::to_string((OM_VERSION >> 16) & 0xf) + "." + std::to_string((OM_VERSION >> 8) & 0xf);
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

int NumCores() { return static_cast<int>(std::thread::hardware_concurrency()); }

std::string UtcNow() {
  char text[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

std::string SourceTreePath(const std::string& relative) {
  namespace fs = std::filesystem;
  if (const char* root = std::getenv("MSDEFORM_SOURCE_DIR"); root != nullptr && *root != '\0') {
    return (fs::path(root) / relative).string();
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
      if (fs::exists(dir / relative, ec)) return (dir / relative).string();
      if (dir == dir.root_path()) break;
    }
  }
  return relative;
}

std::string DataDir() {
  if (const char* data = std::getenv("MSDEFORM_DATA_DIR"); data != nullptr && *data != '\0') {
    return data;
  }
  return SourceTreePath("data");
}

bool Sha256File(const std::string& path, std::string* digest, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = path + ": cannot read";
    return false;
  }
  Sha256Hasher hasher(/*use_cpu_extensions=*/true);
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    hasher.Update(reinterpret_cast<const unsigned char*>(buffer.data()),
                  static_cast<size_t>(in.gcount()));
  }
  if (in.bad()) {
    *error = path + ": cannot read";
    return false;
  }
  *digest = hasher.HexDigest();
  return true;
}

std::string Sha256(const std::string& bytes, bool use_cpu_extensions) {
  Sha256Hasher hasher(use_cpu_extensions);
  hasher.Update(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  return hasher.HexDigest();
}

bool Sha256ExtensionsAvailable() {
#ifdef MSDEFORM_SHA_EXTENSIONS
  return RunsShaExtensions();
#else
  return false;
#endif
}

}  // namespace msdeform
