#include "drivers/io/png.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "support/memory_cap.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

namespace fs = std::filesystem;

template <typename ImageT>
ImageT random_image(int w, int h, unsigned seed) {
  ImageT image(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<unsigned> dist(
      0, (1u << (8 * sizeof(typename ImageT::value_type))) - 1);
  for (auto& v : image.elements()) v = static_cast<typename ImageT::value_type>(dist(rng));
  return image;
}

std::vector<char> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const char* data, std::size_t n) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(data, static_cast<std::streamsize>(n));
}

// Expects an ImageFileError whose message names `file` and contains `fragment`.
template <typename F>
void expect_image_error(F&& f, const fs::path& file, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no ImageFileError for " << file;
  } catch (const ImageFileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
    EXPECT_EQ(e.path(), file);
  }
}

TEST(Png, RoundTripsEveryType) {
  const fs::path dir = testing::scratch_dir();
  const auto rgb8 = random_image<ImageRGB8>(37, 23, 1);
  const auto gray8 = random_image<ImageGray8>(1, 1, 2);
  const auto depth = random_image<DepthImage>(64, 3, 3);
  const auto rgb16 = random_image<ImageRGB16>(5, 41, 4);
  const auto rgba8 = random_image<ImageRGBA8>(17, 9, 5);
  write_png(dir / "rgb8.png", rgb8);
  write_png(dir / "gray8.png", gray8);
  write_png(dir / "depth.png", depth);
  write_png(dir / "rgb16.png", rgb16);
  write_png(dir / "rgba8.png", rgba8);
  EXPECT_EQ(read_png_rgb8(dir / "rgb8.png"), rgb8);
  EXPECT_EQ(read_png_gray8(dir / "gray8.png"), gray8);
  EXPECT_EQ(read_png_depth16(dir / "depth.png"), depth);
  EXPECT_EQ(read_png_rgb16(dir / "rgb16.png"), rgb16);
  // No temporary file is left behind.
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }
}

TEST(Png, DepthExtremesSurvive) {
  const fs::path dir = testing::scratch_dir();
  DepthImage depth(4, 1);
  depth.at(0, 0) = 0;
  depth.at(1, 0) = 1;
  depth.at(2, 0) = 0x0100;  // byte order would swap this to 1
  depth.at(3, 0) = 65535;
  write_png(dir / "d.png", depth);
  EXPECT_EQ(read_png_depth16(dir / "d.png"), depth);
}

TEST(Png, OverwritesAtomically) {
  const fs::path dir = testing::scratch_dir();
  write_png(dir / "a.png", random_image<ImageRGB8>(8, 8, 1));
  const auto second = random_image<ImageRGB8>(3, 5, 2);
  write_png(dir / "a.png", second);
  EXPECT_EQ(read_png_rgb8(dir / "a.png"), second);
}

TEST(Png, EightBitReadersConvert) {
  const fs::path dir = testing::scratch_dir();
  // Gray -> RGB replicates.
  const auto gray = random_image<ImageGray8>(6, 4, 7);
  write_png(dir / "gray.png", gray);
  const ImageRGB8 rgb_from_gray = read_png_rgb8(dir / "gray.png");
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb_from_gray.at(x, y, c), gray.at(x, y));
  // RGBA -> RGB drops alpha.
  const auto rgba = random_image<ImageRGBA8>(6, 4, 8);
  write_png(dir / "rgba.png", rgba);
  const ImageRGB8 rgb_from_rgba = read_png_rgb8(dir / "rgba.png");
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb_from_rgba.at(x, y, c), rgba.at(x, y, c));
  // 16-bit -> 8-bit scales with rounding.
  const auto rgb16 = random_image<ImageRGB16>(6, 4, 9);
  write_png(dir / "rgb16.png", rgb16);
  const ImageRGB8 rgb_from_16 = read_png_rgb8(dir / "rgb16.png");
  for (std::size_t i = 0; i < rgb16.elements().size(); ++i) {
    const double expected = rgb16.elements()[i] * 255.0 / 65535.0;
    EXPECT_NEAR(rgb_from_16.elements()[i], expected, 0.51);
  }
  const auto depth = random_image<DepthImage>(6, 4, 10);
  write_png(dir / "depth.png", depth);
  const ImageGray8 gray_from_16 = read_png_gray8(dir / "depth.png");
  for (std::size_t i = 0; i < depth.elements().size(); ++i) {
    EXPECT_NEAR(gray_from_16.elements()[i], depth.elements()[i] * 255.0 / 65535.0, 0.51);
  }
  // RGB -> gray by Rec. 709 luma.
  const auto rgb = random_image<ImageRGB8>(6, 4, 11);
  write_png(dir / "rgb.png", rgb);
  const ImageGray8 luma = read_png_gray8(dir / "rgb.png");
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      const double l =
          0.2126 * rgb.at(x, y, 0) + 0.7152 * rgb.at(x, y, 1) + 0.0722 * rgb.at(x, y, 2);
      EXPECT_NEAR(luma.at(x, y), l, 1.01);
    }
}

// Writes with libpng directly: layouts our writer never produces (palette, 2-bit, Adam7).
void write_palette_png(const fs::path& path, bool interlaced) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, 4, 3, 2, PNG_COLOR_TYPE_PALETTE,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color palette[4] = {{0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {10, 20, 30}};
  png_set_PLTE(png, info, palette, 4);
  png_byte alpha[4] = {0, 128, 255, 255};
  png_set_tRNS(png, info, alpha, 4, nullptr);
  png_write_info(png, info);
  // 2 bits per pixel, 4 pixels per row: indices (0,1,2,3), (3,2,1,0), (1,1,1,1).
  png_byte row0[1] = {0b00011011}, row1[1] = {0b11100100}, row2[1] = {0b01010101};
  png_bytep rows[3] = {row0, row1, row2};
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

TEST(Png, PaletteAndInterlacedConvertToRgb8) {
  const fs::path dir = testing::scratch_dir();
  for (bool interlaced : {false, true}) {
    const fs::path p = dir / (interlaced ? "adam7.png" : "plain.png");
    write_palette_png(p, interlaced);
    const ImageRGB8 rgb = read_png_rgb8(p);
    ASSERT_EQ(rgb.width(), 4);
    ASSERT_EQ(rgb.height(), 3);
    EXPECT_EQ(rgb.at(1, 0, 0), 255);
    EXPECT_EQ(rgb.at(2, 0, 1), 255);
    EXPECT_EQ(rgb.at(0, 1, 2), 30);
    EXPECT_EQ(rgb.at(3, 2, 0), 255);
    const ImageGray8 gray = read_png_gray8(p);
    EXPECT_EQ(gray.at(0, 0), 0);
    EXPECT_NEAR(gray.at(2, 0), 0.7152 * 255, 1.01);
    // 16-bit readers refuse it.
    expect_image_error([&] { (void)read_png_depth16(p); }, p, "got 2-bit palette");
  }
}

TEST(Png, SixteenBitReadersRefuseOtherLayouts) {
  const fs::path dir = testing::scratch_dir();
  write_png(dir / "gray8.png", ImageGray8(3, 3));
  write_png(dir / "rgb8.png", ImageRGB8(3, 3));
  write_png(dir / "rgb16.png", ImageRGB16(3, 3));
  write_png(dir / "depth.png", DepthImage(3, 3));
  expect_image_error([&] { (void)read_png_depth16(dir / "gray8.png"); }, dir / "gray8.png",
                     "expected a 16-bit single-channel PNG, got 8-bit gray");
  expect_image_error([&] { (void)read_png_depth16(dir / "rgb16.png"); }, dir / "rgb16.png",
                     "got 16-bit RGB");
  expect_image_error([&] { (void)read_png_rgb16(dir / "rgb8.png"); }, dir / "rgb8.png",
                     "expected a 16-bit RGB PNG, got 8-bit RGB");
  expect_image_error([&] { (void)read_png_rgb16(dir / "depth.png"); }, dir / "depth.png",
                     "got 16-bit gray");
}

TEST(Png, MissingEmptyAndForeignFiles) {
  const fs::path dir = testing::scratch_dir();
  expect_image_error([&] { (void)read_png_rgb8(dir / "none.png"); }, dir / "none.png",
                     "cannot open");
  write_bytes(dir / "empty.png", "", 0);
  expect_image_error([&] { (void)read_png_rgb8(dir / "empty.png"); }, dir / "empty.png",
                     "empty file");
  const std::string text = "P6\n2 2\n255\n............";
  write_bytes(dir / "ppm.png", text.data(), text.size());
  expect_image_error([&] { (void)read_png_depth16(dir / "ppm.png"); }, dir / "ppm.png",
                     "not a PNG file");
  expect_image_error([&] { (void)read_png_rgb8(dir); }, dir, "");
}

TEST(Png, EveryTruncationIsAnError) {
  const fs::path dir = testing::scratch_dir();
  const fs::path full = dir / "full.png";
  write_png(full, random_image<ImageRGB16>(13, 11, 3));
  const std::vector<char> bytes = read_bytes(full);
  ASSERT_GT(bytes.size(), 100u);
  const fs::path cut = dir / "cut.png";
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    write_bytes(cut, bytes.data(), n);
    expect_image_error([&] { (void)read_png_rgb16(cut); }, cut, "");
    expect_image_error([&] { (void)read_png_rgb8(cut); }, cut, "");
  }
  write_bytes(cut, bytes.data(), bytes.size() - 5);
  expect_image_error([&] { (void)read_png_rgb16(cut); }, cut, "truncated or corrupt PNG");
}

TEST(Png, RandomBytesAndCorruptionNeverCrash) {
  const fs::path dir = testing::scratch_dir();
  std::mt19937 rng(1234);
  const fs::path p = dir / "noise.png";
  // Pure noise, with and without a valid signature in front.
  for (int i = 0; i < 200; ++i) {
    std::vector<char> noise(1 + rng() % 600);
    for (auto& b : noise) b = static_cast<char>(rng());
    if (i % 2 == 0) {
      const char sig[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
      std::copy(sig, sig + std::min<std::size_t>(8, noise.size()), noise.begin());
    }
    write_bytes(p, noise.data(), noise.size());
    expect_image_error([&] { (void)read_png_rgb8(p); }, p, "");
  }
  // A valid file with a few bytes flipped: an error or an image, never a crash or a leak.
  write_png(dir / "good.png", random_image<ImageRGB8>(20, 10, 5));
  const std::vector<char> good = read_bytes(dir / "good.png");
  int errors = 0;
  for (int i = 0; i < 300; ++i) {
    std::vector<char> bad = good;
    for (int k = 0; k < 3; ++k)
      bad[8 + rng() % (bad.size() - 8)] ^= static_cast<char>(1 + rng() % 255);
    write_bytes(p, bad.data(), bad.size());
    try {
      (void)read_png_rgb8(p);
    } catch (const ImageFileError& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos);
    }
  }
  EXPECT_GT(errors, 250);  // every chunk carries a CRC
}

std::uint32_t crc32(const unsigned char* data, std::size_t n) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

// A small gray PNG whose IHDR claims width x height (the pixel data is still 2 x 2's).
fs::path png_claiming(const std::string& name, std::uint32_t width, std::uint32_t height) {
  const fs::path dir = testing::scratch_dir();
  write_png(dir / "small.png", ImageGray8(2, 2));
  std::vector<char> bytes = read_bytes(dir / "small.png");
  // IHDR data starts at byte 16 (8 signature + 4 length + 4 type): width, height big-endian.
  auto* u = reinterpret_cast<unsigned char*>(bytes.data());
  for (int i = 0; i < 4; ++i) {
    u[16 + i] = static_cast<unsigned char>(width >> (24 - 8 * i));
    u[20 + i] = static_cast<unsigned char>(height >> (24 - 8 * i));
  }
  const std::uint32_t crc = crc32(u + 12, 17);  // type + 13 data bytes
  u[29] = static_cast<unsigned char>(crc >> 24);
  u[30] = static_cast<unsigned char>(crc >> 16);
  u[31] = static_cast<unsigned char>(crc >> 8);
  u[32] = static_cast<unsigned char>(crc);
  write_bytes(dir / name, bytes.data(), bytes.size());
  return dir / name;
}

TEST(Png, AbsurdDimensionsAreRefusedBeforeAllocation) {
  const fs::path huge = png_claiming("huge.png", 1000000, 1000000);
  expect_image_error([&] { (void)read_png_gray8(huge); }, huge, "exceeds user limit");
}

// Claims within libpng's side limit that the file cannot back: 16384 x 16384 is over the pixel
// limit; 8192 x 8192 gray needs 64 MiB of pixels, at least 65 KB deflated, in a 70-byte file.
// Each is refused before the image is allocated (the reader runs with 16 MiB to spare).
TEST(Png, ClaimsTheFileCannotHoldAreRefusedBeforeAllocation) {
  auto read_capped = [](const fs::path& path) {
    return testing::what_with_memory_cap(16u << 20, [&] { (void)read_png_gray8(path); });
  };
  const fs::path over = png_claiming("over.png", 16384, 16384);
  std::string what = read_capped(over);
  EXPECT_NE(what.find("over.png: image too large (16384x16384; limit 67108864 pixels)"),
            std::string::npos)
      << what;
  const fs::path empty = png_claiming("empty.png", 8192, 8192);
  what = read_capped(empty);
  EXPECT_NE(what.find("empty.png: truncated: 8192x8192 pixels need at least 65035 bytes"),
            std::string::npos)
      << what;
}

TEST(Png, WriteFailuresNameTheFile) {
  const fs::path dir = testing::scratch_dir();
  const fs::path target = dir / "no_such_dir" / "a.png";
  fs::path tmp = target;
  tmp += ".tmp";
  expect_image_error([&] { write_png(target, ImageRGB8(2, 2)); }, tmp, "cannot create");
  expect_image_error([&] { write_png(dir / "e.png", ImageRGB8()); }, dir / "e.png", "empty");
}

TEST(Png, EncodeInMemoryMatchesFile) {
  const fs::path dir = testing::scratch_dir();
  const auto rgb = random_image<ImageRGB8>(31, 17, 6);
  const std::vector<std::uint8_t> bytes = encode_png(rgb);
  ASSERT_GT(bytes.size(), 8u);
  write_bytes(dir / "mem.png", reinterpret_cast<const char*>(bytes.data()), bytes.size());
  EXPECT_EQ(read_png_rgb8(dir / "mem.png"), rgb);
  write_png(dir / "file.png", rgb);
  const std::vector<char> file_bytes = read_bytes(dir / "file.png");
  const std::vector<std::uint8_t> file_unsigned(file_bytes.begin(), file_bytes.end());
  EXPECT_EQ(bytes, file_unsigned);
}

}  // namespace
}  // namespace probeless
