#include "kernels/occlusion/cvf/cvf_matte.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "kernels/occlusion/common/cvf_kernel_args.hpp"
#include "kernels/occlusion/common/vector16_cl.hpp"
#include "kernels/occlusion/cvf/cvf_cl.hpp"
#include "kernels/occlusion/cvf/cvf_local_histogram_cl.hpp"
#include "kernels/occlusion/cvf/cvf_tiles_cl.hpp"
#include "kernels/occlusion/cvf/cvf_vector_cl.hpp"

namespace probeless::occlusion {
namespace {

int low_radius(const GuidedFilterParams& p) {
  return p.subsample == 1
             ? p.radius
             : std::max(1, static_cast<int>(std::lround(double(p.radius) / p.subsample)));
}

const CvfLocalParams& checked(const CvfLocalParams& lp, bool local) {
  const CvfParams& p = lp.cvf;
  if (p.bins_per_channel < 1 || p.bins_per_channel > 16)
    throw std::invalid_argument("cvf: bins per channel must be 1..16");
  if (p.wide.subsample < 1 || p.feather.subsample != 1)
    throw std::invalid_argument("cvf: wide subsample must be >= 1, the feather filter full-res");
  if (p.band_px < 0 || p.wide.radius < 0 || p.feather.radius < 0)
    throw std::invalid_argument("cvf: negative radius");
  // Up to 64 px: wider than any sensor's minimum-range hand at 640 x 480 needs.
  if (lp.hole_core_px < 0 || lp.hole_core_px > 64)
    throw std::invalid_argument("cvf: hole core radius must be 0..64 (px at 640 px width)");
  if (!local) return lp;
  // The tiles' pair of histograms in a work-group's local memory (cvf_local_histogram.cl).
  if (p.bins_per_channel > 8) throw std::invalid_argument("cvf: bins per channel must be 1..8");
  if (lp.tile_px < 1) throw std::invalid_argument("cvf: tile_px must be >= 1");
  // The prior's window counts are bytes: (2 r + 1)^2 <= 255.
  if (lp.prior_radius < 0 || lp.prior_radius > 7)
    throw std::invalid_argument("cvf: prior radius must be 0..7");
  return lp;
}

std::string cvf_options(const CvfLocalParams& lp, bool local) {
  const CvfParams& p = lp.cvf;
  auto o = fmt::format("-DBINS={} -DSUBSAMPLE={} -DLOCAL={}", p.bins_per_channel, p.wide.subsample,
                       local ? 1 : 0);
  if (local)
    o += fmt::format(" -DTILE={} -DPRIOR={} -DSOFT={}", lp.tile_px, lp.prior_radius,
                     lp.soft_where_ambiguous ? 1 : 0);
  return o;
}

CvfLocalParams as_thesis(const CvfParams& p) {
  CvfLocalParams lp;
  lp.cvf = p;
  lp.hole_core_px = 0;  // the thesis treats every hole as "process"
  return lp;
}

// A w x 4h planar image (4 planes of w x h) as an interleaved 4-channel one.
Image<float, 4> from_planes(const ImageF& planes) {
  const int w = planes.width(), h = planes.height() / 4;
  Image<float, 4> out(w, h);
  for (int c = 0; c < 4; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.at(x, y, c) = planes.at(x, c * h + y);
  return out;
}

}  // namespace

CvfLayout resolve(CvfLayout layout, const ComputeContext& ctx) {
  if (layout != CvfLayout::Auto) return layout;
  return ctx.info().type == "CPU" ? CvfLayout::Strips : CvfLayout::Tiles;
}

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfLocalParams& params, bool trace, CvfLayout layout)
    : CvfMatte(ctx, params, true, trace, layout) {}

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfParams& thesis, bool trace, CvfLayout layout)
    : CvfMatte(ctx, as_thesis(thesis), false, trace, layout) {}

CvfMatte::CvfMatte(ComputeContext& ctx, const CvfLocalParams& lp, bool local, bool trace,
                   CvfLayout layout)
    : ctx_(ctx),
      params_(checked(lp, local)),
      local_(local),
      trace_(trace),
      layout_(resolve(layout, ctx)) {
  const CvfParams& params = params_.cvf;
  const auto options = cvf_options(params_, local);
  hist_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, hist_bytes());
  if (local && params_.near_occluders) near_.emplace(ctx, near_occluder_params(params_));
  if (params_.hole_core_px > 0) hole_cores_.emplace(ctx);
  if (layout_ == CvfLayout::Tiles) {
    categoriser_.emplace(ctx, params.categorise);
    if (local) local_costs_.emplace(ctx, params_);
    tile_wide_.emplace(ctx, low_radius(params.wide), params.wide.eps,
                       GuidedFilter::Output::MeanCoefficients);
    tile_feather_.emplace(ctx, params.feather.radius, params.feather.eps,
                          GuidedFilter::Output::VisibilityFromCost);
    auto k = [&](const char* name) {
      return ctx.kernel("cvf_tiles", cl_source::cvf_tiles, options, name);
    };
    histogram_ = k("cvf_histogram");
    cost_pack_ = k(local ? "cvf_cost_image_pack" : "cvf_cost_pack");
    mask_pack_ = k("cvf_mask_pack");
    return;
  }
  if (params.categorise.erosion_px > 16 || params.band_px > 16)
    throw std::invalid_argument("cvf: erosion and band radii must be <= 16");
  wide_.emplace(ctx, low_radius(params.wide), params.wide.eps, StripGuidedFilter::Input::CvfCost,
                StripGuidedFilter::Output::MeanCoefficients, options, trace);
  feather_.emplace(ctx, params.feather.radius, params.feather.eps,
                   StripGuidedFilter::Input::CvfFeather,
                   StripGuidedFilter::Output::VisibilityFromCost, options, trace);
  static const std::string source = std::string(cl_source::vector16) +
                                    std::string(cl_source::cvf_vector) +
                                    std::string(cl_source::cvf);
  classify_ = ctx.kernel(
      "cvf", source,
      fmt::format("{} -DEROSION={} -DBAND={}{}", options, std::max(0, params.categorise.erosion_px),
                  params.band_px, depth_tolerance_options(params.categorise)),
      "cvf_classify");
  if (local) {
    likelihoods_ = ctx.kernel(
        "cvf_local_histogram", cl_source::cvf_local_histogram,
        fmt::format("-DBINS={} -DTILE={} -DPRIOR_RADIUS={} -DSOFT={}", params.bins_per_channel,
                    params_.tile_px, params_.prior_radius, params_.soft_where_ambiguous ? 1 : 0),
        "cvf_local_likelihoods");
    overlap_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_float));
    stats_ = ::cl::Buffer(ctx.context(), CL_MEM_READ_WRITE, sizeof(cl_int));
  }
}

const DeviceImage<std::uint16_t, 1>* CvfMatte::judged_depth() {
  if (cores_run_ && !judged_depth_) judged_depth_ = &hole_cores_->mark_near_occluders(colour_);
  return judged_depth_;
}

void CvfMatte::stage_done(const char* stage) {
  if (!profiling_) return;
  ctx_.queue().finish();
  const auto now = std::chrono::steady_clock::now();
  stage_times_.push_back(
      {stage, std::chrono::duration<double, std::milli>(now - stage_start_).count()});
  stage_start_ = now;
}

void CvfMatte::process(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  check_inputs(in, name());
  stage_times_.clear();
  if (profiling_) {
    ctx_.queue().finish();
    stage_start_ = std::chrono::steady_clock::now();
  }
  OcclusionInputs inputs = in;
  judged_depth_ = nullptr;
  cores_run_ = hole_cores_ && in.width() > 0;
  if (cores_run_) {
    // Over the objects' rectangle only: the depth test is "ignore" off the object, so nothing
    // after it reads the depth there, except the near occluders' colour models.
    inputs.real_depth_mm =
        &hole_cores_->run(*in.real_depth_mm, hole_core_radius(params_.hole_core_px, in.width()),
                          in.colour, near_ ? std::nullopt : in.objects);
    colour_ = in.colour;
    if (params_.rim_in_front) {
      // The rim that takes the core's colour is in front too: CVF judges by the same marked
      // depth that it hands the stabiliser (judged_depth()).
      judged_depth_ = inputs.real_depth_mm = &hole_cores_->mark_near_occluders(in.colour);
    }
    stage_done("hole cores");
  }
  if (layout_ == CvfLayout::Tiles) {
    process_tiles(inputs, alpha);
  } else {
    process_strips(inputs, alpha);
  }
  if (near_) {
    near_->process(inputs, alpha);
    stage_done("near occluders");
  }
}

void CvfMatte::process_tiles(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  const CvfParams& p = params_.cvf;
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  const int s = p.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  tile_wide_in_.resize(c, wl, hl);
  tile_feather_in_.resize(c, w, h);
  // 1. Depth test and erosion (thesis 3.3.1).
  categoriser_->run(in);
  const auto& categories = categoriser_->categories().buffer();
  stage_done("categories");
  // 2. Colour models in the band around the process region (thesis 3.3.2).
  categoriser_->dilate(categoriser_->process_mask(), band_, p.band_px);
  stage_done("band");
  if (local_) {
    // 2.-3. Local colour models, prior, costs and softness (cvf_local_histogram.cl).
    local_costs_->run(in, categoriser_->categories(), band_);
    stage_done("tile histograms + likelihoods + costs");
    set_args(cost_pack_, in.colour->buffer(), local_costs_->cost().buffer(), w, h, wl, hl,
             tile_wide_in_.buffer());
    run_pixels(ctx_, cost_pack_, wl, hl);
  } else {
    ctx_.queue().enqueueFillBuffer(hist_, cl_uint{0}, 0, hist_bytes());
    const std::size_t local = 256;
    const std::size_t groups =
        std::clamp<std::size_t>((static_cast<std::size_t>(w) * h + 8191) / 8192, 1, 64);
    set_args(histogram_, in.colour->buffer(), categories, band_.buffer(), w * h, hist_);
    ctx_.queue().enqueueNDRangeKernel(histogram_, ::cl::NullRange, ::cl::NDRange(groups * local),
                                      ::cl::NDRange(local));
    stage_done("histograms");
    // 3. Costs, packed with the guide at the wide filter's resolution (thesis 3.3.3).
    set_args(cost_pack_, in.colour->buffer(), in.real_depth_mm->buffer(),
             in.virtual_depth_mm->buffer(), categories, hist_, std::max(1, p.min_samples), w, h, wl,
             hl, tile_wide_in_.buffer());
    run_pixels(ctx_, cost_pack_, wl, hl);
  }
  stage_done("costs");
  // 4. Wide guided filter on the costs, threshold on undecided pixels (thesis 3.3.4), soft
  // where the colour models and the prior cannot decide (the shipped method).
  tile_wide_->coefficients(tile_wide_in_, tile_wide_ab_);
  tile_wide_->apply(tile_wide_ab_, &tile_wide_mean_, nullptr, nullptr, nullptr);
  stage_done("wide filter");
  set_args(mask_pack_, in.colour->buffer(), categories, tile_wide_mean_.buffer(), w, h, wl, hl,
           tile_feather_in_.buffer());
  if (local_) mask_pack_.setArg(8, local_costs_->softness().buffer());
  run_pixels(ctx_, mask_pack_, w, h);
  stage_done("threshold");
  // 5. Narrow guided filter to feather; alpha = 1 - cost on the object.
  tile_feather_->coefficients(tile_feather_in_, tile_feather_ab_);
  stage_done("feather coefficients");
  tile_feather_->apply(tile_feather_ab_, nullptr, &tile_feather_in_, in.virtual_depth_mm, &alpha);
  stage_done("feather apply");
}

void CvfMatte::fill_known_rows(const PixelRect& rows, int w, int h) {
  if (rows.height() == h) return;  // the kernel writes every row
  auto& q = ctx_.queue();
  // Per row (begin, end) = (w, 0): no object columns.
  q.enqueueFillBuffer(row_object_, cl_int2{{w, 0}}, 0, 2 * sizeof(cl_int) * h);
  const auto fill_rows = [&](const ::cl::Buffer& buffer, std::size_t bytes_per_row) {
    const int above = rows.empty() ? h : rows.y0;  // rows [0, above) and [rows.y1, h)
    if (above > 0) q.enqueueFillBuffer(buffer, cl_uchar{0}, 0, bytes_per_row * above);
    if (!rows.empty() && rows.y1 < h)
      q.enqueueFillBuffer(buffer, cl_uchar{0}, bytes_per_row * rows.y1,
                          bytes_per_row * (h - rows.y1));
  };
  fill_rows(categories_.buffer(), static_cast<std::size_t>(w));
  if (local_) fill_rows(prior_.buffer(), 2 * static_cast<std::size_t>(w));
}

void CvfMatte::process_strips(const OcclusionInputs& in, DeviceImage<float, 1>& alpha) {
  const CvfParams& p = params_.cvf;
  const int w = in.width(), h = in.height();
  const auto& c = ctx_.context();
  auto& q = ctx_.queue();
  alpha.resize(c, w, h);
  if (alpha.empty()) return;
  const int s = p.wide.subsample;
  const int wl = (w + s - 1) / s, hl = (h + s - 1) / s;
  wide_mean_.resize(c, wl + 2 * StripGuidedFilter::kMeanPad, 4 * hl);
  if (trace_) {
    wide_in_.resize(c, wl, 4 * hl);
    feather_in_.resize(c, w, 4 * h);
  }
  const int b = p.bins_per_channel, nbins = b * b * b;
  const int tx = local_ ? tiles_x(w) : 0, tiles = local_ ? tx * tiles_y(h) : 0;
  if (local_) {
    if (tiles > tiles_capacity_) {
      const auto n = static_cast<std::size_t>(tiles) * 2 * nbins;
      tile_hist_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, sizeof(cl_uint) * n);
      lik_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, sizeof(cl_float) * n);
      tiles_capacity_ = tiles;
    }
    prior_.resize(c, w, h);
    q.enqueueFillBuffer(tile_hist_, cl_uint{0}, 0,
                        sizeof(cl_uint) * static_cast<std::size_t>(tiles) * 2 * nbins);
  }
  // 1.-2. Depth test, erosion, band and colour models in one pass (thesis 3.3.1-3.3.2), with
  // the tiles' models and the prior's counts for the shipped method.
  categories_.resize(c, w, h);
  const auto& categories = categories_.buffer();
  q.enqueueFillBuffer(hist_, cl_uint{0}, 0, hist_bytes());
  {
    // A strip walks 2 (erosion + max(band, prior)) rows outside it (cvf.cl).
    const int reach = std::max(p.band_px, local_ ? params_.prior_radius : 0);
    // Off the object every pixel is "ignore"; the band and the prior reach `reach` px beyond
    // it. Rows farther from the objects' rectangle are known without a look: no category, no
    // band, no prior counts, no object columns. They are filled, the kernel runs over the rest.
    const PixelRect work = grown(in.object_rect(), reach, w, h);
    const int strips = StripGuidedFilter::strip_count(std::max(work.height(), 1),
                                                      2 * (p.categorise.erosion_px + reach),
                                                      static_cast<int>(ctx_.info().compute_units));
    const int strip_rows = std::max(1, (work.height() + strips - 1) / strips);
    const int groups = (work.height() + strip_rows - 1) / strip_rows;
    const std::size_t srow = StripGuidedFilter::scratch_row(w);
    const std::size_t rows = 2 * p.categorise.erosion_px + 2 + 3 + 2 * reach + 2 + (local_ ? 2 : 0);
    const std::size_t floats = srow * rows + static_cast<std::size_t>(tx) * 2 * nbins;
    const std::size_t bytes = sizeof(float) * floats * groups;
    if (bytes > classify_scratch_bytes_) {
      classify_scratch_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, bytes);
      classify_scratch_bytes_ = bytes;
    }
    if (h > row_object_rows_) {
      row_object_ = ::cl::Buffer(c, CL_MEM_READ_WRITE, 2 * sizeof(cl_int) * h);
      row_object_rows_ = h;
    }
    fill_known_rows(work, w, h);
    set_args(classify_, w, h, strip_rows, work.y0, work.y1, p.categorise.depth_tolerance_mm,
             classify_scratch_, in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(),
             in.colour->buffer(), categories, hist_, row_object_);
    if (local_) set_args_from(classify_, 13, tx, tile_hist_, prior_.buffer());
    if (groups > 0)
      q.enqueueNDRangeKernel(classify_, ::cl::NullRange,
                             ::cl::NDRange(1, static_cast<std::size_t>(groups)),
                             ::cl::NDRange(1, 1));
  }
  stage_done("categories + band + histograms");
  // Pixels whose filter windows see no object are not filtered (cvf_guided.cl,
  // object_columns()): the wide filter's output there is (a, b) = (0, 0.5) from the constant
  // cost, needing no object within 2 r of its pixel (r at its resolution); the feather's alpha
  // is 0 off the object. The trace wants every pixel's input.
  if (!trace_) {
    wide_->set_active_rows(row_object_, h, s, 2 * wide_->radius() * s);
    feather_->set_active_rows(row_object_, h, 1, 0);
  }
  if (local_) {
    // The tiles' likelihoods shrunk towards the frame's, its overlap and validity.
    set_args(likelihoods_, tile_hist_, hist_, tiles, p.min_samples, lik_, overlap_, stats_);
    q.enqueueNDRangeKernel(likelihoods_, ::cl::NullRange, ::cl::NDRange(tiles), ::cl::NullRange);
    stage_done("tile likelihoods");
  }

  // 3.-4. Costs (thesis 3.3.3), computed inside the wide guided filter at its resolution.
  {
    auto& k = wide_->kernel();
    cl_uint next = 0;
    if (local_) {
      set_args_from(k, StripGuidedFilter::kFirstArg, in.colour->buffer(), categories,
                    in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), lik_, stats_,
                    prior_.buffer(), tx, tiles_y(h), w, h, wide_mean_.buffer());
      next = StripGuidedFilter::kFirstArg + 12;
    } else {
      set_args_from(k, StripGuidedFilter::kFirstArg, in.colour->buffer(), categories,
                    in.real_depth_mm->buffer(), in.virtual_depth_mm->buffer(), hist_,
                    std::max(1, p.min_samples), w, h, wide_mean_.buffer());
      next = StripGuidedFilter::kFirstArg + 9;
    }
    if (trace_) k.setArg(next, wide_in_.buffer());
    wide_->run(wl, hl);
  }
  stage_done("costs + wide filter");

  // 5. Threshold (thesis 3.3.4) inside the narrow guided filter that feathers; alpha = 1 - cost.
  {
    auto& k = feather_->kernel();
    set_args_from(k, StripGuidedFilter::kFirstArg, in.colour->buffer(), categories,
                  wide_mean_.buffer(), wl, hl);
    cl_uint next = StripGuidedFilter::kFirstArg + 5;
    if (local_) {
      set_args_from(k, next, prior_.buffer(), overlap_, stats_);
      next += 3;
    }
    set_args_from(k, next, in.virtual_depth_mm->buffer(), alpha.buffer());
    if (trace_) k.setArg(next + 2, feather_in_.buffer());
    feather_->run(w, h);
  }
  stage_done("threshold + feather");
}

namespace {

TileColourModels download_tiles(::cl::CommandQueue& q, const ::cl::Buffer& buffer, int tile_px,
                                int tiles_x, int tiles_y, int bins_per_channel) {
  TileColourModels t;
  t.tile_px = tile_px;
  t.tiles_x = tiles_x;
  t.tiles_y = tiles_y;
  t.bins_per_channel = bins_per_channel;
  const int n = t.bins();
  std::vector<cl_uint> all(static_cast<std::size_t>(t.tiles()) * 2 * n);
  q.enqueueReadBuffer(buffer, CL_TRUE, 0, sizeof(cl_uint) * all.size(), all.data());
  for (int k = 0; k < t.tiles(); ++k) {
    const auto base = all.begin() + static_cast<std::ptrdiff_t>(k) * 2 * n;
    t.infront.insert(t.infront.end(), base, base + n);
    t.behind.insert(t.behind.end(), base + n, base + 2 * n);
    t.infront_total.push_back(std::accumulate(base, base + n, 0U));
    t.behind_total.push_back(std::accumulate(base + n, base + 2 * n, 0U));
  }
  return t;
}

}  // namespace

CvfDeviceTrace CvfMatte::download_trace() {
  auto& q = ctx_.queue();
  CvfDeviceTrace t;
  const ::cl::Buffer* hist = &hist_;
  const ::cl::Buffer* tiles = &tile_hist_;
  if (layout_ == CvfLayout::Tiles) {
    t.categories = categoriser_->categories().download(q);
    t.band = band_.download(q);
    t.wide_input = tile_wide_in_.download(q);
    t.feather_input = tile_feather_in_.download(q);
    if (local_) {
      hist = &local_costs_->global_histogram();
      tiles = &local_costs_->tile_histograms();
    }
  } else {
    const auto packed = categories_.download(q);
    t.categories = CategoryImage(packed.width(), packed.height());
    t.band = ImageGray8(packed.width(), packed.height());
    for (std::size_t i = 0; i < packed.elements().size(); ++i) {
      t.categories.elements()[i] = packed.elements()[i] & 3;
      t.band.elements()[i] = (packed.elements()[i] >> 2) & 1;
    }
    if (trace_) {
      t.wide_input = from_planes(wide_in_.download(q));
      t.feather_input = from_planes(feather_in_.download(q));
    }
  }
  const int b = params_.cvf.bins_per_channel, n = b * b * b;
  std::vector<cl_uint> h(2 * static_cast<std::size_t>(n));
  q.enqueueReadBuffer(*hist, CL_TRUE, 0, sizeof(cl_uint) * h.size(), h.data());
  t.models = {b, std::vector<std::uint32_t>(h.begin(), h.begin() + n),
              std::vector<std::uint32_t>(h.begin() + n, h.begin() + 2 * n)};
  if (local_ && !t.categories.empty())
    t.tiles = download_tiles(q, *tiles, params_.tile_px, tiles_x(t.categories.width()),
                             tiles_y(t.categories.height()), b);
  return t;
}

}  // namespace probeless::occlusion
