// The fuzz targets without libFuzzer (the `fuzz_smoke.<name>` tests of `make test`, built by
// GCC in the release build): every file of the seed corpus through LLVMFuzzerTestOneInput,
// then deterministic random mutations of them (bit flips, byte changes, inserts, deletes,
// splices and boundary integers written over the bytes, as libFuzzer's own mutators do).
// Usage: fuzz_smoke_<name> CORPUS_DIR [MUTATIONS] [MAX_LEN]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_support.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void mutate(Bytes& b, const std::vector<Bytes>& corpus, std::mt19937_64& rng, std::size_t max_len) {
  auto pick = [&](std::size_t n) { return n ? static_cast<std::size_t>(rng() % n) : 0; };
  static constexpr std::uint64_t kInteresting[] = {0,          1,          0x7f,       0x80,
                                                   0xff,       0x7fff,     0xffff,     0x7fffffff,
                                                   0x80000000, 0xffffffff, ~0ull >> 1, ~0ull};
  const int edits = 1 + static_cast<int>(pick(4));
  for (int e = 0; e < edits; ++e) {
    switch (pick(7)) {
      case 0:
        if (!b.empty()) b[pick(b.size())] ^= static_cast<std::uint8_t>(1u << pick(8));
        break;
      case 1:
        if (!b.empty()) b[pick(b.size())] = static_cast<std::uint8_t>(rng());
        break;
      case 2:
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)),
                 static_cast<std::uint8_t>(rng()));
        break;
      case 3:
        if (!b.empty()) {
          const std::size_t at = pick(b.size());
          const std::size_t n = std::min(b.size() - at, 1 + pick(16));
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(at),
                  b.begin() + static_cast<std::ptrdiff_t>(at + n));
        }
        break;
      case 4: {  // a piece of another seed
        const Bytes& other = corpus[pick(corpus.size())];
        if (other.empty()) break;
        const std::size_t from = pick(other.size());
        const std::size_t n = std::min(other.size() - from, 1 + pick(64));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)),
                 other.begin() + static_cast<std::ptrdiff_t>(from),
                 other.begin() + static_cast<std::ptrdiff_t>(from + n));
        break;
      }
      case 5: {  // a boundary integer, binary, over 1, 2, 4 or 8 bytes
        const std::uint64_t v = kInteresting[pick(std::size(kInteresting))];
        const std::size_t width = std::size_t{1} << pick(4);
        if (b.size() < width) break;
        const std::size_t at = pick(b.size() - width + 1);
        for (std::size_t i = 0; i < width; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
        break;
      }
      default: {  // a boundary integer as decimal text (the text formats' sizes and counts)
        static constexpr const char* kNumbers[] = {
            "0",     "-1",  "65536", "4294967296",         "2147483648",
            "1e308", "nan", "-0",    "9223372036854775808"};
        const std::string s = kNumbers[pick(std::size(kNumbers))];
        const std::size_t at = pick(b.size() + 1);
        const std::size_t n = std::min(b.size() - at, pick(4));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(at),
                b.begin() + static_cast<std::ptrdiff_t>(at + n));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), s.begin(), s.end());
        break;
      }
    }
  }
  if (b.size() > max_len) b.resize(max_len);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [MUTATIONS] [MAX_LEN]\n", argv[0]);
    return 2;
  }
  const long mutations = argc > 2 ? std::stol(argv[2]) : 2000;
  const std::size_t max_len = argc > 3 ? std::stoul(argv[3]) : 65536;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(argv[1]))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());  // the same order, hence the same mutations, every run
  if (files.empty()) {
    std::fprintf(stderr, "%s: no seed inputs\n", argv[1]);
    return 1;
  }
  std::vector<Bytes> corpus;
  for (const auto& f : files) {
    corpus.push_back(read_file(f));
    LLVMFuzzerTestOneInput(corpus.back().data(), corpus.back().size());
  }
  std::mt19937_64 rng(20);  // fixed seed: a failure reproduces
  for (long i = 0; i < mutations; ++i) {
    Bytes input = corpus[static_cast<std::size_t>(rng() % corpus.size())];
    mutate(input, corpus, rng, max_len);
    LLVMFuzzerTestOneInput(input.data(), input.size());
  }
  std::printf("%zu seeds and %ld mutations of them: no crash\n", files.size(), mutations);
  return 0;
}
