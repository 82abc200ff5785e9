#include "core/camera/ocam.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/error.hpp"
#include "core/read_limits.hpp"

namespace probeless {

namespace {

double polyval(const std::vector<double>& ascending, double x) {
  double v = 0;
  for (auto it = ascending.rbegin(); it != ascending.rend(); ++it) v = v * x + *it;
  return v;
}

// invpol is a least-squares fit of the inverse of pol with at most 0.01 px error (OCamCalib's
// findinvpoly); unproject() accepts pixels this far beyond the domain so that every ray
// project() accepts comes back.
constexpr double kInvpolSlackPx = 1.0;

}  // namespace

OCamCamera::OCamCamera(OCamParams p) : p_(std::move(p)) {
  if (p_.pol.empty() || p_.invpol.empty())
    throw std::invalid_argument("OCamCamera: pol and invpol must not be empty");
  if (!(p_.pol[0] < 0))
    throw std::invalid_argument(
        "OCamCamera: pol[0] must be negative (OCamCalib's z axis "
        "points away from the scene)");
  if (p_.width <= 0 || p_.height <= 0)
    throw std::invalid_argument("OCamCamera: image size must be positive");
  if (p_.c - p_.d * p_.e == 0) throw std::invalid_argument("OCamCamera: singular affine matrix");

  // The domain reaches the farthest image corner, where OCamCalib fits invpol, and stops
  // early if the angle stops growing with the radius (a polynomial turning back).
  double corner_rho = 0;
  for (double x : {-0.5, p_.width - 0.5})
    for (double y : {-0.5, p_.height - 0.5})
      corner_rho = std::max(corner_rho, sensor_point({x, y}).norm());
  auto angle_at = [&](double rho) { return std::atan2(rho, -polyval(p_.pol, rho)); };
  constexpr double kStepPx = 0.25;
  double rho = 0, alpha = 0;
  while (rho < corner_rho) {
    const double next_rho = std::min(rho + kStepPx, corner_rho);
    const double next_alpha = angle_at(next_rho);
    if (!(next_alpha > alpha)) break;
    rho = next_rho;
    alpha = next_alpha;
  }
  // invpol must grow with the angle over the same range; theta is measured from the sensor
  // plane in OCamCalib (-pi/2 on the axis).
  constexpr double kStepRad = 1e-4;
  double prev = polyval(p_.invpol, -std::numbers::pi / 2);
  for (double a = kStepRad; a < alpha; a += kStepRad) {
    const double r = polyval(p_.invpol, a - std::numbers::pi / 2);
    if (!(r > prev)) {
      alpha = a - kStepRad;
      break;
    }
    prev = r;
  }
  if (!(rho > 0 && alpha > 0)) throw std::invalid_argument("OCamCamera: empty field of view");
  max_rho_ = rho;
  max_alpha_ = alpha;
}

// The pixel relative to the centre with the affine part undone (OCamCalib's cam2world), as
// OCamCalib's (xp, yp): (along rows, along columns).
Eigen::Vector2d OCamCamera::sensor_point(const Eigen::Vector2d& pixel) const {
  const double row = pixel.y() - p_.xc, col = pixel.x() - p_.yc;
  const double invdet = 1.0 / (p_.c - p_.d * p_.e);
  return {invdet * (row - p_.d * col), invdet * (-p_.e * row + p_.c * col)};
}

std::optional<Eigen::Vector2d> OCamCamera::project(const Eigen::Vector3d& p) const {
  const double norm = std::hypot(p.x(), p.y());
  const double alpha = std::atan2(norm, p.z());  // angle from our optical axis
  if (!(alpha <= max_alpha_)) return std::nullopt;
  if (norm == 0) {
    if (!(p.z() > 0)) return std::nullopt;
    return Eigen::Vector2d(p_.yc, p_.xc);
  }
  // OCamCalib's world2cam with its x = our y (rows), its y = our x (columns), its z = -ours.
  const double rho = polyval(p_.invpol, alpha - std::numbers::pi / 2);
  const double along_rows = p.y() / norm * rho, along_cols = p.x() / norm * rho;
  const double row = p_.c * along_rows + p_.d * along_cols + p_.xc;
  const double col = p_.e * along_rows + along_cols + p_.yc;
  return Eigen::Vector2d(col, row);
}

std::optional<Eigen::Vector3d> OCamCamera::unproject(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d m = sensor_point(pixel);
  const double rho = m.norm();
  if (!(rho <= max_rho_ + kInvpolSlackPx)) return std::nullopt;
  const double z = polyval(p_.pol, rho);
  return Eigen::Vector3d(m.y(), m.x(), -z).normalized();
}

std::unique_ptr<CameraModel> OCamCamera::clone() const {
  return std::make_unique<OCamCamera>(*this);
}

// ---- calib_results.txt ----

namespace {

struct DataLine {
  int number;
  std::vector<std::string_view> tokens;
};

class CalibText {
 public:
  CalibText(std::string_view text, std::string_view source) : source_(source) {
    int number = 0;
    while (!text.empty()) {
      const auto eol = text.find('\n');
      std::string_view line = text.substr(0, eol);
      text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
      ++number;
      DataLine d{number, split(line)};
      if (!d.tokens.empty() && d.tokens.front().front() != '#') lines_.push_back(std::move(d));
    }
    last_line_ = number;
  }

  // The next data line, described as `what` in the error when the text ends early.
  const DataLine& next(const std::string& what) {
    if (next_ >= lines_.size())
      throw ParseError(source_, last_line_ + 1, "missing " + what + ": the file ends early");
    return lines_[next_++];
  }
  void expect_end() const {
    if (next_ < lines_.size())
      throw ParseError(source_, lines_[next_].number, "unexpected data after the image size");
  }

  double number(const DataLine& line, std::size_t i, const std::string& what) const {
    if (i >= line.tokens.size())
      throw ParseError(source_, line.number, what + ": the line ends early");
    std::string_view t = line.tokens[i];
    if (t.size() > 1 && t.front() == '+') t.remove_prefix(1);
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      throw ParseError(source_, line.number,
                       what + ": '" + std::string(line.tokens[i]) + "' is not a number");
    return v;
  }
  int integer(const DataLine& line, std::size_t i, const std::string& what, int max) const {
    const double v = number(line, i, what);
    if (v != std::floor(v) || v < 1 || v > max)
      throw ParseError(source_, line.number,
                       what + ": expected an integer in 1.." + std::to_string(max) + ", got '" +
                           std::string(line.tokens[i]) + "'");
    return static_cast<int>(v);
  }
  void expect_count(const DataLine& line, std::size_t n, const std::string& what) const {
    if (line.tokens.size() > n)
      throw ParseError(source_, line.number,
                       what + ": expected " + std::to_string(n) + " numbers, found " +
                           std::to_string(line.tokens.size()));
    if (line.tokens.size() < n)
      throw ParseError(source_, line.number,
                       what + ": expected " + std::to_string(n) + " numbers, the line ends after " +
                           std::to_string(line.tokens.size()));
  }
  // "N a0 a1 ... a(N-1)": a polynomial in ascending powers, preceded by its length.
  std::vector<double> polynomial(const DataLine& line, const std::string& what) const {
    const int n = integer(line, 0, what + " length", 64);
    expect_count(line, static_cast<std::size_t>(n) + 1, what);
    std::vector<double> coeffs;
    for (int i = 1; i <= n; ++i) coeffs.push_back(number(line, static_cast<std::size_t>(i), what));
    return coeffs;
  }
  const std::string& source() const { return source_; }

 private:
  static std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> out;
    constexpr std::string_view kSpace = " \t\r\f\v";
    std::size_t i = line.find_first_not_of(kSpace);
    while (i != std::string_view::npos) {
      const std::size_t j = line.find_first_of(kSpace, i);
      out.push_back(line.substr(i, j == std::string_view::npos ? j : j - i));
      i = j == std::string_view::npos ? j : line.find_first_not_of(kSpace, j);
    }
    return out;
  }

  std::string source_;
  std::vector<DataLine> lines_;
  std::size_t next_ = 0;
  int last_line_ = 0;
};

}  // namespace

OCamCamera OCamCamera::parse(std::string_view text, std::string_view source_name) {
  CalibText in(text, source_name);
  OCamParams p;

  const DataLine& pol = in.next("pol (length and coefficients of the direct polynomial)");
  p.pol = in.polynomial(pol, "pol");
  if (!(p.pol[0] < 0))
    throw ParseError(in.source(), pol.number,
                     "pol: the constant term must be negative (OCamCalib's z axis points away "
                     "from the scene)");

  const DataLine& invpol = in.next("invpol (length and coefficients of the inverse polynomial)");
  p.invpol = in.polynomial(invpol, "invpol");

  const DataLine& centre = in.next("the centre (xc yc)");
  in.expect_count(centre, 2, "centre");
  p.xc = in.number(centre, 0, "centre row xc");
  p.yc = in.number(centre, 1, "centre column yc");

  const DataLine& affine = in.next("the affine parameters (c d e)");
  in.expect_count(affine, 3, "affine");
  p.c = in.number(affine, 0, "affine c");
  p.d = in.number(affine, 1, "affine d");
  p.e = in.number(affine, 2, "affine e");
  if (p.c - p.d * p.e == 0)
    throw ParseError(in.source(), affine.number, "affine: c - d e must not be zero");

  const DataLine& size = in.next("the image size (height width)");
  in.expect_count(size, 2, "image size");
  const int side = static_cast<int>(read_limits::kMaxImageSide);
  p.height = in.integer(size, 0, "image height", side);
  p.width = in.integer(size, 1, "image width", side);
  if (!read_limits::image_size_ok(p.width, p.height))
    throw ParseError(in.source(), size.number,
                     "image size: " + std::to_string(p.width) + "x" + std::to_string(p.height) +
                         " is over the limit of " + std::to_string(read_limits::kMaxImagePixels) +
                         " pixels");
  in.expect_end();

  try {
    return OCamCamera(std::move(p));
  } catch (const std::invalid_argument& e) {
    throw ParseError(in.source(), 0, e.what());
  }
}

}  // namespace probeless
