#include "drivers/io/png.hpp"

#include <png.h>
#include <zlib.h>

#include <bit>
#include <cerrno>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <system_error>

#include "core/read_limits.hpp"

namespace probeless {
namespace {

// libpng reports errors through a callback that must not return: it long-jumps back to the
// setjmp of the call that started the operation. longjmp is only well defined in C++ when no
// destructor is skipped, so the functions below that call setjmp (marked "jump target") hold
// trivially destructible locals only and every C++ object lives in their callers. The frames
// jumped over are libpng's own (C) and the error callback.

// Chosen by measurement on 640x480 frames (docs/formats.md "PNG conventions"): the Sub filter
// with zlib's run-length strategy encodes a colour frame in about 14 ms, a depth frame in 6 ms
// and a 16-bit raw frame in 20 ms, faster than level 1's default strategy (22/8/37 ms) and
// within a few percent of level 6's size (which takes 60-180 ms).
constexpr int kCompressionLevel = 1;
constexpr int kCompressionStrategy = Z_RLE;
constexpr int kWriteFilters = PNG_FILTER_SUB;
// Bounds a corrupt header's claims before anything is allocated (core/read_limits.hpp).
constexpr auto kMaxSide = static_cast<png_uint_32>(read_limits::kMaxImageSide);
constexpr bool kLittleEndianHost = std::endian::native == std::endian::little;

struct PngErrorState {
  char message[256] = {};
  char warning[256] = {};  // the last one: libpng often explains an error in a warning first
};

void on_png_error(png_structp png, png_const_charp message) {
  if (auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png))) {
    std::snprintf(state->message, sizeof state->message, "%s", message ? message : "error");
  }
  png_longjmp(png, 1);
}

void on_png_warning(png_structp png, png_const_charp message) {
  if (auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png))) {
    std::snprintf(state->warning, sizeof state->warning, "%s", message ? message : "warning");
  }
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using UniqueFile = std::unique_ptr<std::FILE, FileCloser>;

std::string errno_message(int err) {
  return std::generic_category().message(err);
}

// libpng's read or write struct and its info struct, destroyed together.
enum class PngDirection { Read, Write };
template <PngDirection D>
class PngHandle {
 public:
  explicit PngHandle(PngErrorState* errors) {
    png_ =
        D == PngDirection::Read
            ? png_create_read_struct(PNG_LIBPNG_VER_STRING, errors, on_png_error, on_png_warning)
            : png_create_write_struct(PNG_LIBPNG_VER_STRING, errors, on_png_error, on_png_warning);
    if (png_) info_ = png_create_info_struct(png_);
  }
  ~PngHandle() {
    if constexpr (D == PngDirection::Read) {
      png_destroy_read_struct(&png_, &info_, nullptr);
    } else {
      png_destroy_write_struct(&png_, &info_);
    }
  }
  PngHandle(const PngHandle&) = delete;
  PngHandle& operator=(const PngHandle&) = delete;

  bool valid() const { return png_ && info_; }
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};
using PngReadHandle = PngHandle<PngDirection::Read>;
using PngWriteHandle = PngHandle<PngDirection::Write>;

// ---- reading ----------------------------------------------------------------------------

enum class ReadTarget { RGB8, Gray8, Gray16, RGB16 };

struct PngLayout {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int colour_type = 0;
  int channels = 0;
  std::size_t row_bytes = 0;
};

// Jump target. Reads the header (after the 8 signature bytes already consumed).
bool read_header(png_structp png, png_infop info, std::FILE* file, PngLayout* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
  png_set_user_limits(png, kMaxSide, kMaxSide);
  png_read_info(png, info);
  out->width = png_get_image_width(png, info);
  out->height = png_get_image_height(png, info);
  out->bit_depth = png_get_bit_depth(png, info);
  out->colour_type = png_get_color_type(png, info);
  return true;
}

// Jump target. Sets the conversions for `target` and reports the resulting row layout.
bool set_transforms(png_structp png, png_infop info, ReadTarget target, PngLayout* out) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int colour_type = out->colour_type;
  if (target == ReadTarget::RGB8 || target == ReadTarget::Gray8) {
    if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (colour_type == PNG_COLOR_TYPE_GRAY && out->bit_depth < 8) {
      png_set_expand_gray_1_2_4_to_8(png);
    }
    if (out->bit_depth == 16) png_set_scale_16(png);
    if ((colour_type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS)) {
      png_set_strip_alpha(png);
    }
    const bool is_colour = (colour_type & PNG_COLOR_MASK_COLOR) != 0;
    if (target == ReadTarget::RGB8 && !is_colour) png_set_gray_to_rgb(png);
    // Rec. 709 luma weights (libpng's defaults without a cHRM chunk).
    if (target == ReadTarget::Gray8 && is_colour) {
      png_set_rgb_to_gray_fixed(png, PNG_ERROR_ACTION_NONE, -1, -1);
    }
  } else if (kLittleEndianHost) {
    png_set_swap(png);  // PNG stores 16-bit samples big-endian
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  out->channels = png_get_channels(png, info);
  out->bit_depth = png_get_bit_depth(png, info);
  out->row_bytes = png_get_rowbytes(png, info);
  return true;
}

// Jump target.
bool read_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);  // checks the trailing chunks: a missing IEND is truncation
  return true;
}

// The bytes of a non-interlaced image as stored before deflating: a filter byte and the
// samples of every row (interlacing only adds filter bytes).
std::uint64_t stored_bytes(std::uint64_t width, std::uint64_t height, int colour_type,
                           int bit_depth) {
  std::uint64_t channels = 1;  // gray, palette
  if (colour_type == PNG_COLOR_TYPE_GRAY_ALPHA) channels = 2;
  if (colour_type == PNG_COLOR_TYPE_RGB) channels = 3;
  if (colour_type == PNG_COLOR_TYPE_RGB_ALPHA) channels = 4;
  const auto bits = width * channels * static_cast<std::uint64_t>(bit_depth);
  return height * (1 + (bits + 7) / 8);
}

std::string describe_layout(int bit_depth, int colour_type) {
  const char* kind = "unknown colour type";
  switch (colour_type) {
    case PNG_COLOR_TYPE_GRAY:
      kind = "gray";
      break;
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      kind = "gray+alpha";
      break;
    case PNG_COLOR_TYPE_RGB:
      kind = "RGB";
      break;
    case PNG_COLOR_TYPE_RGB_ALPHA:
      kind = "RGBA";
      break;
    case PNG_COLOR_TYPE_PALETTE:
      kind = "palette";
      break;
    default:
      break;
  }
  return std::to_string(bit_depth) + "-bit " + kind;
}

std::string libpng_failure(const PngErrorState& errors) {
  std::string text = std::string("truncated or corrupt PNG (libpng: ") + errors.message;
  if (errors.warning[0] != '\0') text += std::string("; ") + errors.warning;
  return text + ")";
}

template <typename ImageT>
ImageT read_png_as(const std::filesystem::path& path, ReadTarget target) {
  UniqueFile file(std::fopen(path.c_str(), "rb"));
  if (!file) throw ImageFileError(path, "cannot open: " + errno_message(errno));

  png_byte signature[8];
  const std::size_t got = std::fread(signature, 1, sizeof signature, file.get());
  if (std::ferror(file.get())) throw ImageFileError(path, "cannot read: " + errno_message(errno));
  if (got == 0) throw ImageFileError(path, "empty file (expected a PNG image)");
  if (got < sizeof signature || png_sig_cmp(signature, 0, sizeof signature) != 0) {
    throw ImageFileError(path, "not a PNG file (bad signature)");
  }

  // Its size bounds what the header may claim (not known for a pipe: no bound then).
  std::error_code size_error;
  std::uintmax_t file_bytes = std::filesystem::file_size(path, size_error);
  if (size_error) file_bytes = UINTMAX_MAX;

  PngErrorState errors;
  PngReadHandle handle(&errors);
  if (!handle.valid()) throw ImageFileError(path, "libpng could not allocate a reader");

  PngLayout layout;
  if (!read_header(handle.png(), handle.info(), file.get(), &layout)) {
    throw ImageFileError(path, libpng_failure(errors));
  }
  const int original_depth = layout.bit_depth;
  const int original_type = layout.colour_type;
  if (target == ReadTarget::Gray16 &&
      (original_depth != 16 || original_type != PNG_COLOR_TYPE_GRAY)) {
    throw ImageFileError(path, "expected a 16-bit single-channel PNG, got " +
                                   describe_layout(original_depth, original_type));
  }
  if (target == ReadTarget::RGB16 &&
      (original_depth != 16 || original_type != PNG_COLOR_TYPE_RGB)) {
    throw ImageFileError(
        path, "expected a 16-bit RGB PNG, got " + describe_layout(original_depth, original_type));
  }
  if (!set_transforms(handle.png(), handle.info(), target, &layout)) {
    throw ImageFileError(path, libpng_failure(errors));
  }

  using T = typename ImageT::value_type;
  const std::size_t expected_row = std::size_t{layout.width} * ImageT::channels * sizeof(T);
  if (layout.channels != ImageT::channels || layout.bit_depth != 8 * static_cast<int>(sizeof(T)) ||
      layout.row_bytes != expected_row) {
    throw ImageFileError(path, "cannot convert " + describe_layout(original_depth, original_type) +
                                   " to " + std::to_string(ImageT::channels) + " channel(s) of " +
                                   std::to_string(8 * sizeof(T)) + " bits");
  }
  if (!read_limits::image_size_ok(layout.width, layout.height)) {
    throw ImageFileError(path, "image too large (" + std::to_string(layout.width) + "x" +
                                   std::to_string(layout.height) + "; limit " +
                                   std::to_string(read_limits::kMaxImagePixels) + " pixels)");
  }
  // The pixels are deflated: the file needs at least 1/1032 of their bytes as stored.
  const std::uint64_t stored =
      stored_bytes(layout.width, layout.height, original_type, original_depth);
  const std::uint64_t least = stored / read_limits::kMaxDeflateRatio;
  if (file_bytes < least) {
    throw ImageFileError(path, "truncated: " + std::to_string(layout.width) + "x" +
                                   std::to_string(layout.height) + " pixels need at least " +
                                   std::to_string(least) + " bytes, the file has " +
                                   std::to_string(file_bytes));
  }

  ImageT image(static_cast<int>(layout.width), static_cast<int>(layout.height));
  std::vector<png_bytep> rows(layout.height);
  for (png_uint_32 y = 0; y < layout.height; ++y) {
    rows[y] = reinterpret_cast<png_bytep>(image.row(static_cast<int>(y)));
  }
  if (!read_rows(handle.png(), handle.info(), rows.data())) {
    throw ImageFileError(path, libpng_failure(errors));
  }
  return image;
}

// ---- writing ----------------------------------------------------------------------------

struct WriteSpec {
  png_uint_32 width;
  png_uint_32 height;
  int bit_depth;
  int colour_type;
};

// Jump target. `file` may be null when the caller has installed its own write function.
bool write_image(png_structp png, png_infop info, std::FILE* file, const WriteSpec* spec,
                 png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  if (file) png_init_io(png, file);
  png_set_IHDR(png, info, spec->width, spec->height, spec->bit_depth, spec->colour_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, kCompressionLevel);
  png_set_compression_strategy(png, kCompressionStrategy);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, kWriteFilters);
  png_write_info(png, info);
  if (spec->bit_depth == 16 && kLittleEndianHost) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

template <typename ImageT>
constexpr int colour_type_for() {
  switch (ImageT::channels) {
    case 1:
      return PNG_COLOR_TYPE_GRAY;
    case 3:
      return PNG_COLOR_TYPE_RGB;
    case 4:
      return PNG_COLOR_TYPE_RGB_ALPHA;
    default:
      return -1;
  }
}

template <typename ImageT>
WriteSpec write_spec(const ImageT& image) {
  static_assert(colour_type_for<ImageT>() >= 0, "no PNG colour type for this channel count");
  return {static_cast<png_uint_32>(image.width()), static_cast<png_uint_32>(image.height()),
          static_cast<int>(8 * sizeof(typename ImageT::value_type)), colour_type_for<ImageT>()};
}

template <typename ImageT>
std::vector<png_bytep> row_pointers(const ImageT& image) {
  // libpng's write API takes non-const rows but never writes through them.
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height()));
  for (int y = 0; y < image.height(); ++y) {
    rows[static_cast<std::size_t>(y)] =
        const_cast<png_bytep>(reinterpret_cast<const png_byte*>(image.row(y)));
  }
  return rows;
}

// Removes the temporary file unless released (the write completed and was renamed).
class TempFileGuard {
 public:
  explicit TempFileGuard(std::filesystem::path path) : path_(std::move(path)) {}
  ~TempFileGuard() {
    if (!path_.empty()) {
      std::error_code ignored;
      std::filesystem::remove(path_, ignored);
    }
  }
  TempFileGuard(const TempFileGuard&) = delete;
  TempFileGuard& operator=(const TempFileGuard&) = delete;
  void release() { path_.clear(); }

 private:
  std::filesystem::path path_;
};

template <typename ImageT>
void write_png_file(const std::filesystem::path& path, const ImageT& image) {
  if (image.empty()) throw ImageFileError(path, "cannot write an empty image as PNG");
  std::filesystem::path tmp = path;
  tmp += ".tmp";

  UniqueFile file(std::fopen(tmp.c_str(), "wb"));
  if (!file) throw ImageFileError(tmp, "cannot create: " + errno_message(errno));
  TempFileGuard guard(tmp);

  PngErrorState errors;
  {
    PngWriteHandle handle(&errors);
    if (!handle.valid()) throw ImageFileError(path, "libpng could not allocate a writer");
    const WriteSpec spec = write_spec(image);
    std::vector<png_bytep> rows = row_pointers(image);
    if (!write_image(handle.png(), handle.info(), file.get(), &spec, rows.data())) {
      throw ImageFileError(tmp, std::string("cannot write PNG (libpng: ") + errors.message + ")");
    }
  }
  if (std::fclose(file.release()) != 0) {
    throw ImageFileError(tmp, "cannot write: " + errno_message(errno));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw ImageFileError(path, "cannot rename " + tmp.string() + ": " + ec.message());
  guard.release();
}

void append_to_vector(png_structp png, png_bytep data, std::size_t length) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  bool failed = false;
  try {
    out->insert(out->end(), data, data + length);
  } catch (...) {
    failed = true;  // no exception may cross libpng; report through its own error path
  }
  if (failed) png_error(png, "out of memory");
}

void flush_nothing(png_structp) {}

}  // namespace

ImageRGB8 read_png_rgb8(const std::filesystem::path& path) {
  return read_png_as<ImageRGB8>(path, ReadTarget::RGB8);
}
ImageGray8 read_png_gray8(const std::filesystem::path& path) {
  return read_png_as<ImageGray8>(path, ReadTarget::Gray8);
}
DepthImage read_png_depth16(const std::filesystem::path& path) {
  return read_png_as<DepthImage>(path, ReadTarget::Gray16);
}
ImageRGB16 read_png_rgb16(const std::filesystem::path& path) {
  return read_png_as<ImageRGB16>(path, ReadTarget::RGB16);
}

void write_png(const std::filesystem::path& path, const ImageRGB8& image) {
  write_png_file(path, image);
}
void write_png(const std::filesystem::path& path, const ImageGray8& image) {
  write_png_file(path, image);
}
void write_png(const std::filesystem::path& path, const DepthImage& image) {
  write_png_file(path, image);
}
void write_png(const std::filesystem::path& path, const ImageRGB16& image) {
  write_png_file(path, image);
}
void write_png(const std::filesystem::path& path, const ImageRGBA8& image) {
  write_png_file(path, image);
}

std::vector<std::uint8_t> encode_png(const ImageRGB8& image) {
  if (image.empty()) throw ImageFileError("<memory>", "cannot encode an empty image as PNG");
  std::vector<std::uint8_t> out;
  out.reserve(image.size_bytes() / 2);
  PngErrorState errors;
  PngWriteHandle handle(&errors);
  if (!handle.valid()) throw ImageFileError("<memory>", "libpng could not allocate a writer");
  png_set_write_fn(handle.png(), &out, append_to_vector, flush_nothing);
  const WriteSpec spec = write_spec(image);
  std::vector<png_bytep> rows = row_pointers(image);
  if (!write_image(handle.png(), handle.info(), nullptr, &spec, rows.data())) {
    throw ImageFileError("<memory>",
                         std::string("cannot encode PNG (libpng: ") + errors.message + ")");
  }
  return out;
}

}  // namespace probeless
