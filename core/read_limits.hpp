#pragma once
// What a file may claim before anything is allocated for it: every reader of a file format
// (images, models, calibrations) checks a header's sizes and counts against these limits AND
// against the file's own size (a claim needs at least so many bytes of data behind it)
// before it allocates. The values and their reasons are listed in docs/security.md
// ("Reader limits"); change them here and there together.
#include <cstddef>
#include <cstdint>

namespace probeless::read_limits {

// The largest width or height of an image or a camera. The widest image the project reads is
// an equirectangular light probe: 16384 x 8192 at most; 32768 leaves room and keeps every
// index (x * channels, y * row) within int.
inline constexpr std::int64_t kMaxImageSide = 32768;

// The most pixels in one image (2^26 = 8192 x 8192 or 16384 x 4096): the float RGB image that
// a probe becomes is then at most 768 MiB, which a 2 GB board can still hold beside the
// service. A camera frame is far below (640 x 480, a 1296 x 972 fisheye).
inline constexpr std::int64_t kMaxImagePixels = std::int64_t{1} << 26;

// The largest image file read whole into memory (Radiance .hdr): a flat RGBE image at the pixel
// limit is 256 MiB, so 1 GiB is no legitimate file's size.
inline constexpr std::int64_t kMaxImageFileBytes = std::int64_t{1} << 30;

// An OpenEXR chunk (a block of 1 to 256 scanlines, or a tile) costs at least its 8-byte entry
// in the offset table and its 8-byte header: a file smaller than that for the chunks its data
// window needs is truncated (EXR's codecs compress too well to bound the data itself).
inline constexpr std::int64_t kMinExrBytesPerChunk = 16;
inline constexpr std::int64_t kMaxExrScanlinesPerChunk = 256;

// zlib's largest compression factor (zlib technical details: 1032:1, a run of one byte): a
// deflate stream (PNG) of N bytes never inflates to more than 1032 N bytes, so a header that
// claims more pixel bytes than that is lying about the file it is in.
inline constexpr std::int64_t kMaxDeflateRatio = 1032;

// The largest 3D model file (glTF JSON or binary, OBJ text: the parsers hold all of it), and
// the most elements in one glTF accessor (16.7 M vertices, or the indices of 5.6 M triangles:
// a scanned room; its VEC4 read as doubles while converting is 512 MiB).
inline constexpr std::int64_t kMaxModelFileBytes = std::int64_t{1} << 30;
inline constexpr std::int64_t kMaxModelElements = std::int64_t{1} << 24;

// True when width x height is an image size a reader may allocate.
inline constexpr bool image_size_ok(std::int64_t width, std::int64_t height) {
  return width > 0 && height > 0 && width <= kMaxImageSide && height <= kMaxImageSide &&
         width * height <= kMaxImagePixels;
}

}  // namespace probeless::read_limits
