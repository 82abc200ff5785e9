// The cache files of base/atomic_file.hpp (and the raw fields of base/raw_bytes.hpp): whole
// or absent, never a torn file under the final name, and a damaged one is told apart from a
// good one.
#include "base/atomic_file.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "base/hash.hpp"
#include "base/raw_bytes.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

namespace fs = std::filesystem;
using Status = ChecksummedFile::Status;

class AtomicFileTest : public ::testing::Test {
 protected:
  static std::string read(const fs::path& p) {
    std::string bytes(fs::file_size(p), '\0');
    std::ifstream(p, std::ios::binary)
        .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return bytes;
  }
  static void write_raw(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
  }
  std::vector<fs::path> files() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename());
    return out;
  }

  const fs::path dir_ = testing::scratch_dir();
};

TEST_F(AtomicFileTest, WritesTheWholeFileAndLeavesNoTemporary) {
  const fs::path path = dir_ / "sub" / "entry.bin";  // the directories are created
  const std::string data("one\0two", 7);
  ASSERT_TRUE(write_file_atomically(path, data));
  EXPECT_EQ(read(path), data);
  ASSERT_TRUE(write_file_atomically(path, "replaced"));
  EXPECT_EQ(read(path), "replaced");
  std::vector<fs::path> left;
  for (const auto& e : fs::directory_iterator(dir_ / "sub")) left.push_back(e.path().filename());
  EXPECT_EQ(left, std::vector<fs::path>{"entry.bin"});
}

TEST_F(AtomicFileTest, AFailedWriteLeavesNothingBehind) {
  // The final name is taken by a directory: the rename fails after the temporary was
  // written, which must then be removed, and the directory left as it was.
  fs::create_directories(dir_ / "entry.bin" / "inside");
  EXPECT_FALSE(write_file_atomically(dir_ / "entry.bin", "data"));
  EXPECT_EQ(files(), std::vector<fs::path>{"entry.bin"});
  EXPECT_TRUE(fs::is_directory(dir_ / "entry.bin" / "inside"));
  // A directory that cannot be created (a file stands where it would go).
  write_raw(dir_ / "plain", "x");
  EXPECT_FALSE(write_file_atomically(dir_ / "plain" / "entry.bin", "data"));
  EXPECT_EQ(read(dir_ / "plain"), "x");
}

TEST_F(AtomicFileTest, ChecksummedRoundTripAndLayout) {
  const fs::path path = dir_ / "entry.bin";
  const std::string body = "MAGIC123payload";
  ASSERT_TRUE(write_checksummed_file(path, body));
  // The layout existing cache files have: the body, then its FNV-1a in host byte order.
  const std::string raw = read(path);
  ASSERT_EQ(raw.size(), body.size() + 8);
  EXPECT_EQ(raw.substr(0, body.size()), body);
  std::uint64_t stored = 0;
  std::memcpy(&stored, raw.data() + body.size(), sizeof stored);
  EXPECT_EQ(stored, fnv1a64(body));

  const ChecksummedFile file = read_checksummed_file(path, 8);
  EXPECT_EQ(file.status, Status::Ok);
  EXPECT_EQ(file.body, body);
}

TEST_F(AtomicFileTest, DamageIsDetected) {
  const fs::path path = dir_ / "entry.bin";
  EXPECT_EQ(read_checksummed_file(path).status, Status::Missing);
  ASSERT_TRUE(write_checksummed_file(path, "MAGIC123payload"));
  const std::string good = read(path);

  std::string flipped = good;
  flipped[10] ^= 0x01;
  write_raw(path, flipped);
  ChecksummedFile file = read_checksummed_file(path);
  EXPECT_EQ(file.status, Status::BadChecksum);
  EXPECT_TRUE(file.body.empty());

  write_raw(path, good.substr(0, good.size() - 1));  // torn: the checksum's last byte missing
  EXPECT_EQ(read_checksummed_file(path).status, Status::BadChecksum);

  // Shorter than the checksum plus the caller's smallest body.
  write_raw(path, good.substr(0, 8 + 7));
  EXPECT_EQ(read_checksummed_file(path, 8).status, Status::Truncated);
  write_raw(path, "");
  EXPECT_EQ(read_checksummed_file(path).status, Status::Truncated);
}

TEST(FileNamePart, KeepsSafeCharactersOnly) {
  EXPECT_EQ(file_name_part("my kernel!"), "my_kernel_");
  EXPECT_EQ(file_name_part("../etc/passwd"), "___etc_passwd");
  EXPECT_EQ(file_name_part("ok-name_2"), "ok-name_2");
  EXPECT_EQ(file_name_part(std::string(50, 'x')), std::string(40, 'x'));
  EXPECT_EQ(file_name_part(""), "");
}

TEST(RawBytes, RoundTripAndShortInput) {
  std::string out;
  put_raw(out, std::uint32_t{7});
  put_raw(out, std::uint64_t{0x0102030405060708ULL});
  ASSERT_EQ(out.size(), 12u);
  std::string_view in = out;
  std::uint32_t a = 0;
  std::uint64_t b = 0;
  ASSERT_TRUE(get_raw(in, a));
  ASSERT_TRUE(get_raw(in, b));
  EXPECT_EQ(a, 7u);
  EXPECT_EQ(b, 0x0102030405060708ULL);
  EXPECT_TRUE(in.empty());
  std::string_view short_in = std::string_view(out).substr(0, 3);
  EXPECT_FALSE(get_raw(short_in, a));
  EXPECT_EQ(short_in.size(), 3u);  // nothing consumed
}

}  // namespace
}  // namespace probeless
