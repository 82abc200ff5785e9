// OCamCalib model: parsing calib_results.txt, the axis and (row, column) conventions, and round
// trips on a synthetic calibration and on the real one in ../shared/data.
#include "core/camera/ocam.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "support/test_data.hpp"

namespace probeless {
namespace {

constexpr double kPi = std::numbers::pi;

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Eigen::Vector3d ray_at(double alpha, double phi) {
  return {std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), std::cos(alpha)};
}

// A synthetic 640x480 lens, pol = -200 + 0.0015 rho^2 (the horizon, 90 deg off axis, at rho =
// sqrt(200 / 0.0015) = 365.1 px; about 96 deg in the corners), with a slightly non-identity
// affine part, and invpol fitted the way OCamCalib's findinvpoly does.
constexpr double kA = 200, kB = 0.0015;
const double kHorizonRho = std::sqrt(kA / kB);

std::vector<double> fit_invpol(const std::vector<double>& pol, double max_rho, int degree) {
  auto angle_at = [&](double rho) {
    double z = 0;
    for (std::size_t i = pol.size(); i-- > 0;) z = z * rho + pol[i];
    return std::atan2(rho, -z);
  };
  std::vector<double> theta, rho;
  for (double r = 0; r <= max_rho + 20; r += 0.5) {
    rho.push_back(r);
    theta.push_back(angle_at(r) - kPi / 2);  // OCamCalib measures from the sensor plane
  }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(rho.size()), degree + 1);
  Eigen::VectorXd b(static_cast<Eigen::Index>(rho.size()));
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    double t = 1;
    for (int j = 0; j <= degree; ++j, t *= theta[static_cast<std::size_t>(i)]) A(i, j) = t;
    b(i) = rho[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  return {c.data(), c.data() + c.size()};
}

std::string synthetic_text() {
  const std::vector<double> pol{-kA, 0, kB};
  const std::vector<double> invpol = fit_invpol(pol, 420, 14);
  std::ostringstream out;
  out.precision(17);
  out << "#polynomial coefficients for the DIRECT mapping function\n\n" << pol.size();
  for (double v : pol) out << ' ' << v;
  out << "\n\n#polynomial coefficients for the inverse mapping function\n\n" << invpol.size();
  for (double v : invpol) out << ' ' << v;
  out << "\n\n#center: \"row\" and \"column\", starting from 0 (C convention)\n\n"
      << "250.25 310.75\n\n"
      << "#affine parameters \"c\", \"d\", \"e\"\n\n"
      << "1.0005 0.0003 -0.0002\n\n"
      << "#image size: \"height\" and \"width\"\n\n"
      << "480 640\n";
  return out.str();
}

// Replaces line `number` (1-based) of `text`, or deletes it when `with` is nullopt.
std::string edit_line(const std::string& text, int number, std::optional<std::string> with) {
  std::istringstream in(text);
  std::string line, out;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == number) {
      if (with) out += *with + "\n";
    } else {
      out += line + "\n";
    }
  }
  return out;
}

void expect_round_trips(const OCamCamera& cam, double tol_px, double tol_rad) {
  int pixels = 0;
  for (double y = -0.49; y < cam.height() - 0.5; y += 4.7)
    for (double x = -0.49; x < cam.width() - 0.5; x += 4.7) {
      const Eigen::Vector2d px(x, y);
      const auto ray = cam.unproject(px);
      ASSERT_TRUE(ray) << "every pixel of the image is in the domain: " << px.transpose();
      const auto back = cam.project(*ray);
      ASSERT_TRUE(back) << px.transpose();
      EXPECT_LT((*back - px).norm(), tol_px) << px.transpose();
      ++pixels;
    }
  EXPECT_GT(pixels, 1000);
  for (double alpha = 0; alpha <= cam.max_angle(); alpha += cam.max_angle() / 50)
    for (double phi = -kPi; phi < kPi; phi += kPi / 36) {
      const Eigen::Vector3d ray = ray_at(alpha, phi);
      const auto px = cam.project(ray);
      ASSERT_TRUE(px) << "alpha=" << alpha << " phi=" << phi;
      const auto back = cam.unproject(*px);
      ASSERT_TRUE(back) << "alpha=" << alpha << " phi=" << phi;
      EXPECT_LT(angle_between(*back, ray), tol_rad) << "alpha=" << alpha << " phi=" << phi;
    }
}

TEST(OCam, ParsesTheToolboxLayout) {
  const OCamCamera cam = OCamCamera::parse(synthetic_text(), "synthetic");
  const OCamParams& p = cam.params();
  EXPECT_EQ(p.pol, (std::vector<double>{-kA, 0, kB}));
  EXPECT_EQ(p.invpol.size(), 15u);
  EXPECT_EQ(p.xc, 250.25);  // row
  EXPECT_EQ(p.yc, 310.75);  // column
  EXPECT_EQ(p.c, 1.0005);
  EXPECT_EQ(p.d, 0.0003);
  EXPECT_EQ(p.e, -0.0002);
  EXPECT_EQ(cam.width(), 640);
  EXPECT_EQ(cam.height(), 480);
  EXPECT_EQ(cam.kind(), "ocam");
}

TEST(OCam, AxesFollowOurConvention) {
  const OCamCamera cam = OCamCamera::parse(synthetic_text());
  // The centre is (row xc, column yc) in the file: our pixel (x = yc, y = xc) is the axis.
  const auto axis = cam.unproject({310.75, 250.25});
  ASSERT_TRUE(axis);
  EXPECT_LT(angle_between(*axis, {0, 0, 1}), 1e-12);
  const auto centre = cam.project({0, 0, 3});
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->x(), 310.75, 1e-12);
  EXPECT_NEAR(centre->y(), 250.25, 1e-12);
  // Right of the centre is +x, below it +y, and both are in front of the camera.
  const auto right = cam.unproject({410.75, 250.25});
  const auto down = cam.unproject({310.75, 350.25});
  ASSERT_TRUE(right && down);
  EXPECT_GT(right->x(), 0.3);
  EXPECT_NEAR(right->y(), 0, 1e-3);  // the affine part is nearly the identity
  EXPECT_GT(right->z(), 0);
  EXPECT_GT(down->y(), 0.3);
  EXPECT_NEAR(down->x(), 0, 1e-3);
  // 90 deg off the axis lands on the horizon circle pol(rho) = 0.
  for (double phi : {0.0, 1.0, 2.5, -2.0}) {
    const auto px = cam.project(ray_at(kPi / 2, phi));
    ASSERT_TRUE(px);
    const double rho = std::hypot(px->x() - 310.75, px->y() - 250.25);
    EXPECT_NEAR(rho, kHorizonRho, 0.5) << phi;
  }
  EXPECT_FALSE(cam.project({0, 0, -1}));
  EXPECT_GT(cam.max_angle(), kPi / 2);
}

TEST(OCam, SyntheticRoundTrips) {
  const OCamCamera cam = OCamCamera::parse(synthetic_text());
  expect_round_trips(cam, 0.01, 1e-5);
}

TEST(OCam, ParseErrorsNameTheLine) {
  const std::string good = synthetic_text();
  auto line_of = [](const std::string& text) {
    try {
      OCamCamera::parse(text, "calib.txt");
    } catch (const ParseError& e) {
      EXPECT_EQ(e.source(), "calib.txt");
      EXPECT_NE(std::string(e.what()).find("calib.txt:"), std::string::npos) << e.what();
      return e.line();
    }
    ADD_FAILURE() << "no ParseError";
    return -1;
  };
  // Data lines of the synthetic text: pol 3, invpol 7, centre 11, affine 15, size 19.
  EXPECT_EQ(line_of(edit_line(good, 19, std::nullopt)), 19);       // size missing: EOF
  EXPECT_EQ(line_of(edit_line(good, 15, "1.0 zero 0.0")), 15);     // not a number
  EXPECT_EQ(line_of(edit_line(good, 3, "3 -200 0")), 3);           // truncated pol
  EXPECT_EQ(line_of(edit_line(good, 3, "3 -200 0 0.0015 7")), 3);  // too many numbers
  EXPECT_EQ(line_of(edit_line(good, 3, "2.5 -200 0")), 3);         // length not integer
  EXPECT_EQ(line_of(edit_line(good, 3, "3 200 0 0.0015")), 3);     // wrong z sign
  EXPECT_EQ(line_of(edit_line(good, 11, "250.25")), 11);           // truncated centre
  EXPECT_EQ(line_of(edit_line(good, 19, "480 640.5")), 19);        // size not integer
  EXPECT_EQ(line_of(edit_line(good, 19, "480 640\n\n1 2")), 21);   // trailing data
  // Sizes within core/read_limits.hpp (both used to pass up to 65536, 2^32 pixels).
  EXPECT_EQ(line_of(edit_line(good, 19, "480 65536")), 19);    // a side over 32768
  EXPECT_EQ(line_of(edit_line(good, 19, "32768 32768")), 19);  // over 2^26 pixels
  EXPECT_EQ(line_of(edit_line(good, 7, std::nullopt)), 10);    // invpol missing: centre is read
  EXPECT_EQ(line_of(""), 1);
  EXPECT_EQ(line_of("# only a comment\n"), 2);
  // Windows line endings and a leading '+' are accepted.
  std::string crlf;
  for (char ch : good) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  EXPECT_EQ(OCamCamera::parse(crlf).params(), OCamCamera::parse(good).params());
  EXPECT_NO_THROW(OCamCamera::parse(edit_line(good, 15, "+1.0005 +0.0003 -0.0002")));
}

// The real calibration shipped with OCamCalib's fisheye sample image.
class OCamRealFile : public ::testing::Test {
 protected:
  void SetUp() override {
    PROBELESS_REQUIRE_DATA("fisheye/ocamcalib/calib_results_fisheye.txt");
    const auto path = testing::shared_data_dir() / "fisheye/ocamcalib/calib_results_fisheye.txt";
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    cam_.emplace(OCamCamera::parse(text.str(), path.string()));
  }
  std::optional<OCamCamera> cam_;
};

TEST_F(OCamRealFile, Conventions) {
  const OCamCamera& cam = *cam_;
  EXPECT_EQ(cam.width(), 1024);
  EXPECT_EQ(cam.height(), 768);
  const OCamParams& p = cam.params();
  // The image centre (row 381.78, column 505.48) is the optical axis in our frame.
  const auto axis = cam.unproject({p.yc, p.xc});
  ASSERT_TRUE(axis);
  EXPECT_LT(angle_between(*axis, {0, 0, 1}), 1e-12);
  const auto right = cam.unproject({p.yc + 200, p.xc});
  ASSERT_TRUE(right);
  EXPECT_GT(right->x(), 0);
  EXPECT_NEAR(right->y(), 0, 1e-12);
  EXPECT_GT(right->z(), 0);
  // Both polynomials put 90 deg on the same horizon circle (about 730 px: this lens's
  // visible image circle, about 560 px, is only about 65 deg off the axis).
  double lo = 0, hi = 2000;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    double z = 0;
    for (std::size_t k = p.pol.size(); k-- > 0;) z = z * mid + p.pol[k];
    (z < 0 ? lo : hi) = mid;
  }
  EXPECT_NEAR(p.invpol[0], lo, 10.0);  // invpol at theta = 0 (the horizon)
  // Every pixel of the frame is in the domain, which reaches about 74 deg.
  EXPECT_GT(cam.max_angle(), 70 * kPi / 180);
  EXPECT_LT(cam.max_angle(), 80 * kPi / 180);
}

TEST_F(OCamRealFile, RoundTripsOverTheFieldOfView) {
  expect_round_trips(*cam_, 0.05, 1e-4);
}

}  // namespace
}  // namespace probeless
