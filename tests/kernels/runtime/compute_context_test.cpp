#include "kernels/runtime/compute_context.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "kernels/runtime/device_image.hpp"
#include "support/cl_context.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

namespace fs = std::filesystem;
using testing::cl_context;

// A tiny program; the scratch cache directory is fresh per test, so the first build is
// always from source.
constexpr std::string_view kAddOne = R"(
__kernel void add_one(__global int* v, int n) {
  const int i = get_global_id(0);
  if (i < n) v[i] += ADD;
}
)";

ComputeOptions options_with_cache(const fs::path& dir) {
  ComputeOptions o;
  o.cache_dir = dir;
  return o;
}

std::vector<fs::path> cache_files(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  return files;
}

// Runs the program to prove that whatever the cache produced is executable.
void expect_program_works(ComputeContext& ctx, const cl::Program& program) {
  cl::Kernel k(program, "add_one");
  std::vector<int> host{1, 2, 3};
  cl::Buffer buf(ctx.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(int) * 3,
                 host.data());
  k.setArg(0, buf);
  k.setArg(1, 3);
  ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(3));
  ctx.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof(int) * 3, host.data());
  EXPECT_EQ(host, (std::vector<int>{3, 4, 5}));
}

TEST(ComputeContext, DescribesTheDefaultDevice) {
  const auto text = cl_context().describe();
  EXPECT_NE(text.find(cl_context().info().device_name), std::string::npos) << text;
  EXPECT_GT(cl_context().info().compute_units, 0U);
}

TEST(ComputeContext, SecondContextLoadsTheBinaryFromDisk) {
  const auto dir = testing::scratch_dir();
  {
    ComputeContext first(options_with_cache(dir));
    auto p = first.program("add_one", kAddOne, "-DADD=2");
    first.program("add_one", kAddOne, "-DADD=2");  // same context: from memory
    EXPECT_EQ(first.cache_stats().source_builds, 1);
    EXPECT_EQ(first.cache_stats().memory_hits, 1);
    EXPECT_EQ(first.cache_stats().disk_hits, 0);
    ASSERT_EQ(cache_files(dir).size(), 1U);
  }
  ComputeContext second(options_with_cache(dir));
  const auto p = second.program("add_one", kAddOne, "-DADD=2");
  EXPECT_EQ(second.cache_stats().disk_hits, 1);
  EXPECT_EQ(second.cache_stats().source_builds, 0);
  expect_program_works(second, p);
}

TEST(ComputeContext, OptionsAreInTheKey) {
  const auto dir = testing::scratch_dir();
  ComputeContext ctx(options_with_cache(dir));
  ctx.program("add_one", kAddOne, "-DADD=2");
  ctx.program("add_one", kAddOne, "-DADD=3");
  EXPECT_EQ(ctx.cache_stats().source_builds, 2);
  EXPECT_EQ(cache_files(dir).size(), 2U);
}

TEST(ComputeContext, CorruptCacheFileIsDiscardedAndRebuilt) {
  const auto dir = testing::scratch_dir();
  {
    ComputeContext first(options_with_cache(dir));
    first.program("add_one", kAddOne, "-DADD=2");
  }
  const auto files = cache_files(dir);
  ASSERT_EQ(files.size(), 1U);
  const auto size = fs::file_size(files[0]);
  {  // flip a byte in the middle of the binary, as a bad sector or a torn write would
    std::fstream f(files[0], std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(size / 2));
    char c = 0;
    f.read(&c, 1);
    c = static_cast<char>(c ^ 0x5a);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.write(&c, 1);
  }
  {
    ComputeContext second(options_with_cache(dir));
    const auto p = second.program("add_one", kAddOne, "-DADD=2");
    EXPECT_EQ(second.cache_stats().discarded_files, 1);
    EXPECT_EQ(second.cache_stats().source_builds, 1);
    EXPECT_EQ(second.cache_stats().disk_hits, 0);
    expect_program_works(second, p);
  }
  // A truncated (zero-length) file, as a crash between create and write leaves it.
  { std::ofstream truncate(files[0], std::ios::binary | std::ios::trunc); }
  {
    ComputeContext third(options_with_cache(dir));
    third.program("add_one", kAddOne, "-DADD=2");
    EXPECT_EQ(third.cache_stats().discarded_files, 1);
    EXPECT_EQ(third.cache_stats().source_builds, 1);
  }
  ComputeContext fourth(options_with_cache(dir));  // and the rewritten file is good again
  fourth.program("add_one", kAddOne, "-DADD=2");
  EXPECT_EQ(fourth.cache_stats().disk_hits, 1);
  EXPECT_EQ(cache_files(dir).size(), 1U);  // no temporaries left behind
}

TEST(ComputeContext, BrokenSourceThrowsClBuildErrorWithTheLog) {
  constexpr std::string_view broken = R"(
__kernel void broken(__global int* v) { v[0] = undeclared_thing_42; }
)";
  try {
    cl_context().program("broken_on_purpose", broken, "-DSOMETHING=1");
    FAIL() << "expected ClBuildError";
  } catch (const ClBuildError& e) {
    EXPECT_EQ(e.program_name(), "broken_on_purpose");
    EXPECT_EQ(e.options(), "-DSOMETHING=1");
    EXPECT_NE(e.log().find("undeclared_thing_42"), std::string::npos) << e.log();
    EXPECT_NE(std::string(e.what()).find("undeclared_thing_42"), std::string::npos);
  }
}

TEST(ComputeContext, NoMatchingDeviceListsWhatThereIs) {
  ComputeOptions o;
  o.selector.platform_substring = "no such platform xyz";
  try {
    ComputeContext ctx(o);
    FAIL() << "expected DeviceSelectionError";
  } catch (const DeviceSelectionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no such platform xyz"), std::string::npos) << what;
    EXPECT_NE(what.find(cl_context().info().platform_name), std::string::npos) << what;
  }
}

TEST(ComputeContext, UnwritableCacheStillBuilds) {
  ComputeOptions o = options_with_cache("/proc/probeless-cannot-write-here");
  ComputeContext ctx(o);
  expect_program_works(ctx, ctx.program("add_one", kAddOne, "-DADD=2"));
  EXPECT_EQ(ctx.cache_stats().write_failures, 1);
}

TEST(ProgramCacheDir, FollowsTheEnvironmentInOrder) {
  const auto saved = [](const char* n) {
    const char* v = std::getenv(n);
    return v ? std::optional<std::string>(v) : std::nullopt;
  };
  const char* names[] = {"PROBELESS_CACHE_DIR", "CACHE_DIRECTORY", "XDG_CACHE_HOME", "HOME"};
  std::vector<std::optional<std::string>> old;
  for (auto* n : names) old.push_back(saved(n));

  setenv("PROBELESS_CACHE_DIR", "/a", 1);
  setenv("CACHE_DIRECTORY", "/b:/other", 1);
  setenv("XDG_CACHE_HOME", "/c", 1);
  setenv("HOME", "/d", 1);
  EXPECT_EQ(default_program_cache_dir(), fs::path("/a/opencl"));
  unsetenv("PROBELESS_CACHE_DIR");
  EXPECT_EQ(default_program_cache_dir(), fs::path("/b/opencl"));
  unsetenv("CACHE_DIRECTORY");
  EXPECT_EQ(default_program_cache_dir(), fs::path("/c/probeless/opencl"));
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(default_program_cache_dir(), fs::path("/d/.cache/probeless/opencl"));

  for (std::size_t i = 0; i < old.size(); ++i) {
    if (old[i])
      setenv(names[i], old[i]->c_str(), 1);
    else
      unsetenv(names[i]);
  }
}

template <typename ImageT>
ImageT random_image(int w, int h, unsigned seed) {
  ImageT image(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dist(0, 60000);
  for (auto& v : image.elements()) v = static_cast<typename ImageT::value_type>(dist(rng));
  return image;
}

TEST(DeviceImage, RoundTripsEverySize) {
  auto& ctx = cl_context();
  for (const auto& [w, h] : testing::kernel_test_sizes()) {
    const auto rgb = random_image<ImageRGB8>(w, h, 1);
    const auto depth = random_image<DepthImage>(w, h, 2);
    const auto f = random_image<ImageF>(w, h, 3);
    EXPECT_EQ(DeviceImageRGB8(ctx, rgb).download(ctx.queue()), rgb);
    EXPECT_EQ(DeviceDepthImage(ctx, depth).download(ctx.queue()), depth);
    EXPECT_EQ(DeviceImageF(ctx, f).download(ctx.queue()), f);
  }
}

TEST(DeviceImage, EmptyImagesHoldNoBuffer) {
  auto& ctx = cl_context();
  DeviceImage<float, 1> empty(ctx, ImageF(0, 7));
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.download(ctx.queue()).height(), 7);
}

TEST(DeviceImage, UploadResizes) {
  auto& ctx = cl_context();
  DeviceImage<float, 1> img;
  const auto f = random_image<ImageF>(5, 4, 9);
  img.upload(ctx.queue(), f);
  EXPECT_TRUE(img.same_size(5, 4));
  EXPECT_EQ(img.download(ctx.queue()), f);
}

TEST(RoundUp, ToTheLocalSize) {
  EXPECT_EQ(round_up(1, 16), 16U);
  EXPECT_EQ(round_up(16, 16), 16U);
  EXPECT_EQ(round_up(17, 16), 32U);
  EXPECT_EQ(round_up(641, 16), 656U);
}

}  // namespace
}  // namespace probeless

namespace probeless {
namespace {

// run_2d over a rectangle: the work-items' ids are the pixels' own coordinates (a global
// offset), every pixel of the rectangle is visited, and the rounding up to the local size
// reaches at most a local size's width and height past it.
TEST(ComputeContext, Run2dOverARectangleVisitsItsPixelsByTheirCoordinates) {
  auto& ctx = testing::cl_context();
  const int w = 53, h = 37;
  ::cl::Kernel mark = ctx.kernel("mark_pixels", R"(
__kernel void mark_pixels(__global int* v, int w, int h) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < w && y < h) v[y * w + x] = 1 + y * w + x;
}
)",
                                 "", "mark_pixels");
  const std::size_t lx = ctx.local_2d()[0], ly = ctx.local_2d()[1];
  for (const PixelRect& r :
       {PixelRect{7, 5, 30, 21}, PixelRect{0, 0, w, h}, PixelRect{52, 36, 53, 37}, PixelRect{}}) {
    std::vector<int> host(static_cast<std::size_t>(w * h), 0);
    ::cl::Buffer buf(ctx.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                     sizeof(int) * host.size(), host.data());
    mark.setArg(0, buf);
    mark.setArg(1, w);
    mark.setArg(2, h);
    ctx.run_2d(mark, r);
    ctx.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof(int) * host.size(), host.data());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int v = host[static_cast<std::size_t>(y * w + x)];
        const bool reachable = x >= r.x0 && y >= r.y0 &&
                               x < r.x0 + static_cast<int>((r.width() + lx - 1) / lx * lx) &&
                               y < r.y0 + static_cast<int>((r.height() + ly - 1) / ly * ly);
        if (r.contains(x, y)) {
          ASSERT_EQ(v, 1 + y * w + x) << x << "," << y;
        } else if (!reachable || r.empty()) {
          ASSERT_EQ(v, 0) << x << "," << y << " outside the rectangle's launch";
        } else {
          ASSERT_TRUE(v == 0 || v == 1 + y * w + x) << x << "," << y;
        }
      }
  }
}

}  // namespace
}  // namespace probeless
