// The occlusion stages given the objects' rectangle (OcclusionInputs::objects) compute only
// there and around it, with the same result as over the whole frame: the hole cores inside
// the rectangle, and the shipped CVF's whole matte. Each run follows one on another scene, so
// what a stage leaves outside the rectangle is stale, as it is in the service.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "kernels/occlusion/cvf/cvf_matte.hpp"
#include "kernels/occlusion/cvf/hole_core.hpp"
#include "kernels/occlusion/cvf/hole_core_reference.hpp"
#include "kernels/occlusion/method_registry.hpp"
#include "support/cl_context.hpp"

namespace probeless::occlusion {
namespace {

using testing::cl_context;

struct Scene {
  ImageRGB8 colour;
  DepthImage depth;
  ImageF virt;
};

// A textured wall at 2 m with 10 % single-pixel holes, a hand without depth (a wide hole, a
// core at any radius used here) at `hand`, and the virtual object (1.2 m) on `object`.
Scene scene(int w, int h, const PixelRect& object, const PixelRect& hand, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> grain(-12, 12), pick(0, 9);
  Scene s{ImageRGB8(w, h), DepthImage(w, h), ImageF(w, h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool on_hand = hand.contains(x, y);
      const int base[3] = {on_hand                 ? 200
                           : (x / 24 + y / 24) % 2 ? 90
                                                   : 170,
                           on_hand ? 150 : 120, on_hand ? 125 : 130};
      for (int c = 0; c < 3; ++c)
        s.colour.at(x, y, c) = static_cast<std::uint8_t>(std::clamp(base[c] + grain(rng), 0, 255));
      s.depth.at(x, y) = on_hand || pick(rng) == 0 ? 0 : 2000;
      s.virt.at(x, y) = object.contains(x, y) ? 1200.0F : 0.0F;
    }
  return s;
}

template <typename T, int C>
bool equal_inside(const Image<T, C>& a, const Image<T, C>& b, const PixelRect& r) {
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x)
      for (int c = 0; c < C; ++c)
        if (a.at(x, y, c) != b.at(x, y, c)) return false;
  return true;
}

// Rectangles inside, across the border, at a corner, not a multiple of the column pass's 16
// lanes, empty and the whole frame.
std::vector<PixelRect> rects(int w, int h) {
  return {{37, 21, 150, 98},     {-5, 60, 40, h + 9}, {w - 30, h - 17, w + 4, h}, {0, 0, 1, 1}, {},
          PixelRect::whole(w, h)};
}

TEST(HoleCore, OnlyTheNeededPixelsAreComputedAndRight) {
  auto& ctx = cl_context();
  const int w = 203, h = 131, r = 9;
  HoleCoreFill fill(ctx);
  for (const PixelRect& needed : rects(w, h)) {
    const auto other = scene(w, h, {}, {0, 0, w, h / 2}, 1);
    const DeviceImage<std::uint16_t, 1> stale(ctx, other.depth);
    fill.run(stale, r);
    fill.mark_near_occluders();
    const auto s = scene(w, h, {}, {90, 40, 170, 120}, 2);
    const DeviceImage<std::uint16_t, 1> depth(ctx, s.depth);
    const auto got = fill.run(depth, r, nullptr, needed).download(ctx.queue());
    const auto got_marked = fill.mark_near_occluders().download(ctx.queue());
    const PixelRect inside = intersect(needed, PixelRect::whole(w, h));
    EXPECT_TRUE(equal_inside(got, fill_hole_cores_reference(s.depth, r), inside))
        << needed.x0 << "," << needed.y0 << " " << needed.x1 << "," << needed.y1;
    EXPECT_TRUE(equal_inside(got_marked, mark_near_occluders_reference(s.depth, r), inside))
        << "marked, " << needed.x0 << "," << needed.y0 << " " << needed.x1 << "," << needed.y1;
  }
}

// The service's case: the renderer's rectangle around the object (one pixel wider), a hand
// without depth over part of it, CVF as shipped (hole cores on) and with near occluders (which
// read the whole frame's depth, so the cores then run over it all).
TEST(CvfMatte, TheObjectsRectangleGivesTheWholeFramesMatte) {
  auto& ctx = cl_context();
  const int w = 320, h = 240;
  for (const bool near_occluders : {false, true}) {
    MethodParams p;
    p.cvf.near_occluders = near_occluders;
    auto whole = make_method(ctx, "cvf", p), cut = make_method(ctx, "cvf", p);
    const PixelRect objects[] = {{60, 40, 260, 220}, {0, 100, 140, 240}, {250, 0, 320, 60}};
    for (const PixelRect& object : objects) {
      const auto other = scene(w, h, {10, 10, 300, 230}, {0, 0, 80, 240}, 3);
      const DeviceImageRGB8 other_colour(ctx, other.colour);
      const DeviceImage<std::uint16_t, 1> other_depth(ctx, other.depth);
      const DeviceImageF other_virt(ctx, other.virt);
      DeviceImageF alpha_whole, alpha_cut;
      cut->process({&other_colour, &other_depth, &other_virt}, alpha_cut);
      const auto s = scene(w, h, object, {150, 60, 230, 200}, 4);
      const DeviceImageRGB8 colour(ctx, s.colour);
      const DeviceImage<std::uint16_t, 1> depth(ctx, s.depth);
      const DeviceImageF virt(ctx, s.virt);
      const PixelRect drawn = grown(object, 1, w, h);
      const OcclusionInputs in_whole{&colour, &depth, &virt};
      const OcclusionInputs in_cut{&colour, &depth, &virt, drawn};
      whole->process(in_whole, alpha_whole);
      cut->process(in_cut, alpha_cut);
      const auto a = alpha_whole.download(ctx.queue()), b = alpha_cut.download(ctx.queue());
      EXPECT_TRUE(std::equal(a.elements().begin(), a.elements().end(), b.elements().begin()))
          << "near occluders " << near_occluders << ", object at " << object.x0 << "," << object.y0;
      // The stabiliser reads the judged depth on the object only.
      const auto ja = whole->as_judged(in_whole).real_depth_mm->download(ctx.queue());
      const auto jb = cut->as_judged(in_cut).real_depth_mm->download(ctx.queue());
      EXPECT_TRUE(equal_inside(ja, jb, drawn));
    }
  }
}

// What the first kernel leaves for the filters (categories, band, colour models of the frame
// and the tiles) over the whole frame, where the rows far from the rectangle are filled, not
// computed; after a frame whose object covered the frame.
TEST(CvfMatte, TheObjectsRectangleGivesTheWholeFramesCategoriesAndModels) {
  auto& ctx = cl_context();
  const int w = 320, h = 240;
  CvfMatte whole(ctx, CvfLocalParams{}, true), cut(ctx, CvfLocalParams{}, true);
  for (const PixelRect& object : {PixelRect{60, 40, 260, 220}, PixelRect{0, 200, 50, 240},
                                  PixelRect{100, 0, 200, 3}, PixelRect{}}) {
    const auto other = scene(w, h, {0, 0, w, h}, {0, 0, 80, 240}, 5);
    const DeviceImageRGB8 other_colour(ctx, other.colour);
    const DeviceImage<std::uint16_t, 1> other_depth(ctx, other.depth);
    const DeviceImageF other_virt(ctx, other.virt);
    DeviceImageF alpha_whole, alpha_cut;
    cut.process({&other_colour, &other_depth, &other_virt}, alpha_cut);
    const auto s = scene(w, h, object, {150, 60, 230, 200}, 6);
    const DeviceImageRGB8 colour(ctx, s.colour);
    const DeviceImage<std::uint16_t, 1> depth(ctx, s.depth);
    const DeviceImageF virt(ctx, s.virt);
    whole.process({&colour, &depth, &virt}, alpha_whole);
    cut.process({&colour, &depth, &virt, grown(object, 1, w, h)}, alpha_cut);
    const auto a = whole.download_trace(), b = cut.download_trace();
    const auto where = ::testing::Message() << "object at " << object.x0 << "," << object.y0;
    EXPECT_EQ(a.categories, b.categories) << where;
    EXPECT_EQ(a.band, b.band) << where;
    EXPECT_EQ(a.models.infront, b.models.infront) << where;
    EXPECT_EQ(a.models.behind, b.models.behind) << where;
    EXPECT_EQ(a.tiles.infront, b.tiles.infront) << where;
    EXPECT_EQ(a.tiles.behind, b.tiles.behind) << where;
    EXPECT_EQ(alpha_whole.download(ctx.queue()), alpha_cut.download(ctx.queue())) << where;
  }
}

}  // namespace
}  // namespace probeless::occlusion
